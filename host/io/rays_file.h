// The Embree anchor's .rays files (anchors/embree/README.md "File formats"): a 64-byte header, the
// rays, one result per ray.  Read by the bench to trace exactly the anchor's rays and compare with
// Embree's answers; written by `render --dump-rays` (a render's own rays and answers) and by
// `bench --answers-out` (a file read again with this tracer's answers, for the anchor's
// double-precision referee).  One reader and one writer serve all three.
#pragma once

#include "kernels/types.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// Embree's closest-hit record in a .rays file (28 bytes).
struct EmbreeHit {
    float t;
    uint32_t prim;  // kEmbreeNoPrim = miss
    float u, v, ng[3];
};
static_assert(sizeof(EmbreeHit) == 28, ".rays result record is 28 bytes");

constexpr uint32_t kEmbreeNoPrim = 0xFFFFFFFFu;
// A miss as the anchor stores it.
constexpr EmbreeHit kEmbreeMiss{INFINITY, kEmbreeNoPrim, 0, 0, {0, 0, 0}};

using RaysHeader = std::array<char, 64>;

struct RaysFile {
    std::string path;
    uint32_t kind = 0;  // 0 = closest hit, 1 = occlusion
    uint32_t set = 0;   // 0 = primary, 1 = incoherent (or deeper bounces), 2 = shadow
    uint32_t segments = 0, strands = 0, width = 0, height = 0, curve = 0;
    uint64_t scene_hash = 0;
    std::string scene;
    RaysHeader header{};                // as read, to write the file again with other answers
    std::vector<HtRay> rays;            // record layout = HtRay (org, tnear, dir, tfar)
    std::vector<EmbreeHit> hits;        // kind 0
    std::vector<uint32_t> occluded;     // kind 1
    std::string set_name() const;
};

// Throws SceneError (core/errors.h: a bad input file) naming the file and the problem.
RaysFile read_rays_file(const std::string& path);

// A header for rays not read from a file (`render --dump-rays`): version 1, the record sizes of
// `kind`, `count` rays; width, height (not a pixel grid) and curve type 0 (round linear);
// `scene_hash` the anchor's content hash of the scene (scene/scene.h hair_file_hash, 0: unknown);
// `scene` NUL padded to 8 bytes, not terminated.
RaysHeader make_rays_header(uint32_t kind, uint32_t set, uint32_t count, uint32_t segments, uint32_t strands,
                            uint64_t scene_hash, const std::string& scene);

// Writes `path`: `header` (its kind and ray count must match), the rays, and `hits` (kind 0) or
// `occluded` (kind 1, 0 or 1 per ray), one answer per ray; the other vector is ignored.  Throws
// std::runtime_error naming the path.
void write_rays_file(const std::string& path, const RaysHeader& header, const std::vector<HtRay>& rays,
                     const std::vector<EmbreeHit>& hits, const std::vector<uint32_t>& occluded);

}  // namespace ht
