// The wavefront's per-path device buffers, declared once.  Slot k of a pass owns element k of
// each (the per-work-group counts: one element per kPathGroup slots); the bytes a path costs,
// the allocation and the memory plan (render/memory_plan.h) all follow from this table, so a
// buffer added here is counted everywhere.  A pixel of a pass takes one slot, or max(N, M) with
// --first-hit-splits N and --first-hit-light-samples M: its camera path and the continuations and
// light samples of its first vertex each own a path state, the first shade queues M shadow rays
// per camera ray, and after the first bounce the queues hold up to N rays per camera ray.
#pragma once

#include "kernels/aovs.h"
#include "kernels/types.h"

#include <cstddef>
#include <cstdint>

namespace ht {

// Work-group size of every stage launch; compact.cl's prefix sums require exactly this
// (HT_COMPACT_GROUP), and traversal runs equally fast at 32-256 (docs/POCL.md §1).
constexpr size_t kPathGroup = 64;

enum class PathBuffer {
    RaysA, RaysB,              // ping-pong extension-ray queues (shade reads one, compact fills the other)
    RayPathA, RayPathB,        // the path of each queued ray
    Hits,                      // closest hit of each queued ray
    Paths,                     // HtPathState of each path of the pass
    ShadowRays, ShadowContrib, // next-event ray per shaded slot and its unoccluded contribution
    Occluded,                  // intersect_shadow's answer per shadow ray
    StageRays, StagePath,      // shade's uncompacted extension rays and their paths
    Transmittance,             // --indirect afs: rgb(a) transmittance per shadow ray
    DualRecords,               // --indirect dual: shade's HtDualRecord per shadow slot
    GroupSums,                 // compaction's per-work-group counts
    Aovs, ShadowAovs,          // --aovs: per-path records and per-shadow-slot shares (kernels/aovs.h)
    ConnectRays, ConnectContrib, ConnectOccluded,  // --light-vertices: shade's connection per ray
    Count
};

struct PathBufferSpec {
    PathBuffer id;
    const char* name;
    size_t element_bytes;
    size_t slots_per_element;  // 1, or kPathGroup for per-work-group records
    enum Use { Always, IndirectAfs, IndirectDual, Aovs, LightVertices } use;  // allocated always, or only for that setting
};

constexpr PathBufferSpec kPathBuffers[] = {
    {PathBuffer::RaysA, "rays[0]", sizeof(HtRay), 1, PathBufferSpec::Always},
    {PathBuffer::RaysB, "rays[1]", sizeof(HtRay), 1, PathBufferSpec::Always},
    {PathBuffer::RayPathA, "ray_path[0]", sizeof(uint32_t), 1, PathBufferSpec::Always},
    {PathBuffer::RayPathB, "ray_path[1]", sizeof(uint32_t), 1, PathBufferSpec::Always},
    {PathBuffer::Hits, "hits", sizeof(HtHit), 1, PathBufferSpec::Always},
    {PathBuffer::Paths, "paths", sizeof(HtPathState), 1, PathBufferSpec::Always},
    {PathBuffer::ShadowRays, "shadow_rays", sizeof(HtRay), 1, PathBufferSpec::Always},
    {PathBuffer::ShadowContrib, "shadow_contrib", sizeof(HtShadowContrib), 1, PathBufferSpec::Always},
    {PathBuffer::Occluded, "occluded", sizeof(uint32_t), 1, PathBufferSpec::Always},
    {PathBuffer::StageRays, "stage_rays", sizeof(HtRay), 1, PathBufferSpec::Always},
    {PathBuffer::StagePath, "stage_path", sizeof(uint32_t), 1, PathBufferSpec::Always},
    {PathBuffer::Transmittance, "transmittance", 4 * sizeof(float), 1, PathBufferSpec::IndirectAfs},
    {PathBuffer::DualRecords, "dual_records", sizeof(HtDualRecord), 1, PathBufferSpec::IndirectDual},
    {PathBuffer::GroupSums, "group_sums", sizeof(uint32_t), kPathGroup, PathBufferSpec::Always},
    {PathBuffer::Aovs, "aovs", HT_AOV_STRIDE * sizeof(float), 1, PathBufferSpec::Aovs},
    {PathBuffer::ShadowAovs, "shadow_aovs", HT_SHADOW_AOV_STRIDE * sizeof(float), 1, PathBufferSpec::Aovs},
    {PathBuffer::ConnectRays, "connect_rays", sizeof(HtRay), 1, PathBufferSpec::LightVertices},
    {PathBuffer::ConnectContrib, "connect_contrib", sizeof(HtShadowContrib), 1, PathBufferSpec::LightVertices},
    {PathBuffer::ConnectOccluded, "connect_occluded", sizeof(uint32_t), 1, PathBufferSpec::LightVertices},
};
static_assert(sizeof(kPathBuffers) / sizeof(kPathBuffers[0]) == size_t(PathBuffer::Count),
              "one kPathBuffers row per PathBuffer");

constexpr bool path_buffer_rows_in_order() {
    for (size_t i = 0; i < size_t(PathBuffer::Count); ++i)
        if (size_t(kPathBuffers[i].id) != i) return false;
    return true;
}
static_assert(path_buffer_rows_in_order(), "kPathBuffers rows in PathBuffer order");

// The buffers one render uses (the AFS transmittance only with --indirect afs, the AOV records
// only with --aovs), and the path slots each pixel of a pass takes.
struct PathBufferSet {
    bool indirect_afs = false;
    bool indirect_dual = false;
    bool aovs = false;
    bool light_vertices = false;
    size_t slots_per_pixel = 1;  // max(--first-hit-splits, --first-hit-light-samples)

    bool uses(const PathBufferSpec& b) const {
        return b.use == PathBufferSpec::Always || (b.use == PathBufferSpec::IndirectAfs && indirect_afs) ||
               (b.use == PathBufferSpec::IndirectDual && indirect_dual) ||
               (b.use == PathBufferSpec::Aovs && aovs) ||
               (b.use == PathBufferSpec::LightVertices && light_vertices);
    }
    // Slots allocated for a pass of `paths` paths: whole work-groups.
    static size_t slots(size_t paths) { return (paths + kPathGroup - 1) / kPathGroup * kPathGroup; }
    // Bytes of buffer b for a pass of `paths` paths (0 when unused); per-group buffers get one
    // spare element, so that no buffer is ever of size 0 (OpenCL refuses those).
    uint64_t bytes(const PathBufferSpec& b, size_t paths) const {
        if (!uses(b)) return 0;
        return uint64_t(slots(paths) / b.slots_per_element + (b.slots_per_element > 1 ? 1 : 0)) * b.element_bytes;
    }
    // Bytes of all buffers for a pass of `paths` paths.
    uint64_t pass_bytes(size_t paths) const {
        uint64_t sum = 0;
        for (const PathBufferSpec& b : kPathBuffers) sum += bytes(b, paths);
        return sum;
    }
    // The largest single element: bounds the paths per pass by the device's largest allocation.
    size_t largest_element() const {
        size_t m = 0;
        for (const PathBufferSpec& b : kPathBuffers)
            if (uses(b) && b.slots_per_element == 1 && b.element_bytes > m) m = b.element_bytes;
        return m;
    }
};

}  // namespace ht
