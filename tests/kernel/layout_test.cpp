// The device compiler's side of the layout contract: kernels/layout_probe.cl reports sizeof and
// offsetof for every entry of kernels/layouts.h, which must equal the declared numbers (the host
// compiler checks the same numbers at build time, host/core/kernel_layouts.cpp).  A struct that
// OpenCL C pads or aligns differently from C++ would otherwise scramble every buffer of it.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "kernels/layouts.h"

#include <string>
#include <vector>

namespace {

struct Entry {
    std::string name;
    unsigned expected;
};

std::vector<Entry> declared_layouts() {
    std::vector<Entry> e;
#define HT_LIST_SIZE(T, bytes) e.push_back({"sizeof(" #T ")", bytes});
#define HT_LIST_FIELD(T, field, offset) e.push_back({"offsetof(" #T ", " #field ")", offset});
    HT_SHARED_LAYOUTS(HT_LIST_SIZE, HT_LIST_FIELD)
#undef HT_LIST_SIZE
#undef HT_LIST_FIELD
    return e;
}

TEST(KernelLayouts, DeviceCompilerAgreesWithTheDeclaredLayouts) {
    const std::vector<Entry> declared = declared_layouts();
    ASSERT_GT(declared.size(), 60u);  // every shared struct with its fields
    ht::ClContext cl;
    cl::Program prog = cl.build("layout_probe.cl", ht::base_kernel_options());
    cl::Kernel k(prog, "layout_probe");
    cl::Buffer out(cl.context(), CL_MEM_WRITE_ONLY, declared.size() * sizeof(cl_uint));
    k.setArg(0, out);
    cl.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
    std::vector<cl_uint> got(declared.size());
    cl.queue().enqueueReadBuffer(out, CL_TRUE, 0, got.size() * sizeof(cl_uint), got.data());
    for (size_t i = 0; i < declared.size(); ++i)
        EXPECT_EQ(got[i], declared[i].expected) << declared[i].name << " on " << cl.info().name;
}

}  // namespace
