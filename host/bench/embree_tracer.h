// Embree 3 on exactly the rays hairtrace traces, in the same process (`hairtrace bench --embree`):
// the yardstick side by side, with the machine's drift cancelled.  Compiled in when CMake finds
// libembree-dev; otherwise embree_available() is false and the tracer refuses to construct.
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace ht {

struct EmbreeHit;

bool embree_available();

class EmbreeTracer {
public:
    // Round linear curves over the strands, primID = global segment index (as the anchor).
    explicit EmbreeTracer(const Strands& strands);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    double build_ms() const;
    // One timed pass over every ray on 2 threads (4096-ray chunks): its milliseconds (the bench
    // pairs each with one of its own; answer() below is its warm-up).
    double pass_ms(const std::vector<HtRay>& rays, bool shadow);
    // One pass keeping every answer, to check another tracer ray by ray: closest hits in the
    // anchor's record (t, primID, u, v, Ng; misses t = inf, primID = ~0) or occlusion flags.
    void answer(const std::vector<HtRay>& rays, bool shadow, std::vector<EmbreeHit>& hits,
                std::vector<uint32_t>& occluded);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace ht
