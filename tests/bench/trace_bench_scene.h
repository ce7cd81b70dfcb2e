// Shared scene and rays for the traversal microbenchmarks (double and float TUs).
#pragma once

#include "bvh/bvh.h"

#include <vector>

namespace ht_bench {

// 2,000 wavy strands x 50 segments (r = 0.01, segment length 0.05) in a 2-unit cube, the
// finished geometry, and 64k rays: "primary" from a camera 6 units away aimed at the cube,
// "incoherent" from random points inside it in random directions.
struct TraceScene {
    ht::SceneGeometry geo;
    std::vector<HtRay> primary, incoherent;
};
const TraceScene& trace_scene();

}  // namespace ht_bench
