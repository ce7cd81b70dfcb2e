#include "render/shadow_lists.h"

#include "render/candidate_lists.h"
#include "render/primitive_images.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace ht {

uint64_t ShadowLists::bytes() const {
    return grids.size() * sizeof(HtShadowGrid) + (start.size() + count.size() + primitive.size()) * sizeof(uint32_t) +
           key.size() * sizeof(float);
}

namespace {

// The primitives' shadows across direction `dir` as images on a grid (cell units), keyed by how
// far along dir each reaches, rounded up; false when a point is not finite.  The same bounds as
// the camera's (render/primitive_images.h): a primitive lies in the hull of its vertices' balls,
// and the hull's shadow in the hull of the balls' shadows, a capsule's as the hull of its two end
// boxes.  The boxes are widened by `margin` (world units) for the kernel's float arithmetic.
bool project_along(const SceneGeometry& g, const PrimitiveStarts& starts, const glm::dvec3& w, const glm::dvec3& u, const glm::dvec3& v, double margin,
                   double cell_radii, HtShadowGrid* grid, ProjectedPrimitives* out) {
    const size_t np = g.points.size();
    if (np == 0 || g.segments.empty()) return false;
    // point i's u, v, w and its ball radius widened by the margin (made again for each primitive
    // at the point, rather than kept per point: the array cost more in fresh pages than the
    // arithmetic twice)
    const auto point_at = [&](size_t i, double* a) {
        const glm::dvec3 p(g.points[i].x, g.points[i].y, g.points[i].z);
        a[0] = glm::dot(p, u), a[1] = glm::dot(p, v), a[2] = glm::dot(p, w), a[3] = ball_radius(g, i) + margin;
    };
    // per thread: the extent of the balls' boxes, the radii's sum, whether all is finite
    struct Share {
        double lo_u = HUGE_VAL, hi_u = -HUGE_VAL, lo_v = HUGE_VAL, hi_v = -HUGE_VAL, radius_sum = 0;
        size_t radius_count = 0;
        bool finite = true;
    };
    std::vector<Share> shares(static_cast<size_t>(host_threads()));
    in_parallel(np, [&](int t, size_t begin, size_t end) {
        Share& sh = shares[size_t(t)];
        for (size_t i = begin; i < end; ++i) {
            double a[4];
            point_at(i, a);
            sh.finite = sh.finite && std::isfinite(a[0] + a[1] + a[2] + a[3]);
            sh.lo_u = std::min(sh.lo_u, a[0] - a[3]), sh.hi_u = std::max(sh.hi_u, a[0] + a[3]);
            sh.lo_v = std::min(sh.lo_v, a[1] - a[3]), sh.hi_v = std::max(sh.hi_v, a[1] + a[3]);
            if (g.points[i].r > 0) sh.radius_sum += g.points[i].r, ++sh.radius_count;
        }
    });
    Share all;
    for (const Share& sh : shares) {
        all.lo_u = std::min(all.lo_u, sh.lo_u), all.hi_u = std::max(all.hi_u, sh.hi_u);
        all.lo_v = std::min(all.lo_v, sh.lo_v), all.hi_v = std::max(all.hi_v, sh.hi_v);
        all.radius_sum += sh.radius_sum, all.radius_count += sh.radius_count;
        all.finite = all.finite && sh.finite;
    }
    if (!all.finite) return false;
    // cells of cell_radii mean radii (or a 1024th of the extent without fibres), fewer than
    // kMaxShadowGridSide a side, and one more than the extent needs: every box lies inside the
    // grid, so a ray whose cell is outside it meets nothing (kernels/geometry/candidate_list.h)
    const double extent = std::max(all.hi_u - all.lo_u, all.hi_v - all.lo_v);
    double cell = all.radius_count ? cell_radii * all.radius_sum / double(all.radius_count) : extent / 1024;
    // no more cells than kShadowCellsPerPrimitive per primitive: thin, sparse fibres over a wide
    // extent would otherwise spend megabytes on empty cells
    const double cells = std::max(1024.0, kShadowCellsPerPrimitive * double(g.segments.size()));
    cell = std::max({cell, std::sqrt((all.hi_u - all.lo_u) * (all.hi_v - all.lo_v) / cells), extent / (kMaxShadowGridSide - 2), 1e-30});
    const uint32_t nx = std::min(kMaxShadowGridSide, uint32_t(std::floor((all.hi_u - all.lo_u) / cell)) + 2);
    const uint32_t ny = std::min(kMaxShadowGridSide, uint32_t(std::floor((all.hi_v - all.lo_v) / cell)) + 2);
    for (int i = 0; i < 3; ++i) grid->u[i] = float(u[i]), grid->v[i] = float(v[i]);
    grid->u[3] = round_down(all.lo_u), grid->v[3] = round_down(all.lo_v);
    grid->inv_cell = float(1 / cell);
    grid->nx = nx, grid->ny = ny;
    // The primitives' images, in cell units of the float values above (the kernel finds a cell
    // with those), in point order: a capsule's as its two end balls' boxes, a triangle's as the
    // box of its three; keyed by how far along w they reach, rounded up.
    const double u0 = grid->u[3], v0 = grid->v[3], inv = grid->inv_cell;
    out->bounded = images_in_point_order(starts, out->images, [&](size_t first, uint32_t k, uint32_t n, PrimitiveImage* im) {
        im->primitive = k;
        double key = -HUGE_VAL, box[4] = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
        for (uint32_t j = 0; j < n; ++j) {
            double p[4];
            point_at(first + j, p);
            const double e[4] = {(p[0] - p[3] - u0) * inv, (p[0] + p[3] - u0) * inv, (p[1] - p[3] - v0) * inv,
                                 (p[1] + p[3] - v0) * inv};
            box[0] = std::min(box[0], e[0]), box[1] = std::max(box[1], e[1]);
            box[2] = std::min(box[2], e[2]), box[3] = std::max(box[3], e[3]);
            key = std::max(key, p[2] + p[3]);
            if (j < 2) {
                float* d = j == 0 ? im->a : im->b;
                d[0] = round_down(e[0]), d[1] = round_up(e[1]), d[2] = round_down(e[2]), d[3] = round_up(e[3]);
            }
        }
        if (n == 3)  // a triangle: its box at both ends
            for (float* d : {im->a, im->b})
                d[0] = round_down(box[0]), d[1] = round_up(box[1]), d[2] = round_down(box[2]), d[3] = round_up(box[3]);
        im->depth = round_up(key);
        return ImageMade::Keep;
    });
    out->width = int(nx), out->height = int(ny);
    return out->bounded;
}

}  // namespace

ShadowLists build_shadow_lists(const SceneGeometry& g, const std::vector<HtLight>& lights, double cell_radii,
                               const PrimitiveStarts* given) {
    ShadowLists out;
    // the kernel's float rounding of a ray origin's coordinates and of the capsule roots: a few
    // ulps of the scene's largest coordinate, covered by far
    double scale = 1;
    for (const HtPoint& p : g.points) scale = std::max({scale, std::fabs(double(p.x)), std::fabs(double(p.y)), std::fabs(double(p.z))});
    const double margin = 1e-5 * scale;
    PrimitiveStarts made;
    const PrimitiveStarts* starts = given;
    for (const HtLight& light : lights) {
        if (light.type != HT_LIGHT_DIRECTIONAL || out.grids.size() == kMaxShadowGrids) continue;
        HtShadowGrid grid{};
        // the shadow ray's direction as the kernel makes it (kernels/lights.h): the light's, negated
        for (int i = 0; i < 3; ++i) grid.dir[i] = -light.direction[i];
        const glm::dvec3 w = glm::normalize(glm::dvec3(grid.dir[0], grid.dir[1], grid.dir[2]));
        if (!std::isfinite(w.x + w.y + w.z)) continue;
        const glm::dvec3 other = std::fabs(w.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 u = glm::normalize(glm::cross(w, other)), v = glm::cross(w, u);
        ProjectedPrimitives projected;
        if (!starts) made = primitive_starts(g), starts = &made;  // once for every light
        if (!project_along(g, *starts, w, u, v, margin, cell_radii, &grid, &projected)) continue;
        PixelCandidates c = pixel_candidates(projected);
        if (!c.enabled) continue;
        grid.cell_offset = uint32_t(out.start.size());
        if (out.grids.empty()) {  // the first grid's lists as they are: most scenes have one sun
            out.start = std::move(c.start), out.count = std::move(c.count);
            out.primitive = std::move(c.primitive), out.key = std::move(c.depth);
        } else {
            const uint32_t entry_offset = uint32_t(out.primitive.size());
            for (size_t i = 0; i < c.start.size(); ++i) out.start.push_back(c.start[i] + entry_offset);
            out.count.insert(out.count.end(), c.count.begin(), c.count.end());
            out.primitive.insert(out.primitive.end(), c.primitive.begin(), c.primitive.end());
            out.key.insert(out.key.end(), c.depth.begin(), c.depth.end());
        }
        out.tree_cells += c.tree_pixels;
        out.grids.push_back(grid);
    }
    return out;
}

}  // namespace ht
