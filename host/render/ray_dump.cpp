#include "render/ray_dump.h"

#include "bvh/start_nodes.h"

#include "kernels/geometry/capsule.h"

#include <algorithm>
#include <filesystem>

namespace ht {

EmbreeHit anchor_hit_record(const SceneGeometry& geometry, const HtRay& ray, const HtHit& hit) {
    if (hit.segment == HT_NO_HIT) return kEmbreeMiss;
    const HtSegment& seg = geometry.segments[hit.segment];
    real3 n;
    if (ht_seg_flags(seg) & HT_SEG_TRIANGLE) {
        n = make_real3(hit.tx, hit.ty, hit.tz);  // HtHit carries a triangle's normal
    } else {
        real3 tangent;
        real u;
        n = ht_capsule_hit_offset(make_real3(ray.ox, ray.oy, ray.oz), make_real3(ray.dx, ray.dy, ray.dz),
                                  ht_point_pos(geometry.points[seg.point]), ht_point_pos(geometry.points[seg.point + 1]),
                                  hit.t, &tangent, &u);
    }
    return EmbreeHit{hit.t, geometry.global_id(seg), hit.u, 0, {float(n.x), float(n.y), float(n.z)}};
}

RayDump::RayDump(std::string dir, std::string scene, uint64_t scene_hash, size_t max_rays)
    : dir_(std::move(dir)), scene_(std::move(scene)), scene_hash_(scene_hash), max_rays_(max_rays) {}

RayDump::Set& RayDump::set(std::vector<Set>& sets, uint32_t bounce) const {
    if (sets.size() <= bounce) sets.resize(bounce + 1);
    return sets[bounce];
}

void RayDump::closest(cl::CommandQueue& queue, const cl::Buffer& rays, const cl::Buffer& hits, uint32_t count,
                      uint32_t bounce, const std::vector<uint32_t>& starts) {
    Set& s = set(closest_, bounce);
    const size_t take = std::min<size_t>(count, max_rays_ - s.rays.size());
    if (take == 0 || !geo_) return;
    std::vector<HtRay> r(take);
    std::vector<HtHit> h(take);
    queue.enqueueReadBuffer(rays, CL_FALSE, 0, take * sizeof(HtRay), r.data());
    queue.enqueueReadBuffer(hits, CL_TRUE, 0, take * sizeof(HtHit), h.data());
    for (size_t i = 0; i < take; ++i) {
        s.rays.push_back(r[i]);
        s.starts.push_back(starts.empty() ? 0u : starts[i]);
        s.hits.push_back(anchor_hit_record(*geo_, r[i], h[i]));
    }
}

void RayDump::shadow(cl::CommandQueue& queue, const cl::Buffer& rays, const cl::Buffer& occluded, uint32_t count,
                     uint32_t bounce) {
    Set& s = set(shadow_, bounce);
    if (s.rays.size() >= max_rays_ || count == 0) return;
    std::vector<HtRay> r(count);
    std::vector<uint32_t> occ(count);
    queue.enqueueReadBuffer(rays, CL_FALSE, 0, count * sizeof(HtRay), r.data());
    queue.enqueueReadBuffer(occluded, CL_TRUE, 0, count * sizeof(uint32_t), occ.data());
    for (size_t i = 0; i < count && s.rays.size() < max_rays_; ++i) {
        if (!(r[i].tmax > r[i].tmin)) continue;  // an empty slot, not a ray
        s.rays.push_back(r[i]);
        s.occluded.push_back(occ[i] ? 1u : 0u);
    }
}

std::vector<std::string> RayDump::write() const {
    std::filesystem::create_directories(dir_);
    uint32_t strands = 0;
    if (geo_)
        for (const HtSegment& g : geo_->segments) strands += (ht_seg_flags(g) & HT_SEG_FIRST) != 0;
    std::vector<std::string> out;
    for (int shadow = 0; shadow < 2; ++shadow) {
        const std::vector<Set>& sets = shadow ? shadow_ : closest_;
        for (uint32_t b = 0; b < sets.size(); ++b) {
            if (sets[b].rays.empty()) continue;
            const std::string path = (std::filesystem::path(dir_) /
                                      (scene_ + ".b" + std::to_string(b) + (shadow ? ".shadow" : ".closest") + ".rays"))
                                         .string();
            const Set& s = sets[b];
            // set: 0 camera rays, 1 deeper bounces, 2 shadow rays
            write_rays_file(path,
                            make_rays_header(shadow ? 1u : 0u, shadow ? 2u : b == 0 ? 0u : 1u, uint32_t(s.rays.size()),
                                             uint32_t(geo_->segment_count), strands, scene_hash_, scene_),
                            s.rays, s.hits, s.occluded);
            out.push_back(path);
            const std::vector<uint32_t>& starts = s.starts;
            if (std::any_of(starts.begin(), starts.end(), [](uint32_t n) { return n != 0u; })) {
                write_start_nodes(start_nodes_path(path), *geo_, starts);
                out.push_back(start_nodes_path(path));
            }
        }
    }
    return out;
}

}  // namespace ht
