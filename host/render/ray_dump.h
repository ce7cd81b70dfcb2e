// `hairtrace render --dump-rays DIR`: the rays a render actually traces, per bounce, closest-hit
// and shadow, written as the Embree anchor's .rays files (host/io/rays_file.h) with this tracer's
// answers as the stored results.  `hairtrace bench --rays` then times
// exactly those rays and, with --embree, checks every answer against Embree in the same process
// (issue #15: measure the rays paths trace, not only camera rays).
#pragma once

#include "bvh/bvh.h"
#include "cl/device.h"
#include "io/rays_file.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// Our answer to `ray` as the anchor's closest-hit record: the global segment id as primID, the hit's
// u, and as Ng the outward geometric normal (a capsule's: the hit point's offset from its axis, of
// length r; a triangle's: the normal HtHit carries); kEmbreeMiss for none.  The dump's records and
// the bench's --answers-out both come from here.
EmbreeHit anchor_hit_record(const SceneGeometry& geometry, const HtRay& ray, const HtHit& hit);

class RayDump {
public:
    // Rays per file; the anchor's sets hold 1024 x 1024.
    static constexpr size_t kDefaultMaxRays = size_t(1) << 20;

    // `scene` names the files: DIR/<scene>.b<bounce>.{closest,shadow}.rays.  `scene_hash`: the
    // anchor's content hash of the scene (scene/scene.h hair_file_hash; 0 unknown), written in each
    // header so that the anchor's tools accept the files with the scene's .hair file.
    RayDump(std::string dir, std::string scene, uint64_t scene_hash = 0, size_t max_rays = kDefaultMaxRays);

    // The renderer's geometry (leaf order -> global segment id, capsule normals); set by
    // Renderer::set_ray_dump.
    void bind(const SceneGeometry& geometry) { geo_ = &geometry; }

    // Hooks of the render loop, after the stage kernel ran on `queue`: copy the first `count`
    // rays and answers of this bounce while the bounce's files are not full.  Shadow slots
    // without a ray (tmax <= tmin, kernels/stages/shade.cl) are skipped.  `starts`: the node each
    // closest-hit ray's traversal began at (empty: the root for all), written beside the set's
    // .rays file (bvh/start_nodes.h) when one is not the root.
    void closest(cl::CommandQueue& queue, const cl::Buffer& rays, const cl::Buffer& hits, uint32_t count,
                 uint32_t bounce, const std::vector<uint32_t>& starts);
    void shadow(cl::CommandQueue& queue, const cl::Buffer& rays, const cl::Buffer& occluded, uint32_t count,
                uint32_t bounce);

    // Writes every non-empty set (and its start nodes); returns the paths written.  Throws
    // std::runtime_error.
    std::vector<std::string> write() const;

private:
    struct Set {
        std::vector<HtRay> rays;
        std::vector<EmbreeHit> hits;     // closest: the anchor's record, primID the global segment id
        std::vector<uint32_t> occluded;  // shadow: 0/1
        std::vector<uint32_t> starts;    // closest: the traversal's start node per ray
    };
    Set& set(std::vector<Set>& sets, uint32_t bounce) const;

    std::string dir_, scene_;
    uint64_t scene_hash_;
    size_t max_rays_;
    const SceneGeometry* geo_ = nullptr;
    std::vector<Set> closest_, shadow_;
};

}  // namespace ht
