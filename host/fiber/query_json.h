// One `hairtrace fiber eval|sample` query: a JSON line -> validated material and directions.
// Kept apart from the command so the reader can be fuzzed on its own (tests/fuzz/fuzz_fiber_json).
#pragma once

#include <string>

#include "kernels/fiber/query.h"
#include "kernels/types.h"

namespace ht {

struct FiberJsonQuery {
    bool valid = false;
    std::string error;   // why the line was refused (valid = false)
    HtMaterial m{};      // validated, converted (make_kernel_material)
    HtFiberQuery q{};    // float copies for the OpenCL path
    real3 wo{}, wi{};    // exact inputs for the double path (wi only for eval)
    double h = 0;
    double u[4] = {0, 0, 0, 0};
};

// Never throws: a bad line gives valid = false and the reason.
FiberJsonQuery parse_fiber_query(const std::string& line, bool sample);

}  // namespace ht
