// The one launcher of the fibre-query kernels (kernels/fiber/fiber_query.cl: fiber_eval,
// fiber_sample): the float path of `hairtrace fiber eval|sample` and the kernel tests run their
// queries through it, so that what the tests check is what the command runs.
#pragma once

#include "cl/device.h"
#include "kernels/fiber/query.h"

#include <vector>

namespace ht {

// One result per query, query i with materials[i]; `program` is fiber/fiber_query.cl built on
// `ctx`, `kernel` "fiber_eval" or "fiber_sample".
std::vector<HtFiberResult> run_fiber_queries(ClContext& ctx, const cl::Program& program, const char* kernel,
                                             const std::vector<HtMaterial>& materials,
                                             const std::vector<HtFiberQuery>& queries);

}  // namespace ht
