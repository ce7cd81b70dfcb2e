// The render programs are built with -cl-denorms-are-zero (host/cl/device.h) because the fibre
// models make denormals on their hot path and x86 takes a microcode assist on each one unless
// FTZ/DAZ are set (docs/PERFORMANCE.md section 3, "Denormals flushed").  The option only permits
// flushing; this checks that PoCL's CPU device does flush under the programs' options, and that
// the probe would see the difference (the same product kept as a denormal without the option).
#include <gtest/gtest.h>

#include "cl/device.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace {

// a[i] * b[i] by the probe kernel, built with `options`.
std::vector<float> products(ht::ClContext& cl, const std::string& options, const std::vector<float>& a,
                            const std::vector<float>& b) {
    cl::Program prog = cl.build("fp_mode_probe.cl", options);
    cl::Kernel k(prog, "fp_mode_probe");
    cl::Buffer ba(cl.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, a.size() * sizeof(float),
                  const_cast<float*>(a.data()));
    cl::Buffer bb(cl.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, b.size() * sizeof(float),
                  const_cast<float*>(b.data()));
    cl::Buffer out(cl.context(), CL_MEM_WRITE_ONLY, a.size() * sizeof(float));
    k.setArg(0, ba);
    k.setArg(1, bb);
    k.setArg(2, out);
    k.setArg(3, cl_uint(a.size()));
    cl.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(ht::round_up(a.size(), 64)), cl::NDRange(64));
    std::vector<float> got(a.size());
    cl.queue().enqueueReadBuffer(out, CL_TRUE, 0, got.size() * sizeof(float), got.data());
    return got;
}

TEST(FloatingPointMode, RenderProgramsFlushDenormalsOnPoclsCpuDevice) {
    std::unique_ptr<ht::ClContext> cl;
    try {
        cl = std::make_unique<ht::ClContext>();
    } catch (const ht::DeviceError& e) {
        GTEST_SKIP() << "no OpenCL device: " << e.what();
    }
    if (cl->info().platform.find("Portable Computing Language") == std::string::npos)
        GTEST_SKIP() << "flushing is the device's choice under -cl-denorms-are-zero; checked on PoCL only, not on "
                     << cl->info().platform;
    // 1e-20 x 1e-20 = 1e-40, a denormal float; 1e-20 x 1e-17 = 1e-37, a normal one
    const std::vector<float> a = {1e-20f, 1e-20f, 1.17549435e-38f, 2.0f};
    const std::vector<float> b = {1e-20f, 1e-17f, 1.0f, 3.0f};
    const std::vector<float> flushed = products(*cl, ht::base_kernel_options(), a, b);
    EXPECT_EQ(flushed[0], 0.0f) << "the render programs' options keep denormals on " << cl->info().name;
    EXPECT_FLOAT_EQ(flushed[1], 1e-37f);
    EXPECT_EQ(flushed[2], 1.17549435e-38f);  // the smallest normal survives
    EXPECT_EQ(flushed[3], 6.0f);
    const std::vector<float> kept = products(*cl, "-cl-std=CL1.2", a, b);
    EXPECT_GT(kept[0], 0.0f) << "without the option the probe's product should stay a denormal";
    EXPECT_LT(kept[0], 1.17549435e-38f);
}

}  // namespace
