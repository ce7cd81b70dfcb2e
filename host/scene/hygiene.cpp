// Geometry hygiene: ONE rule, applied by every loader and generator through sanitize_strands().
//
//   Refused (SceneError "<file>: <strand> point <i>: <problem>"; indices as stored in the file):
//     * a point coordinate that is NaN or infinite;
//     * a radius that is NaN, infinite, zero or negative;
//     * a scene with more than 2^31 points, or whose strand arrays would need more memory than
//       LoadOptions::max_bytes (16 GiB by default); loaders check this from the counts the file
//       states, before allocating anything.
//   Repaired (counted; Scene::warnings gets one line per kind with the count):
//     * a zero-length segment: a point whose distance to the previous kept point of its strand
//       is zero in single precision (squared length below the smallest normal float, which
//       includes identical points) is dropped; the earlier point and its radius are kept;
//     * a strand left with fewer than 2 points (as stored, or after the repair above) is dropped.
//   Nothing else is changed: near-duplicate points, sharp kinks, strands crossing each other
//   and radii varying along a strand are legal input.
//
// Why refuse rather than repair NaN/Inf and bad radii: there is no meaningful value to put in
// their place, and a silently moved point or an invented radius would change the picture without
// the user knowing.  Zero-length segments and too-short strands, on the other hand, have no area
// and cannot be seen; dropping them only protects the tangent computation (a zero-length segment
// has no direction) and the BVH (zero-size leaves).
#include "scene/hygiene.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "scene/scene_error.h"

namespace ht {

uint64_t strands_bytes(uint64_t strand_count, uint64_t point_count) {
    const uint64_t per_point = sizeof(Vec3f) + sizeof(float);         // points + radius
    const uint64_t per_strand = sizeof(uint32_t) + sizeof(uint32_t);  // first_point + material
    return point_count * per_point + (strand_count + 1) * per_strand;
}

namespace {

std::string gib(uint64_t bytes) {
    return str_cat(static_cast<double>(bytes) / double(uint64_t(1) << 30), " GiB");
}

bool finite3(const Vec3f& p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

}  // namespace

void check_scene_size(const std::string& file, const std::string& what, uint64_t strand_count,
                      uint64_t point_count, const LoadOptions& opt) {
    if (point_count > kMaxScenePoints)
        scene_fail(file, what, ": ", point_count, " points is more than the limit of ",
                   kMaxScenePoints, " points");
    // Strand counts beyond the point limit can only come from a lying header; bound them the
    // same way so the byte computation below cannot overflow.
    if (strand_count > kMaxScenePoints)
        scene_fail(file, what, ": ", strand_count, " strands is more than the limit of ",
                   kMaxScenePoints, " strands");
    const uint64_t bytes = strands_bytes(strand_count, point_count);
    if (bytes > opt.max_bytes)
        scene_fail(file, what, ": the strands would need ", gib(bytes), " (", bytes,
                   " bytes), more than the limit of ", gib(opt.max_bytes), " (LoadOptions::max_bytes)");
}

float radius_from_extent(const std::vector<Vec3f>& points) {
    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (const Vec3f& p : points)
        for (int a = 0; a < 3; ++a)
            if (std::isfinite(p[a])) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    float extent = 0.0f;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
    return extent > 0.0f && std::isfinite(extent) ? extent * kRadiusPerExtent : kRadiusPerExtent;
}

bool is_zero_length_segment(const Vec3f& a, const Vec3f& b) {
    const float dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    return dx * dx + dy * dy + dz * dz < FLT_MIN;
}

HygieneReport sanitize_strands(Strands& s, const std::string& file, const StrandNamer& namer) {
    const size_t strand_count = s.strand_count();
    if (s.radius.size() != s.points.size() || s.material.size() != strand_count ||
        (strand_count > 0 && s.first_point.back() != s.points.size()))
        throw std::logic_error("sanitize_strands: inconsistent Strands arrays from " + file);
    auto name = [&](size_t strand) { return namer ? namer(strand) : str_cat("strand ", strand); };

    HygieneReport report;
    size_t kept_points = 0, kept_strands = 0;
    size_t begin = strand_count > 0 ? s.first_point[0] : 0;
    for (size_t strand = 0; strand < strand_count; ++strand) {
        // Read the end before first_point[kept_strands + 1] (which may be this slot) is written.
        const size_t end = s.first_point[strand + 1];
        if (end < begin) throw std::logic_error("sanitize_strands: first_point not monotonic");
        const size_t strand_start = kept_points;
        for (size_t i = begin; i < end; ++i) {
            const Vec3f p = s.points[i];
            const float r = s.radius[i];
            if (!finite3(p))
                scene_fail(file, name(strand), " point ", i - begin,
                           ": non-finite coordinate (", p[0], ", ", p[1], ", ", p[2], ")");
            if (!std::isfinite(r) || !(r > 0.0f))
                scene_fail(file, name(strand), " point ", i - begin, ": radius ", r,
                           " is not a positive finite number");
            if (kept_points > strand_start && is_zero_length_segment(s.points[kept_points - 1], p)) {
                ++report.zero_length_segments;
                continue;
            }
            s.points[kept_points] = p;
            s.radius[kept_points] = r;
            ++kept_points;
        }
        begin = end;
        if (kept_points - strand_start < 2) {
            ++report.short_strands;
            kept_points = strand_start;
            continue;
        }
        s.material[kept_strands] = s.material[strand];
        s.first_point[kept_strands + 1] = static_cast<uint32_t>(kept_points);
        ++kept_strands;
    }
    if (strand_count > 0) s.first_point[0] = 0;
    s.points.resize(kept_points);
    s.radius.resize(kept_points);
    s.material.resize(kept_strands);
    s.first_point.resize(strand_count > 0 ? kept_strands + 1 : 0);
    if (kept_strands == 0) s.first_point.clear();
    return report;
}

void add_hygiene_warnings(Scene& scene, const std::string& file, const HygieneReport& report) {
    if (report.zero_length_segments > 0)
        scene.warnings.push_back(str_cat(file, ": dropped ", report.zero_length_segments,
                                         " duplicate points (zero-length segments)"));
    if (report.short_strands > 0)
        scene.warnings.push_back(str_cat(file, ": dropped ", report.short_strands,
                                         " strands with fewer than 2 distinct points"));
}

}  // namespace ht
