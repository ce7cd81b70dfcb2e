// libFuzzer target: bytes -> one `hairtrace fiber eval|sample` JSON line -> the fibre models in
// double precision.  Anything but a clean refusal or finite, non-negative results is a finding.
#include <cstdio>
#include <cstdlib>

#include "fiber_contract.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string problem = ht_fuzz::judge_fiber_query(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fiber query contract violated: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
