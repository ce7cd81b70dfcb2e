#include "fiber/fiber_query_runner.h"

namespace ht {

std::vector<HtFiberResult> run_fiber_queries(ClContext& ctx, const cl::Program& program, const char* kernel,
                                             const std::vector<HtMaterial>& materials,
                                             const std::vector<HtFiberQuery>& queries) {
    std::vector<HtFiberResult> out(queries.size());
    if (queries.empty()) return out;
    cl::Kernel k(program, kernel);
    // The kernels only read the inputs; COPY_HOST_PTR takes a non-const pointer all the same.
    cl::Buffer bm(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, materials.size() * sizeof(HtMaterial),
                  const_cast<HtMaterial*>(materials.data()));
    cl::Buffer bq(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, queries.size() * sizeof(HtFiberQuery),
                  const_cast<HtFiberQuery*>(queries.data()));
    cl::Buffer bo(ctx.context(), CL_MEM_WRITE_ONLY, queries.size() * sizeof(HtFiberResult));
    const cl_uint n = cl_uint(queries.size());
    k.setArg(0, bm);
    k.setArg(1, bq);
    k.setArg(2, bo);
    k.setArg(3, n);
    ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
    ctx.queue().enqueueReadBuffer(bo, CL_TRUE, 0, n * sizeof(HtFiberResult), out.data());
    return out;
}

}  // namespace ht
