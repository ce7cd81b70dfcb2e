// Readers for the Embree anchor's files (anchors/embree/README.md "File formats"), used by the
// bench to trace exactly the anchor's rays and compare with Embree's answers.
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// Embree's closest-hit record in a .rays file (28 bytes).
struct EmbreeHit {
    float t;
    uint32_t prim;  // 0xFFFFFFFF = miss
    float u, v, ng[3];
};
static_assert(sizeof(EmbreeHit) == 28, ".rays result record is 28 bytes");

struct RaysFile {
    std::string path;
    uint32_t kind = 0;  // 0 = closest hit, 1 = occlusion
    uint32_t set = 0;   // 0 = primary, 1 = incoherent, 2 = shadow
    uint32_t segments = 0, strands = 0, width = 0, height = 0, curve = 0;
    uint64_t scene_hash = 0;
    std::string scene;
    std::array<char, 64> header{};      // as read, for write_rays_file_answers
    std::vector<HtRay> rays;            // record layout = HtRay (org, tnear, dir, tfar)
    std::vector<EmbreeHit> hits;        // kind 0
    std::vector<uint32_t> occluded;     // kind 1
    std::string set_name() const;
};

// Throws std::runtime_error naming the file and the problem.
RaysFile read_rays_file(const std::string& path);

// Writes `path`: the file `source` was read from (its header and rays) with its stored results
// replaced by `hits` (a closest-hit set) or `occluded` (a shadow set), one per ray, so that the
// anchor's independent double-precision referee can judge this tracer's answers where they and
// Embree's differ (bench --answers-out; docs/PERFORMANCE.md section 1 "The anchor's head and
// `straight.hair` sets; a referee for disagreements").  Throws std::runtime_error.
void write_rays_file_answers(const RaysFile& source, const std::string& path, const std::vector<EmbreeHit>& hits,
                             const std::vector<uint32_t>& occluded);

// Minimal reader of Cem Yuksel's .hair format for the bench's own use (thickness = radius,
// as in the anchor).  The scene loader (ht::load_hair_file) replaces it once merged; this one
// exists so the bench can run on this branch.  Throws std::runtime_error.
Strands bench_read_hair_file(const std::string& path);

}  // namespace ht
