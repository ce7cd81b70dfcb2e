#include "bench/bench.h"

#include "cli/args.h"
#include "core/errors.h"

#include "bench/embree_tracer.h"
#include "bench/median.h"
#include "bench/ray_sources.h"
#include "bench/startup.h"
#include "render/candidate_lists.h"
#include "render/path_grid.h"
#include "render/primitive_images.h"
#include "render/ray_dump.h"
#include "render/shadow_lists.h"
#include "render/renderer.h"
#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "bvh/start_nodes.h"
#include "cl/device.h"
#include "io/rays_file.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <thread>
#include <fstream>
#include <memory>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <stdexcept>

#include <time.h>

#include <glm/glm.hpp>

#include "kernels/geometry/capsule.h"

namespace ht {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
// Process CPU time (all threads): with other jobs on the machine, CPU-seconds per ray vary far
// less than wall time, so the bench reports both.
double cpu_ms() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct SceneArg {
    std::string name;
    std::vector<std::string> rays;
};

struct RaySet {
    std::string name;       // primary / incoherent / shadow
    bool shadow = false;
    std::vector<HtRay> rays;
    const RaysFile* reference = nullptr;  // Embree's answers, if loaded from a file
    std::vector<uint32_t> starts;         // where the render started each ray's traversal (a
                                          // `render --dump-rays` .starts file), else empty
};

// ---------------------------------------------------------------- generated rays (no files)

struct Bounds3 {
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
};
Bounds3 bounds_of(const SceneGeometry& g) {
    Bounds3 b;
    for (const HtPoint& p : g.points) {
        const double c[3] = {p.x, p.y, p.z};
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::min(b.lo[k], c[k] - p.r);
            b.hi[k] = std::max(b.hi[k], c[k] + p.r);
        }
    }
    return b;
}

// Pinhole camera from +z looking at the bounds' centre, 30 deg vertical FOV, distance fitting
// the scene's bounding sphere with 5 % margin; 4x4 pixel blocks in ray order (as the anchor).
std::vector<HtRay> camera_rays(const SceneGeometry& g, int res) {
    const Bounds3 b = bounds_of(g);
    double c[3], rad = 1e-6;
    for (int k = 0; k < 3; ++k) c[k] = 0.5 * (b.lo[k] + b.hi[k]);
    // Bounding sphere around the box centre through the farthest point (+ its radius).
    for (const HtPoint& p : g.points) {
        const double dx = p.x - c[0], dy = p.y - c[1], dz = p.z - c[2];
        rad = std::max(rad, std::sqrt(dx * dx + dy * dy + dz * dz) + std::fabs(p.r));
    }
    const double tan_half = std::tan(15.0 * M_PI / 180.0);
    const double dist = 1.05 * rad / std::sin(15.0 * M_PI / 180.0);
    std::vector<HtRay> rays((size_t)res * res);
    for (size_t i = 0; i < rays.size(); ++i) {
        const size_t blk = i / 16, j = i % 16;
        const size_t px = (blk % (res / 4)) * 4 + j % 4, py = (blk / (res / 4)) * 4 + j / 4;
        const double sx = ((px + 0.5) / res * 2 - 1) * tan_half;
        const double sy = (1 - (py + 0.5) / res * 2) * tan_half;
        const double l = std::sqrt(sx * sx + sy * sy + 1);
        rays[i] = HtRay{(float)c[0], (float)c[1], (float)(c[2] + dist), 0.0f, (float)(sx / l),
                        (float)(sy / l), (float)(-1 / l), INFINITY};
    }
    return rays;
}

// Secondary rays from primary hits (the anchor's construction): origin = hit point offset by
// 0.5 r along the normal towards the primary ray's side plus a jitter in a ball of 0.25 r;
// incoherent: direction uniform on the sphere; shadow: towards a point light.
void secondary_rays(const SceneGeometry& g, const std::vector<HtRay>& prim,
                    const std::vector<HtHit>& hits, std::vector<HtRay>& incoherent,
                    std::vector<HtRay>& shadow) {
    std::vector<size_t> hit_idx;
    for (size_t i = 0; i < hits.size(); ++i)
        if (hits[i].segment != HT_NO_HIT) hit_idx.push_back(i);
    incoherent.clear();
    shadow.clear();
    if (hit_idx.empty()) return;
    const Bounds3 b = bounds_of(g);
    double ext = 0, light[3];
    for (int k = 0; k < 3; ++k) ext = std::max(ext, b.hi[k] - b.lo[k]);
    const double lf[3] = {0.6, 0.9, 0.7};
    for (int k = 0; k < 3; ++k) light[k] = 0.5 * (b.lo[k] + b.hi[k]) + lf[k] * ext;
    std::mt19937 rng(0x1C0FFEE);
    std::normal_distribution<double> gn;
    std::uniform_real_distribution<double> un(0, 1);
    auto ball = [&](double r) {
        real3 v;
        do v = make_real3(un(rng) * 2 - 1, un(rng) * 2 - 1, un(rng) * 2 - 1);
        while (dot(v, v) > 1);
        return v * r;
    };
    for (size_t n = 0; n < prim.size(); ++n) {
        const size_t i = hit_idx[n % hit_idx.size()];
        const HtRay& p = prim[i];
        const HtSegment& s = g.segments[hits[i].segment];
        const real3 o = make_real3(p.ox, p.oy, p.oz), d = make_real3(p.dx, p.dy, p.dz);
        const real3 a = ht_point_pos(g.points[s.point]), bb = ht_point_pos(g.points[s.point + 1]);
        real3 tan;
        real u;
        real3 nrm = normalize(ht_capsule_hit_offset(o, d, a, bb, hits[i].t, &tan, &u));
        if (dot(nrm, d) > 0) nrm = -nrm;
        const double r = hits[i].radius;
        const real3 org = o + d * (double)hits[i].t + nrm * (0.5 * r);
        const real3 o1 = org + ball(0.25 * r), o2 = org + ball(0.25 * r);
        const real3 dir = normalize(make_real3(gn(rng), gn(rng), gn(rng)));
        incoherent.push_back(HtRay{(float)o1.x, (float)o1.y, (float)o1.z, 0.0f, (float)dir.x,
                                   (float)dir.y, (float)dir.z, INFINITY});
        const real3 tl = make_real3(light[0], light[1], light[2]) - o2;
        const double dl = length(tl);
        const real3 ld = tl / dl;
        shadow.push_back(HtRay{(float)o2.x, (float)o2.y, (float)o2.z, 0.0f, (float)ld.x,
                               (float)ld.y, (float)ld.z, (float)dl});
    }
}

// ---------------------------------------------------------------- checks

struct Checksum {
    size_t hits = 0;
    double sum_t = 0;
    unsigned long long sum_id = 0;
};

Checksum checksum(const SceneGeometry& g, const std::vector<HtHit>& hits) {
    Checksum c;
    for (const HtHit& h : hits)
        if (h.segment != HT_NO_HIT) {
            ++c.hits;
            c.sum_t += h.t;
            c.sum_id += g.global_id(g.segments[h.segment]);
        }
    return c;
}

struct Agreement {
    size_t n = 0, hitmiss = 0, both = 0, prim = 0, t = 0, ours_only = 0, embree_only = 0;
    // Both hit, |dt| too large, theirs the nearer; of those, theirs within 1e-2 of the origin
    // (where a ray spawned at a fibre's surface would meet that fibre again).
    size_t theirs_nearer = 0, theirs_at_origin = 0;
    bool ok() const { return n > 0 && hitmiss >= n - n / 1000 && t >= both - both / 100; }
};

Agreement compare(const SceneGeometry& g, const std::vector<HtHit>& hits, const std::vector<EmbreeHit>& ref) {
    Agreement a;
    a.n = hits.size();
    for (size_t i = 0; i < hits.size(); ++i) {
        const bool ours = hits[i].segment != HT_NO_HIT, theirs = ref[i].prim != kEmbreeNoPrim;
        if (ours != theirs) {
            (ours ? a.ours_only : a.embree_only)++;
            continue;
        }
        ++a.hitmiss;
        if (!ours) continue;
        ++a.both;
        a.prim += g.global_id(g.segments[hits[i].segment]) == ref[i].prim;
        const double te = ref[i].t;
        const bool same_t = std::fabs(hits[i].t - te) <= 1e-4 * std::max(1.0, te);
        a.t += same_t;
        a.theirs_nearer += !same_t && te < hits[i].t;
        a.theirs_at_origin += !same_t && te < hits[i].t && te < 1e-2;
    }
    return a;
}

Agreement compare_occ(const std::vector<uint32_t>& occ, const std::vector<uint32_t>& ref) {
    Agreement a;
    a.n = occ.size();
    for (size_t i = 0; i < occ.size(); ++i) {
        if ((occ[i] != 0) == (ref[i] != 0)) {
            ++a.hitmiss;
            continue;
        }
        (occ[i] ? a.ours_only : a.embree_only)++;
    }
    a.t = a.both = 0;
    return a;
}

std::string pct(size_t a, size_t n) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4f%%", n ? 100.0 * a / n : 100.0);
    return b;
}

// "<scene>.<set>.rays" -> "<set>": the anchor's primary / incoherent / shadow, and
// b<bounce>.closest / b<bounce>.shadow for `render --dump-rays` files; else the header's set.
std::string set_name_of(const RaysFile& f) {
    const std::string file = std::filesystem::path(f.path).filename().string();
    const size_t dot = file.find('.'), ext = file.rfind(".rays");
    if (dot != std::string::npos && ext != std::string::npos && ext > dot + 1) return file.substr(dot + 1, ext - dot - 1);
    return f.set_name();
}

std::vector<std::string> sibling_rays(const std::string& hair) {
    namespace fs = std::filesystem;
    std::vector<std::string> out;
    const fs::path p(hair);
    if (p.extension() != ".hair") return out;
    for (const char* set : {"primary", "incoherent", "shadow"}) {
        fs::path r = p.parent_path() / (p.stem().string() + "." + set + ".rays");
        if (fs::exists(r)) out.push_back(r.string());
    }
    return out;
}

}  // namespace

namespace {

// One ray set through the tracer: the hits checked (against the file's stored answers when it has
// them; `all_ok` becomes false on a disagreement), then timed.
nlohmann::json measure_ray_set(DeviceTracer& tracer, const SceneGeometry& geo, const RaySet& s, int reps,
                               EmbreeTracer* embree, bool json_out, bool with_grid, const std::string& answers_dir,
                               bool& all_ok) {
    nlohmann::json jr;
    jr["set"] = s.name;
    jr["rays"] = s.rays.size();
    jr["source"] = s.reference ? s.reference->path : "generated";
    tracer.set_rays(s.rays);
    // Warm-up pass = correctness pass (includes PoCL's JIT of the work-group function).
    const auto t_first = Clock::now();
    std::vector<HtHit> hits;
    std::vector<uint32_t> occ;
    if (s.shadow) {
        tracer.enqueue_shadow();
        tracer.finish();
    } else {
        tracer.enqueue_closest();
        tracer.finish();
    }
    jr["first_ms"] = ms_since(t_first);
    if (s.shadow) tracer.read_occluded(occ);
    else tracer.read_hits(hits);

    std::string check_line;
    if (s.shadow) {
        size_t n_occ = 0;
        for (uint32_t o : occ) n_occ += o != 0;
        jr["occluded"] = n_occ;
        check_line = "occluded " + std::to_string(n_occ);
    } else {
        const Checksum c = checksum(geo, hits);
        jr["hits"] = c.hits;
        jr["sum_t"] = c.sum_t;
        jr["sum_segment"] = c.sum_id;
        char b[160];
        std::snprintf(b, sizeof b, "hits %zu  sum_t %.3f  sum_segment %llu", c.hits, c.sum_t,
                      c.sum_id);
        check_line = b;
    }
    // Every answer checked before any rate is printed: against the file's stored answers (Embree's
    // for the anchor's files, hairtrace's own for `render --dump-rays` files, whose header carries
    // no scene hash) and, with --embree, against Embree on the same rays in this process.
    std::vector<std::string> agree_lines;
    auto agree = [&](const char* key, const char* label, const Agreement& a) {
        const bool ok = a.ok();
        all_ok = all_ok && ok;
        jr[key] = {{"hitmiss_agree", a.hitmiss}, {"ours_only", a.ours_only},
                   {"embree_only", a.embree_only}, {"both_hit", a.both},
                   {"primid_agree", a.prim}, {"t_agree", a.t}, {"theirs_nearer", a.theirs_nearer},
                   {"theirs_at_origin", a.theirs_at_origin}, {"ok", ok}};
        char b[400];
        if (s.shadow)
            std::snprintf(b, sizeof b,
                          "    vs %s: occlusion %zu/%zu (%s; ours-only %zu, theirs-only %zu)%s", label,
                          a.hitmiss, a.n, pct(a.hitmiss, a.n).c_str(), a.ours_only,
                          a.embree_only, ok ? "" : "  MISMATCH");
        else
            std::snprintf(b, sizeof b,
                          "    vs %s: hit/miss %zu/%zu (%s; ours-only %zu, theirs-only %zu), "
                          "primID %s, |dt|<=1e-4max(1,t) %s of %zu both-hit (theirs nearer %zu, "
                          "%zu of them at t < 0.01)%s", label,
                          a.hitmiss, a.n, pct(a.hitmiss, a.n).c_str(), a.ours_only,
                          a.embree_only, pct(a.prim, a.both).c_str(),
                          pct(a.t, a.both).c_str(), a.both, a.theirs_nearer, a.theirs_at_origin,
                          ok ? "" : "  MISMATCH");
        agree_lines.push_back(b);
    };
    if (s.reference)
        agree("embree", "stored answers",
              s.shadow ? compare_occ(occ, s.reference->occluded) : compare(geo, hits, s.reference->hits));
    // Embree's answers, checked here, are also its warm-up pass before the timed ones below
    size_t embree_count = 0;  // its hits or occluded rays
    if (embree) {
        std::vector<EmbreeHit> eh;
        std::vector<uint32_t> eo;
        embree->answer(s.rays, s.shadow, eh, eo);
        agree("embree_same_process", "Embree (same process)", s.shadow ? compare_occ(occ, eo) : compare(geo, hits, eh));
        embree_count = s.shadow ? size_t(std::count(eo.begin(), eo.end(), 1u))
                                : size_t(std::count_if(eh.begin(), eh.end(), [](const EmbreeHit& h) { return h.prim != kEmbreeNoPrim; }));
    }
    if (!answers_dir.empty() && s.reference) {
        // the file with these answers (the tree's from the root) in place of its stored ones
        std::vector<EmbreeHit> ours;
        std::vector<uint32_t> ours_occ;
        for (size_t i = 0; i < hits.size(); ++i) ours.push_back(anchor_hit_record(geo, s.rays[i], hits[i]));
        for (const uint32_t o : occ) ours_occ.push_back(o ? 1u : 0u);
        const std::filesystem::path out =
            std::filesystem::path(answers_dir) / (std::filesystem::path(s.reference->path).stem().string() + ".hairtrace.rays");
        write_rays_file(out.string(), s.reference->header, s.reference->rays, ours, ours_occ);
        jr["answers_written"] = out.string();
        if (!json_out) agree_lines.push_back("    this tracer's answers written to " + out.string());
    }

    // Timed passes of the tracer as set up: warm-up done above (the correctness pass); median of reps.
    // With Embree, each pass is paired with one of Embree's on the same rays, which of the two runs
    // first alternating, and the ratio reported is the median of the pairs' ratios (median.h
    // paired_speedup): a shared machine's speed drifts between blocks of passes, and a pair's two
    // passes share the drift (docs/PERFORMANCE.md section 1 "Ratios to Embree from paired passes").
    const auto timed = [&](std::vector<double>& times, std::vector<double>& cpu, std::vector<double>& embree_times) {
        for (int k = 0; k < reps; ++k) {
            const bool embree_first = k % 2 == 0;
            if (embree && embree_first) embree_times.push_back(embree->pass_ms(s.rays, s.shadow));
            const auto t0 = Clock::now();
            const double c0 = cpu_ms();
            if (s.shadow) tracer.enqueue_shadow();
            else tracer.enqueue_closest();
            tracer.finish();
            times.push_back(ms_since(t0));
            cpu.push_back(cpu_ms() - c0);
            if (embree && !embree_first) embree_times.push_back(embree->pass_ms(s.rays, s.shadow));
        }
    };
    const auto rate = [&](double ms) { return ms > 0 ? s.rays.size() / (ms * 1e3) : 0.0; };
    std::vector<double> times, cpu, embree_times;
    timed(times, cpu, embree_times);
    const double med = median(times);
    const double mrays = rate(med);
    // Throughput per CPU-second: what one core does when it is not shared.
    const double mrays_cpu = rate(median(cpu));
    jr["median_ms"] = med;
    jr["mrays_per_s"] = mrays;
    jr["mrays_per_cpu_s"] = mrays_cpu;
    jr["pass_ms"] = times;
    jr["pass_cpu_ms"] = cpu;
    const double embree_ms = median(embree_times), embree_mrays = rate(embree_ms);
    const double tree_ratio = paired_speedup(embree_times, times);
    if (embree) {
        jr["embree_in_process"] = {{"median_ms", embree_ms}, {"mrays_per_s", embree_mrays},
                                   {s.shadow ? "occluded" : "hits", embree_count}, {"pass_ms", embree_times},
                                   {"ratio", tree_ratio}};
    }
    // Another traversal of the same rays (set up by `use`), checked against the root's answers
    // bit for bit (or MISMATCH), then timed as above: its JSON and report line.
    const auto alternative = [&](const char* key, const std::string& label, const std::function<void()>& use) {
        use();
        size_t same = 0;
        if (s.shadow) {
            tracer.enqueue_shadow();
            tracer.finish();
            std::vector<uint32_t> other;
            tracer.read_occluded(other);
            for (size_t i = 0; i < occ.size(); ++i) same += (other[i] != 0) == (occ[i] != 0);
        } else {
            tracer.enqueue_closest();
            tracer.finish();
            std::vector<HtHit> other;
            tracer.read_hits(other);
            for (size_t i = 0; i < hits.size(); ++i)
                same += other[i].segment == hits[i].segment && std::memcmp(&other[i].t, &hits[i].t, sizeof(float)) == 0;
        }
        const size_t answers = s.rays.size();
        const bool ok = same == answers;
        all_ok = all_ok && ok;
        std::vector<double> at, ac, et;
        timed(at, ac, et);
        const double am = median(at), amrays = rate(am), amrays_cpu = rate(median(ac)), ratio = paired_speedup(et, at);
        jr[key] = {{"same_answers", same}, {"ok", ok}, {"median_ms", am}, {"mrays_per_s", amrays},
                   {"mrays_per_cpu_s", amrays_cpu}, {"pass_ms", at}};
        if (embree) {
            jr[key]["ratio_to_embree"] = ratio;
            jr[key]["embree_pass_ms"] = et;
        }
        char b[400];
        std::snprintf(b, sizeof b,
                      "    %s %s; answers identical to the root's: %zu/%zu%s): %.2f Mrays/s (median of %d, %.1f ms); "
                      "%.2f Mrays per CPU-second",
                      s.shadow ? "shadow" : "closest", label.c_str(), same, answers, ok ? "" : "  MISMATCH", amrays, reps, am,
                      amrays_cpu);
        std::string line = b;
        if (embree) {
            std::snprintf(b, sizeof b, "; hairtrace/Embree = %.2f (Embree's paired passes %.2f Mrays/s)", ratio,
                          rate(median(et)));
            line += b;
        }
        return line;
    };
    // The render's own traversals of these rays: the tree from the node each ray's traversal started
    // at in the render (bvh/start_nodes.h), and the path rays' grid (render/path_grid.h), which the
    // render's shadow stage walks too.
    std::string starts_line, grid_line, lists_line;
    if (!s.starts.empty()) {
        size_t started = 0;
        for (uint32_t n : s.starts) started += n != 0u;
        starts_line = alternative("from_start_nodes",
                                  "from the render's start nodes (" + std::to_string(started) + " of " +
                                      std::to_string(s.rays.size()) + " rays not from the root",
                                  [&] { tracer.set_starts(s.starts); });
        jr["from_start_nodes"]["rays_not_from_root"] = started;
    }
    if (with_grid)
        grid_line = alternative("by_path_grid", "by the path rays' grid (" + std::to_string(s.rays.size()) + " rays",
                                [&] { tracer.use_path_grid(); });
    // the render's camera stage with the per-pixel lists of a camera at the rays' common origin
    // (render --camera-rays lists), the lists' making timed apart
    std::string camera_line;
    if (!s.shadow) {
        const FittedCamera fc = camera_of_the_rays(s.rays);
        if (fc.ok) {
            const auto t_lists = Clock::now();
            const ProjectedPrimitives projected = project_primitives(fc.camera, geo);
            PixelCandidates lists = projected.bounded ? pixel_candidates(projected) : PixelCandidates{};
            if (lists.enabled) lists.leaf_node = leaf_entry_nodes(geo);
            const double lists_ms = ms_since(t_lists);
            if (lists.enabled) {
                const double per_segment = double(lists.bytes()) / double(std::max<size_t>(geo.segment_count, 1));
                char what[240];
                std::snprintf(what, sizeof what,
                              "by the per-pixel lists of a camera at their origin (%ux%u pixels, %zu entries, %zu pixels "
                              "keep the tree, %.1f bytes/segment, made in %.0f ms",
                              fc.camera.width, fc.camera.height, lists.primitive.size(), lists.tree_pixels, per_segment, lists_ms);
                camera_line = alternative("by_camera_lists", what, [&] {
                    tracer.set_camera_lists(lists.start, lists.count, lists.primitive, lists.depth, lists.depth_row,
                                            lists.leaf_node, fc.pixels);
                });
                jr["by_camera_lists"]["entries"] = lists.primitive.size();
                jr["by_camera_lists"]["bytes_per_segment"] = per_segment;
                jr["by_camera_lists"]["build_ms"] = lists_ms;
                tracer.use_tree();
            }
        }
    }
    // and the render's shadow stage with the per-cell lists of the lights these rays run to
    // (render --shadow-rays lists); their making timed apart, as the tree's build is
    if (s.shadow) {
        const std::vector<HtLight> lights = lights_the_rays_run_to(s.rays);
        const auto t_lists = Clock::now();
        const ShadowLists lists = lights.empty() ? ShadowLists{} : build_shadow_lists(geo, lights);
        const double lists_ms = ms_since(t_lists);
        if (lists.enabled()) {
            tracer.set_shadow_lists(lists.grids, lists.start, lists.count, lists.primitive, lists.key);
            size_t points = 0;
            for (const HtShadowGrid& g : lists.grids) points += g.kind == HT_SHADOW_GRID_FROM_POINT;
            const double per_segment = double(lists.bytes()) / double(std::max<size_t>(geo.segment_count, 1));
            char what[240];
            std::snprintf(what, sizeof what,
                          "by the lights' shadow lists (%zu directional + %zu point light grids, %zu entries, %.1f bytes/segment, "
                          "made in %.0f ms",
                          lists.grids.size() - points, points, lists.primitive.size(), per_segment, lists_ms);
            lists_line = alternative("by_shadow_lists", what, [&] { tracer.use_shadow_lists(); });
            jr["by_shadow_lists"]["grids"] = lists.grids.size();
            jr["by_shadow_lists"]["point_grids"] = points;
            jr["by_shadow_lists"]["entries"] = lists.primitive.size();
            jr["by_shadow_lists"]["bytes_per_segment"] = per_segment;
            jr["by_shadow_lists"]["build_ms"] = lists_ms;
            tracer.use_tree();  // the tree again for what follows
        }
    }
    if (!json_out) {
        std::printf("  %-10s %zu rays (%s): %s\n", s.name.c_str(), s.rays.size(),
                    !s.reference ? "generated" : ".rays file",
                    check_line.c_str());
        for (const std::string& l : agree_lines) std::printf("%s\n", l.c_str());
        std::printf("    %s: %.2f Mrays/s (median of %d, %.1f ms; first pass %.1f ms); "
                    "%.2f Mrays per CPU-second\n",
                    s.shadow ? "shadow " : "closest", mrays, reps, med,
                    jr["first_ms"].get<double>(), mrays_cpu);
        if (embree)
            std::printf("    Embree (same process, same rays): %.2f Mrays/s, %s %zu; hairtrace/Embree = %.2f\n",
                        embree_mrays, s.shadow ? "occluded" : "hits", embree_count, tree_ratio);
        if (!starts_line.empty()) std::printf("%s\n", starts_line.c_str());
        if (!grid_line.empty()) std::printf("%s\n", grid_line.c_str());
        if (!camera_line.empty()) std::printf("%s\n", camera_line.c_str());
        if (!lists_line.empty()) std::printf("%s\n", lists_line.c_str());
    }
    return jr;
}

// The machine line: what every number of the report was measured on.
nlohmann::json describe_machine(const ClContext& cl, bool print) {
    std::string cpu = "unknown CPU";
    std::ifstream info("/proc/cpuinfo");
    for (std::string line; std::getline(info, line);)
        if (line.rfind("model name", 0) == 0) {
            cpu = line.substr(line.find(':') + 2);
            break;
        }
    const unsigned cores = std::thread::hardware_concurrency();
    if (print)
        std::printf("machine: %s, %u cores; OpenCL device %s (%s, driver %s)\n", cpu.c_str(), cores,
                    cl.info().name.c_str(), cl.info().platform_version.c_str(), cl.info().driver.c_str());
    return {{"cpu", cpu}, {"cores", cores}, {"device", cl.info().name},
            {"platform", cl.info().platform_version}, {"driver", cl.info().driver}};
}

// Wavefront throughput of a small full render of the strands: paths and rays per second per bounce.
nlohmann::json measure_wavefront(ClContext& cl, const std::string& name, const Strands& strands, bool print) {
    Scene scene;
    scene.source = name;
    scene.strands = strands;
    scene.materials = {blond_hair_material()};
    scene.strands.material.assign(scene.strands.strand_count(), 0);
    ensure_camera_and_light(scene);
    RenderSettings rs;
    rs.width = rs.height = 256;
    rs.spp = 2;
    rs.max_depth = 5;
    Renderer renderer(cl, scene, rs);
    Film film;
    renderer.render(film);
    nlohmann::json jb = nlohmann::json::array();
    if (print) std::printf("  wavefront render 256x256, 2 spp, depth 5 (marschner, blond):\n");
    for (size_t b = 0; b < renderer.stats().bounces.size(); ++b) {
        const BounceStats& bs = renderer.stats().bounces[b];
        const double paths_s = bs.seconds > 0 ? bs.paths / bs.seconds : 0.0;
        const double rays_s = bs.seconds > 0 ? (bs.paths + bs.shadow_rays) / bs.seconds : 0.0;
        jb.push_back({{"bounce", b}, {"paths", bs.paths}, {"shadow_rays", bs.shadow_rays},
                      {"seconds", bs.seconds}, {"paths_per_s", paths_s}, {"rays_per_s", rays_s}});
        if (print)
            std::printf("    bounce %zu: %8llu paths %8llu shadow rays  %.3f s  %.2f M paths/s  %.2f M rays/s\n", b,
                        (unsigned long long)bs.paths, (unsigned long long)bs.shadow_rays, bs.seconds,
                        paths_s * 1e-6, rays_s * 1e-6);
    }
    return {{"width", rs.width}, {"height", rs.height}, {"spp", rs.spp}, {"max_depth", rs.max_depth},
            {"seconds", renderer.stats().seconds}, {"bounces", jb}};
}

// What `hairtrace bench` was asked to measure.
struct BenchRequest {
    std::vector<SceneArg> scenes;
    int reps = 5, device = -1, res = 1024;
    bool json = false, embree = false, wavefront = true, startup = false;
    BvhOptions bvh;
    std::string options;
    std::string answers_dir;  // --answers-out
};

// A float option's default as --help prints it: "0.8", not std::to_string's "0.800000".
std::string shortest(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

void declare_bench_options(ArgParser& p) {
    const BvhOptions d;
    p.group("scenes")
        .path("--hair", "FILE.hair", "a Cem Yuksel .hair file to measure", PathKind::Input, "", true)
        .option("--scene", "SCENE", "a scene to measure (file or builtin:NAME; default: builtin:strand builtin:ball)", "", true)
        .path("--rays", "FILE.rays", "a ray set (the Embree anchor's format) for the scene named before it; without any, <stem>.{primary,incoherent,shadow}.rays beside a .hair file are used if present, else rays are generated from a framing camera; every hit is checked against the file's stored answers before any rate is printed; a closest-hit set's X.starts beside it (written by render --dump-rays) also times the rays from the nodes the render started them at, and on a hair-only scene every set is also timed by the render's path-ray grid (render --path-rays grid: the renderer's own kernels and grid, whose size and build time are printed; a shadow set as the render's shadow stage walks it when it has no lists), each with the root's answers checked ray by ray; a closest-hit set whose rays all leave one point (a camera's, as the anchor's primary set) is also traced by the render's camera stage with the per-pixel lists (render --camera-rays lists) of a camera there fitted to the rays (its axis their mean direction, one pixel per ray); every shadow set is also answered by the render's shadow lists (render --shadow-rays lists) of the lights its rays run to (a direction 1 % of them share bit for bit: a directional light; the point where the rest's lines meet, when most of them run to it: a point light; bench/ray_sources.h), their entries, bytes per segment and making time printed, the tree's answers checked ray by ray", PathKind::Input, "", true);
    p.group("measurement")
        .option("--res", "N", "generated primary rays: N x N (rounded down to a multiple of 4)", "1024")
        .option("--reps", "N", "timed passes per case, median reported", "5")
        .flag("--no-wavefront", "skip the per-bounce throughput of a small full render")
        .flag("--startup", "instead of traversal: the time to the first image of each scene (`hairtrace render SCENE --width 64 --height 64 --spp 1` in a fresh process), with empty program caches and from the binary cache, medians of --reps, with the kernel build's share")
        .flag("--embree", "also trace every ray set through Embree 3 in this process (same rays, rtcIntersect1/rtcOccluded1) and print the ratio: each timed pass of ours is paired with one of Embree's (which runs first alternating), and hairtrace/Embree is the median of the pairs' time ratios; needs a build with libembree-dev installed")
        .flag("--json", "machine-readable report")
        .path("--answers-out", "DIR", "write each ray set read from a file again as DIR/<its name>.hairtrace.rays with this tracer's answers (the tree's, from the root, with outward normals, as render --dump-rays writes them) as its stored results, for the Embree anchor's double-precision referee: `hair_refcheck --hair X.hair --rays DIR/X.incoherent.hairtrace.rays`", PathKind::InputFolder);
    p.group("BVH builder")
        .flag("--compact", "the memory-lean preset (leaves <= 8, cheap intersections in the SAH); the options below refine it")
        .option("--leaf", "N", "segments per leaf", std::to_string(d.max_leaf))
        .option("--bins", "N", "SAH bins per axis", std::to_string(d.bins))
        .option("--cisect", "X", "SAH cost of a capsule test relative to a node visit", "1.5")
        .option("--lanes", "N", "the SAH charges --cisect per group of N capsules of a leaf (1: per capsule)", std::to_string(d.leaf_lanes))
        .option("--split", "R", "early split clipping: split a segment's box while its halves' area is below R x its own (0: off)", "0")
        .option("--split-depth", "N", "early split clipping: levels of halving", std::to_string(d.split_depth))
        .option("--obb", "R", "oriented nodes where their children's weighted box area is below R x the axis-aligned one (0: axis-aligned nodes only; host/bvh/NOTES.md \"Oriented nodes by default\")", shortest(d.obb_ratio))
        .option("--obb-split", "R", "with oriented nodes (not --obb 0): also bin each node of >= 16 segments in its segments' dominant frame and split there where that split's weighted area is below R x the axis-aligned best (0: off)", "0");
    p.group("devices")
        .option("--device", "I", "OpenCL device index (default: first CPU/GPU)")
        .option("--options", "\"...\"", "OpenCL build options for the trace kernels", DeviceTracer::default_options());
}

BenchRequest parse_bench_request(const ArgParser& p) {
    BenchRequest r;
    for (const auto& [name, value] : p.given()) {
        if (name == "--hair" || name == "--scene") r.scenes.push_back({value, {}});
        if (name != "--rays") continue;
        if (r.scenes.empty()) throw UsageError("bench: --rays must follow the --hair or --scene it belongs to");
        r.scenes.back().rays.push_back(value);
    }
    if (r.scenes.empty()) r.scenes = {{"builtin:strand", {}}, {"builtin:ball", {}}};
    r.res = p.get_int("--res", 4, 16384) / 4 * 4;
    r.reps = p.get_int("--reps", 1, 100000);
    r.wavefront = !p.has("--no-wavefront");
    r.startup = p.has("--startup");
    r.embree = p.has("--embree");
    r.json = p.has("--json");
    if (p.has("--answers-out")) r.answers_dir = p.get("--answers-out");
    if (p.has("--compact")) r.bvh = BvhOptions::compact();
    if (p.has("--leaf")) r.bvh.max_leaf = p.get_int("--leaf", 1, 1024);
    if (p.has("--bins")) r.bvh.bins = p.get_int("--bins", 4, 64);
    if (p.has("--cisect")) r.bvh.c_isect = float(p.get_double("--cisect", 0, 1e6));
    if (p.has("--lanes")) r.bvh.leaf_lanes = p.get_int("--lanes", 1, 64);
    if (p.has("--split")) r.bvh.split_ratio = float(p.get_double("--split", 0, 1e6));
    if (p.has("--split-depth")) r.bvh.split_depth = p.get_int("--split-depth", 0, 16);
    if (p.has("--obb")) r.bvh.obb_ratio = float(p.get_double("--obb", 0, 1e6));
    if (p.has("--obb-split")) r.bvh.obb_split = float(p.get_double("--obb-split", 0, 1e6));
    if (r.bvh.obb_split > 0 && !(r.bvh.obb_ratio > 0))
        throw p.error("--obb-split", "needs oriented nodes (not --obb 0): the splits serve oriented boxes");
    if (p.has("--device")) r.device = p.get_int("--device", 0, 1000);
    r.options = p.get("--options");
    return r;
}

}  // namespace

int bench_main(const std::vector<std::string>& args) {
    ArgParser p("bench", "BVH build and OpenCL intersection throughput, per scene and ray set; with ray files every ray's\n"
                         "hit is checked against Embree's stored answer before any rate is printed.");
    declare_bench_options(p);
    p.epilog("exit codes: 0 ok, 1 hits disagree with the ray file, 2 usage or a bad input file (a ray file made for\n"
             "another scene: its segment count or content hash differs), 3 device failure");
    p.parse(args);
    if (p.wants_help()) {
        std::printf("%s", p.help().c_str());
        return 0;
    }
    BenchRequest request = parse_bench_request(p);
    std::vector<SceneArg>& scenes = request.scenes;
    const int reps = request.reps, res = request.res;
    const bool json_out = request.json, with_embree = request.embree, wavefront = request.wavefront;
    const BvhOptions& bopt = request.bvh;
    const std::string& options = request.options;
    const int device = request.device;

    nlohmann::json report = nlohmann::json::array();
    bool all_ok = true;
    ClContext cl(device);
    const nlohmann::json report_machine = describe_machine(cl, !json_out);
    if (request.startup) {
        const std::string exe = std::filesystem::read_symlink("/proc/self/exe").string();
        for (const SceneArg& sa : scenes) report.push_back(measure_startup(exe, sa.name, reps, !json_out));
        if (json_out) std::printf("%s\n", nlohmann::json{{"machine", report_machine}, {"startup", report}}.dump(2).c_str());
        return 0;
    }

    for (SceneArg& sa : scenes) {
        nlohmann::json js;
        js["scene"] = sa.name;
        const auto t_load = Clock::now();
        const Strands strands = load_scene(sa.name).strands;
        js["load_ms"] = ms_since(t_load);

        // ---- BVH build, median of 5
        std::vector<double> build_ms;
        SceneGeometry geo;
        for (int k = 0; k < 5; ++k) {
            geo = build_geometry(strands, bopt);
            build_ms.push_back(geo.stats.build_ms);
        }
        const BvhStats& st = geo.stats;
        js["segments"] = geo.segment_count;
        js["bvh"] = {{"build_ms", median(build_ms)}, {"nodes", st.nodes}, {"leaves", st.leaves},
                     {"max_depth", st.max_depth}, {"references", st.references},
                     {"sah_cost", st.sah_cost}, {"bytes_per_segment", st.bytes_per_segment},
                     {"max_leaf", bopt.max_leaf}, {"c_isect", bopt.c_isect}, {"leaf_lanes", bopt.leaf_lanes},
                     {"split_ratio", bopt.split_ratio}, {"split_depth", bopt.split_depth},
                     {"oriented", st.oriented}, {"obb_ratio", bopt.obb_ratio},
                     {"oriented_splits", st.oriented_splits}, {"obb_split", bopt.obb_split}};
        if (!json_out)
            std::printf("\nscene %s: %zu segments, %zu points\n  BVH build %.1f ms (median of 5), "
                        "%zu nodes (%zu oriented), %zu leaves, depth %zu, %zu refs, SAH %.2f, %.1f bytes/segment%s\n",
                        sa.name.c_str(), geo.segment_count, geo.points.size(), median(build_ms),
                        st.nodes, st.oriented, st.leaves, st.max_depth, st.references, st.sah_cost,
                        st.bytes_per_segment,
                        bopt.obb_split > 0 ? (", " + std::to_string(st.oriented_splits) + " oriented splits").c_str() : "");

        // Embree's build as ours: the median of 5 in this process (single builds spread 0.84-1.38x
        // their median of 5 on the AMD EPYC guest, host/bvh/NOTES.md).
        std::unique_ptr<EmbreeTracer> embree;
        if (with_embree) {
            std::vector<double> embree_ms;
            for (int k = 0; k < 5; ++k) {
                embree.reset();
                embree = std::make_unique<EmbreeTracer>(strands);
                embree_ms.push_back(embree->build_ms());
            }
            js["embree_build_ms"] = median(embree_ms);
            if (!json_out) std::printf("  Embree BVH build %.1f ms (median of 5, same process)\n", median(embree_ms));
        }

        // ---- device program
        // in the memory the renderer's geometry has (GeometryMemory::Shared); geo outlives it
        const DeviceGeometry dgeo = upload_geometry(cl, geo, 0, GeometryMemory::Shared);
        DeviceTracer tracer(cl, dgeo, options);
        const double first_ms = tracer.build_ms();
        const bool first_cached = tracer.build_cached();
        DeviceTracer tracer2(cl, dgeo, options);  // same source + options: from the cache
        js["compile"] = {{"first_ms", first_ms}, {"first_cached", first_cached},
                         {"cached_ms", tracer2.build_ms()}, {"options", options}};
        if (!json_out)
            std::printf("  kernel build: %.0f ms (%s), then %.0f ms (%s)\n", first_ms,
                        first_cached ? "binary cache" : "cold", tracer2.build_ms(),
                        tracer2.build_cached() ? "binary cache" : "cold");

        // ---- the render's path-ray grid (render/path_grid.h), for hair-only scenes
        bool with_grid = false;
        if (!geo.triangle_count) {
            const auto t_grid = Clock::now();
            const PathGrid grid = build_path_grid(geo);
            const double grid_ms = ms_since(t_grid);
            const uint64_t max_alloc = cl.info().max_alloc;
            if (!grid.empty() && !grid.fits_buffers(max_alloc)) {
                if (!json_out)  // as the render does (render/renderer.cpp keep_path_grid_if_it_fits)
                    std::printf("  path rays' grid: not timed, an array of %zu bytes exceeds the device's allocation of %llu\n",
                                grid.largest_array_bytes(), (unsigned long long)max_alloc);
            } else if (!grid.empty()) {
                tracer.set_path_grid(grid.cell_start, grid.entries, grid.grid);
                with_grid = true;
                const double per_segment = double(grid.bytes()) / double(std::max<size_t>(geo.segment_count, 1));
                js["path_grid"] = {{"build_ms", grid_ms}, {"cells", grid.cells()}, {"occupied_cells", grid.occupied_cells()},
                                   {"entries", grid.entries.size()}, {"bytes_per_segment", per_segment}, {"cell", grid.grid.cell}};
                if (!json_out)
                    std::printf("  path rays' grid: %zu cells (%zu hold capsules) of %.3g, %zu entries, %.1f bytes/segment "
                                "(with the tree's: %.1f), built in %.0f ms\n",
                                grid.cells(), grid.occupied_cells(), grid.grid.cell, grid.entries.size(), per_segment,
                                per_segment + st.bytes_per_segment, grid_ms);
            }
        }

        // ---- ray sets
        if (sa.rays.empty()) sa.rays = sibling_rays(sa.name);
        std::vector<RaysFile> files;
        std::vector<RaySet> sets;
        const uint64_t content_hash = sa.rays.empty() ? 0 : hair_file_hash(strands);
        for (const std::string& f : sa.rays) {
            files.push_back(read_rays_file(f));
            if (files.back().segments != geo.segment_count)
                throw SceneError(f + ": made for " + std::to_string(files.back().segments) + " segments, scene has " +
                                 std::to_string(geo.segment_count));
            // the anchor's content hash, when the file states one: the same count of segments
            // elsewhere would give answers that disagree for no fault of the tracer
            if (files.back().scene_hash && files.back().scene_hash != content_hash) {
                char b[160];
                std::snprintf(b, sizeof b, ": made for the scene of content hash %016llx, this scene's is %016llx",
                              (unsigned long long)files.back().scene_hash, (unsigned long long)content_hash);
                throw SceneError(f + b);
            }
        }
        for (const RaysFile& f : files) {
            RaySet s;
            s.name = set_name_of(f);
            s.shadow = f.kind == 1;
            s.rays = f.rays;
            s.reference = &f;
            std::string other_tree;
            if (!s.shadow) s.starts = read_start_nodes(start_nodes_path(f.path), geo, f.rays.size(), &other_tree);
            if (!other_tree.empty() && !json_out) std::printf("  start nodes not used: %s\n", other_tree.c_str());
            sets.push_back(std::move(s));
        }
        if (sets.empty()) {
            RaySet p{"primary", false, camera_rays(geo, res), nullptr, {}};
            const std::vector<HtHit> ph = tracer.trace_closest(p.rays);
            RaySet inc{"incoherent", false, {}, nullptr, {}}, sh{"shadow", true, {}, nullptr, {}};
            secondary_rays(geo, p.rays, ph, inc.rays, sh.rays);
            sets.push_back(std::move(p));
            if (!inc.rays.empty()) {
                sets.push_back(std::move(inc));
                sets.push_back(std::move(sh));
            }
        }

        nlohmann::json jsets = nlohmann::json::array();
        for (const RaySet& s : sets) jsets.push_back(measure_ray_set(tracer, geo, s, reps, embree.get(), json_out, with_grid, request.answers_dir, all_ok));
        js["sets"] = jsets;

        if (wavefront) js["wavefront"] = measure_wavefront(cl, sa.name, strands, !json_out);
        report.push_back(js);
    }
    if (json_out) std::printf("%s\n", nlohmann::json{{"machine", report_machine}, {"scenes", report}}.dump(2).c_str());
    return all_ok ? 0 : 1;
}

}  // namespace ht
