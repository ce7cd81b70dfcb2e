#include "render/ray_dump.h"

#include "bvh/start_nodes.h"

#include "kernels/geometry/capsule.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ht {

RayDump::RayDump(std::string dir, std::string scene, size_t max_rays)
    : dir_(std::move(dir)), scene_(std::move(scene)), max_rays_(max_rays) {}

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
        s.answers.push_back(h[i].segment);
        s.t.push_back(h[i].t);
        s.u.push_back(h[i].u);
        real3 n = make_real3(0, 0, 0);
        if (h[i].segment != HT_NO_HIT) {
            const HtSegment& seg = geo_->segments[h[i].segment];
            if (ht_seg_flags(seg) & HT_SEG_TRIANGLE) {
                n = make_real3(h[i].tx, h[i].ty, h[i].tz);  // HtHit carries a triangle's normal
            } else {
                // The anchor stores an outward geometric normal: the hit's offset from the axis.
                real3 tangent;
                real u;
                n = ht_capsule_hit_offset(make_real3(r[i].ox, r[i].oy, r[i].oz), make_real3(r[i].dx, r[i].dy, r[i].dz),
                                          ht_point_pos(geo_->points[seg.point]),
                                          ht_point_pos(geo_->points[seg.point + 1]), h[i].t, &tangent, &u);
            }
        }
        s.ng.insert(s.ng.end(), {float(n.x), float(n.y), float(n.z)});
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
        s.answers.push_back(occ[i] ? 1u : 0u);
    }
}

void RayDump::write_set(const std::string& path, const Set& s, bool shadow, uint32_t bounce) const {
    // The 64-byte little-endian header host/bench/rays_file.cpp reads.
    unsigned char head[64] = {};
    auto put = [&](size_t off, uint32_t v) { std::memcpy(head + off, &v, 4); };
    std::memcpy(head, "HRAY", 4);
    put(4, 1);                                              // version
    put(8, shadow ? 1u : 0u);                               // kind
    put(12, shadow ? 2u : bounce == 0 ? 0u : 1u);           // set: camera / deeper / shadow
    put(16, uint32_t(s.rays.size()));
    put(20, 32);
    put(24, shadow ? 4u : 28u);
    put(28, uint32_t(geo_->segment_count));
    uint32_t strands = 0;
    for (const HtSegment& g : geo_->segments) strands += (ht_seg_flags(g) & HT_SEG_FIRST) != 0;
    put(32, strands);
    // width, height (the rays are not a pixel grid), curve type 0 (round linear) and the scene
    // hash (not computed: 0) stay zero
    std::memcpy(head + 56, scene_.data(), std::min<size_t>(scene_.size(), 8));  // NUL padded, not terminated

    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("--dump-rays: cannot write " + path);
    f.write(reinterpret_cast<const char*>(head), sizeof head);
    f.write(reinterpret_cast<const char*>(s.rays.data()), std::streamsize(s.rays.size() * sizeof(HtRay)));
    for (size_t i = 0; i < s.rays.size(); ++i) {
        if (shadow) {
            f.write(reinterpret_cast<const char*>(&s.answers[i]), 4);
            continue;
        }
        const bool hit = s.answers[i] != HT_NO_HIT;
        float rec[7] = {hit ? s.t[i] : INFINITY, 0, hit ? s.u[i] : 0.0f, 0, s.ng[3 * i], s.ng[3 * i + 1], s.ng[3 * i + 2]};
        const uint32_t prim = hit ? geo_->global_id(geo_->segments[s.answers[i]]) : 0xFFFFFFFFu;
        std::memcpy(&rec[1], &prim, 4);
        f.write(reinterpret_cast<const char*>(rec), sizeof rec);
    }
    if (!f) throw std::runtime_error("--dump-rays: write failed: " + path);
}

std::vector<std::string> RayDump::write() const {
    std::filesystem::create_directories(dir_);
    std::vector<std::string> out;
    for (int shadow = 0; shadow < 2; ++shadow) {
        const std::vector<Set>& sets = shadow ? shadow_ : closest_;
        for (uint32_t b = 0; b < sets.size(); ++b) {
            if (sets[b].rays.empty()) continue;
            const std::string path = (std::filesystem::path(dir_) /
                                      (scene_ + ".b" + std::to_string(b) + (shadow ? ".shadow" : ".closest") + ".rays"))
                                         .string();
            write_set(path, sets[b], shadow != 0, b);
            out.push_back(path);
            const std::vector<uint32_t>& starts = sets[b].starts;
            if (std::any_of(starts.begin(), starts.end(), [](uint32_t n) { return n != 0u; })) {
                write_start_nodes(start_nodes_path(path), *geo_, starts);
                out.push_back(start_nodes_path(path));
            }
        }
    }
    return out;
}

}  // namespace ht
