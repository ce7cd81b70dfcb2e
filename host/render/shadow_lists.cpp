#include "render/shadow_lists.h"

#include "render/candidate_lists.h"
#include "render/primitive_images.h"
#include "render/settings.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <glm/glm.hpp>

namespace ht {

double list_shadow_rays_per_path(const RenderSettings& s) {
    using Indirect = RenderSettings::Indirect;
    const bool own_stage = s.indirect == Indirect::Dual || (s.indirect == Indirect::Afs && s.max_depth <= 1);
    return own_stage ? 0.0 : double(std::max(s.first_hit_light_samples, 1));
}

bool casts_shadow_lists(const HtLight& l) {
    return l.type == HT_LIGHT_DIRECTIONAL || l.type == HT_LIGHT_POINT || l.type == HT_LIGHT_SPOT;
}

uint64_t ShadowLists::bytes() const {
    return grids.size() * sizeof(HtShadowGrid) + (start.size() + count.size() + primitive.size()) * sizeof(uint32_t) +
           key.size() * sizeof(float);
}

namespace {

// The grid across direction w (unit vectors u, v across it): the extent of the points' balls in
// u and v and the cell's side; finite is false when a point is not finite.
struct GridFrame {
    double lo_u = HUGE_VAL, hi_u = -HUGE_VAL, lo_v = HUGE_VAL, hi_v = -HUGE_VAL, cell = 0;
    bool finite = true;
};

// point i's u, v, w and its ball radius widened by the margin (made again for each primitive at
// the point, rather than kept per point: the array cost more in fresh pages than the arithmetic
// twice)
glm::dvec4 point_along(const SceneGeometry& g, size_t i, const glm::dvec3& w, const glm::dvec3& u, const glm::dvec3& v, double margin) {
    const glm::dvec3 p(g.points[i].x, g.points[i].y, g.points[i].z);
    return {glm::dot(p, u), glm::dot(p, v), glm::dot(p, w), ball_radius(g, i) + margin};
}

// Every step-th point (1: every point, as the lists need; more: an estimate's frame).
GridFrame grid_frame(const SceneGeometry& g, const glm::dvec3& w, const glm::dvec3& u, const glm::dvec3& v, double margin,
                     double cell_radii, size_t step = 1) {
    // per thread: the extent of the balls' boxes, the radii's sum, whether all is finite
    struct Share {
        GridFrame f;
        double radius_sum = 0;
        size_t radius_count = 0;
    };
    std::vector<Share> shares(static_cast<size_t>(host_threads()));
    in_parallel((g.points.size() + step - 1) / step, [&](int t, size_t begin, size_t end) {
        Share& sh = shares[size_t(t)];
        for (size_t i = begin * step; i < end * step && i < g.points.size(); i += step) {
            const glm::dvec4 a = point_along(g, i, w, u, v, margin);
            sh.f.finite = sh.f.finite && std::isfinite(a[0] + a[1] + a[2] + a[3]);
            sh.f.lo_u = std::min(sh.f.lo_u, a[0] - a[3]), sh.f.hi_u = std::max(sh.f.hi_u, a[0] + a[3]);
            sh.f.lo_v = std::min(sh.f.lo_v, a[1] - a[3]), sh.f.hi_v = std::max(sh.f.hi_v, a[1] + a[3]);
            if (g.points[i].r > 0) sh.radius_sum += g.points[i].r, ++sh.radius_count;
        }
    });
    GridFrame all;
    double radius_sum = 0;
    size_t radius_count = 0;
    for (const Share& sh : shares) {
        all.lo_u = std::min(all.lo_u, sh.f.lo_u), all.hi_u = std::max(all.hi_u, sh.f.hi_u);
        all.lo_v = std::min(all.lo_v, sh.f.lo_v), all.hi_v = std::max(all.hi_v, sh.f.hi_v);
        radius_sum += sh.radius_sum, radius_count += sh.radius_count;
        all.finite = all.finite && sh.f.finite;
    }
    if (!all.finite) return all;
    // cells of cell_radii mean radii (or a 1024th of the extent without fibres), fewer than
    // kMaxShadowGridSide a side, and one more than the extent needs: every box lies inside the
    // grid, so a ray whose cell is outside it meets nothing (kernels/geometry/candidate_list.h)
    const double extent = std::max(all.hi_u - all.lo_u, all.hi_v - all.lo_v);
    double cell = radius_count ? cell_radii * radius_sum / double(radius_count) : extent / 1024;
    // no more cells than kShadowCellsPerPrimitive per primitive: thin, sparse fibres over a wide
    // extent would otherwise spend megabytes on empty cells
    const double cells = std::max(1024.0, kShadowCellsPerPrimitive * double(g.segments.size()));
    all.cell = std::max({cell, std::sqrt((all.hi_u - all.lo_u) * (all.hi_v - all.lo_v) / cells),
                         extent / (kMaxShadowGridSide - 2), 1e-30});
    return all;
}

// The shadow ray's direction toward `light` as the kernel makes it (kernels/lights.h: the light's,
// negated) into grid->dir, and w (it, normalised) with the unit vectors u, v across it; false
// when it is not finite.
bool light_frame(const HtLight& light, HtShadowGrid* grid, glm::dvec3* w, glm::dvec3* u, glm::dvec3* v) {
    for (int i = 0; i < 3; ++i) grid->dir[i] = -light.direction[i];
    *w = glm::normalize(glm::dvec3(grid->dir[0], grid->dir[1], grid->dir[2]));
    if (!std::isfinite(w->x + w->y + w->z)) return false;
    const glm::dvec3 other = std::fabs(w->x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    *u = glm::normalize(glm::cross(*w, other)), *v = glm::cross(*w, *u);
    return true;
}

// the kernel's float rounding of a ray origin's coordinates and of the capsule roots: a few ulps
// of the scene's largest coordinate, covered by far (every step-th point's, as grid_frame)
double shadow_margin(const SceneGeometry& g, size_t step = 1) {
    double scale = 1;
    for (size_t i = 0; i < g.points.size(); i += step)
        scale = std::max({scale, std::fabs(double(g.points[i].x)), std::fabs(double(g.points[i].y)), std::fabs(double(g.points[i].z))});
    return 1e-5 * scale;
}

// The primitives' shadows across direction `dir` as images on a grid (cell units), keyed by how
// far along dir each reaches, rounded up; false when a point is not finite.  The same bounds as
// the camera's (render/primitive_images.h): a primitive lies in the hull of its vertices' balls,
// and the hull's shadow in the hull of the balls' shadows, a capsule's as the hull of its two end
// boxes.  The boxes are widened by `margin` (world units) for the kernel's float arithmetic.
bool project_along(const SceneGeometry& g, const PrimitiveStarts& starts, const glm::dvec3& w, const glm::dvec3& u, const glm::dvec3& v, double margin,
                   double cell_radii, HtShadowGrid* grid, ProjectedPrimitives* out) {
    if (g.points.empty() || g.segments.empty()) return false;
    const GridFrame all = grid_frame(g, w, u, v, margin, cell_radii);
    if (!all.finite) return false;
    const double cell = all.cell;
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
            const glm::dvec4 p = point_along(g, first + j, w, u, v, margin);
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

// A point or spot light's grid (HT_SHADOW_GRID_FROM_POINT): the image a camera at the light would
// see, holding every primitive.  A shadow ray's line passes within `beside` of the light (the
// kernel sends it the tree otherwise), so each vertex's ball is widened by beside and the
// margin for the kernel's float arithmetic, and the images are made by the camera's own projection
// (render/primitive_images.h).  ok is false when nothing can be proved: a point not finite, a ball
// reaching the light's plane, or the image wider than kMaxPointGridTangent each way from its centre.
struct PointView {
    HtCamera camera{};
    double widen = 0, beside = 0, cell = 0;  // cell: its side in tangent units
    glm::dvec3 f{0.0}, right{0.0}, up{0.0}; // unit frame: depth, image x, image y
    double tx = 0, ty = 0;                   // the image's half-width and half-height (tangents)
    bool ok = false;
};
constexpr double kMaxPointGridTangent = 2.0;  // 63 degrees: a light among the hair gets no grid

// Every step-th point, as grid_frame.
PointView point_view(const SceneGeometry& g, const HtLight& light, double margin, double cell_radii, size_t step = 1) {
    PointView pv;
    const glm::dvec3 L(light.position[0], light.position[1], light.position[2]);
    if (!std::isfinite(L.x + L.y + L.z) || g.points.empty()) return pv;
    margin = std::max(margin, 1e-5 * std::max({std::fabs(L.x), std::fabs(L.y), std::fabs(L.z)}));
    // the points' box centre and largest radius: the image's axis and how far beside the light a
    // fibre's shadow ray may pass (its origin is spawned up to 2.01 radii from the point it aims
    // from, kernels/integrator/shading_point.h ht_fibre_spawn)
    glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
    double r_max = 0;
    for (size_t i = 0; i < g.points.size(); i += step) {
        const glm::dvec3 p(g.points[i].x, g.points[i].y, g.points[i].z);
        lo = glm::min(lo, p), hi = glm::max(hi, p);
        r_max = std::max(r_max, double(g.points[i].r));
    }
    pv.beside = 2.05 * r_max + margin;
    pv.widen = pv.beside + margin;
    pv.f = glm::normalize(0.5 * (lo + hi) - L);
    if (!std::isfinite(pv.f.x + pv.f.y + pv.f.z + r_max)) return pv;
    const glm::dvec3 other = std::fabs(pv.f.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    pv.right = glm::normalize(glm::cross(pv.f, other)), pv.up = glm::cross(pv.right, pv.f);
    // the balls' tangent bounds (as project_primitives bounds them) and their mean angular radius
    struct Share {
        double tx = 0, ty = 0, angle_sum = 0;
        size_t angle_count = 0;
        bool ok = true;
    };
    std::vector<Share> shares(static_cast<size_t>(host_threads()));
    in_parallel((g.points.size() + step - 1) / step, [&](int t, size_t begin, size_t end) {
        Share& sh = shares[size_t(t)];
        for (size_t i = begin * step; i < end * step && i < g.points.size(); i += step) {
            const glm::dvec3 p = glm::dvec3(g.points[i].x, g.points[i].y, g.points[i].z) - L;
            const double x = glm::dot(p, pv.f), a = glm::dot(p, pv.right), b = glm::dot(p, pv.up);
            const double R = ball_radius(g, i) + pv.widen, z0 = x - R, z1 = x + R;
            if (!(z0 > 0) || !std::isfinite(z1 + a + b)) {
                sh.ok = false;
                return;
            }
            sh.tx = std::max({sh.tx, std::fabs((a - R) / z0), std::fabs((a + R) / z0), std::fabs((a - R) / z1), std::fabs((a + R) / z1)});
            sh.ty = std::max({sh.ty, std::fabs((b - R) / z0), std::fabs((b + R) / z0), std::fabs((b - R) / z1), std::fabs((b + R) / z1)});
            if (g.points[i].r > 0) sh.angle_sum += g.points[i].r / x, ++sh.angle_count;
        }
    });
    double angle_sum = 0;
    size_t angle_count = 0;
    for (const Share& sh : shares) {
        if (!sh.ok) return pv;
        pv.tx = std::max(pv.tx, sh.tx), pv.ty = std::max(pv.ty, sh.ty);
        angle_sum += sh.angle_sum, angle_count += sh.angle_count;
    }
    if (!(pv.tx <= kMaxPointGridTangent && pv.ty <= kMaxPointGridTangent)) return pv;
    // cells of cell_radii mean radii at their points' depths (in tangent units), no more than
    // kShadowCellsPerPrimitive per primitive and kMaxShadowGridSide a side, and one more each
    // way than the images need (a ray whose origin falls outside meets nothing)
    const double extent = 2 * std::max(pv.tx, pv.ty);
    double cell = angle_count ? cell_radii * angle_sum / double(angle_count) : extent / 1024;
    const double cells = std::max(1024.0, kShadowCellsPerPrimitive * double(g.segments.size()));
    cell = std::max({cell, std::sqrt(4 * pv.tx * pv.ty / cells), extent / (kMaxShadowGridSide - 4), 1e-30});
    const uint32_t nx = uint32_t(std::ceil(2 * (pv.tx + cell) / cell)), ny = uint32_t(std::ceil(2 * (pv.ty + cell) / cell));
    pv.tx = 0.5 * nx * cell, pv.ty = 0.5 * ny * cell;
    pv.cell = cell;
    for (int i = 0; i < 3; ++i) {
        pv.camera.eye[i] = float(L[i]);
        pv.camera.forward[i] = float(pv.f[i]);
        pv.camera.right[i] = float(pv.right[i] * pv.tx);
        pv.camera.up[i] = float(pv.up[i] * pv.ty);
    }
    pv.camera.width = nx, pv.camera.height = ny;
    pv.ok = true;
    return pv;
}

// The point light's grid from its view: the kernel's rows are those of the inverse of the float
// camera's frame, as project_primitives inverts it.
bool point_grid(const PointView& pv, HtShadowGrid* grid) {
    const HtCamera& c = pv.camera;
    const glm::dmat3 m(glm::dvec3(c.forward[0], c.forward[1], c.forward[2]), glm::dvec3(c.right[0], c.right[1], c.right[2]),
                       glm::dvec3(c.up[0], c.up[1], c.up[2]));
    const glm::dmat3 rows = glm::transpose(glm::inverse(m));
    for (int i = 0; i < 3; ++i)
        grid->dir[i] = c.eye[i], grid->u[i] = float(rows[0][i]), grid->v[i] = float(rows[1][i]), grid->w[i] = float(rows[2][i]);
    grid->dir[3] = float(pv.beside);
    grid->inv_cell = float(1 / pv.cell);
    grid->nx = c.width, grid->ny = c.height;
    grid->kind = HT_SHADOW_GRID_FROM_POINT;
    for (const float* row : {grid->dir, grid->u, grid->v, grid->w})
        if (!std::isfinite(row[0] + row[1] + row[2] + row[3])) return false;
    return true;
}

bool casts_from_a_point(const HtLight& l) { return l.type == HT_LIGHT_POINT || l.type == HT_LIGHT_SPOT; }

}  // namespace

ShadowLists build_shadow_lists(const SceneGeometry& g, const std::vector<HtLight>& lights, double cell_radii,
                               const PrimitiveStarts* given) {
    ShadowLists out;
    const double margin = shadow_margin(g);
    PrimitiveStarts made;
    const PrimitiveStarts* starts = given;
    for (const HtLight& light : lights) {
        if (!casts_shadow_lists(light) || out.grids.size() == kMaxShadowGrids) continue;
        HtShadowGrid grid{};
        ProjectedPrimitives projected;
        if (!starts) made = primitive_starts(g), starts = &made;  // once for every light
        if (casts_from_a_point(light)) {
            const PointView pv = point_view(g, light, margin, cell_radii);
            if (!pv.ok || !point_grid(pv, &grid)) continue;
            projected = project_primitives(pv.camera, g, starts, pv.widen);
            if (!projected.bounded) continue;
        } else {
            glm::dvec3 w, u, v;
            if (!light_frame(light, &grid, &w, &u, &v)) continue;
            if (!project_along(g, *starts, w, u, v, margin, cell_radii, &grid, &projected)) continue;
        }
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

double estimate_shadow_list_entries(const SceneGeometry& g, const std::vector<HtLight>& lights, double cell_radii) {
    if (g.points.empty() || g.segments.empty()) return 0;
    // a sample of kEstimateSample points and primitives, evenly strided: a few milliseconds on the
    // anchor's 3.2 M-segment head, where every primitive took half a second
    constexpr size_t kEstimateSample = size_t(1) << 14;
    const size_t point_step = std::max<size_t>(1, g.points.size() / kEstimateSample);
    const size_t step = std::max<size_t>(1, g.segments.size() / kEstimateSample);
    const size_t sampled = (g.segments.size() + step - 1) / step;
    const double margin = shadow_margin(g, point_step);
    double entries = 0;
    size_t grids = 0;
    for (const HtLight& light : lights) {
        if (!casts_shadow_lists(light) || grids == kMaxShadowGrids) continue;
        // per vertex: its cell coordinates and the side in cells of its ball's image
        std::function<glm::dvec3(size_t)> cells_of;
        HtShadowGrid grid{};
        glm::dvec3 w, u, v;
        GridFrame f;
        PointView pv;
        if (casts_from_a_point(light)) {
            pv = point_view(g, light, margin, cell_radii, point_step);
            if (!pv.ok) continue;
            const glm::dvec3 L(light.position[0], light.position[1], light.position[2]);
            cells_of = [&, L](size_t i) {
                const glm::dvec3 p = glm::dvec3(g.points[i].x, g.points[i].y, g.points[i].z) - L;
                const double x = glm::dot(p, pv.f), per_cell = 1 / (x * pv.cell);
                return glm::dvec3(glm::dot(p, pv.right) * per_cell, glm::dot(p, pv.up) * per_cell,
                                  2 * (ball_radius(g, i) + pv.widen) * per_cell + 1);
            };
        } else {
            if (!light_frame(light, &grid, &w, &u, &v)) continue;
            f = grid_frame(g, w, u, v, margin, cell_radii, point_step);
            if (!f.finite) continue;
            cells_of = [&](size_t i) {
                const glm::dvec4 p = point_along(g, i, w, u, v, margin);
                return glm::dvec3(p[0] / f.cell, p[1] / f.cell, 2 * p[3] / f.cell + 1);
            };
        }
        ++grids;
        std::vector<double> sums(static_cast<size_t>(host_threads()), 0.0);
        in_parallel(sampled, [&](int t, size_t begin, size_t end) {
            double sum = 0;
            for (size_t k = begin * step; k < end * step && k < g.segments.size(); k += step) {
                const HtSegment& seg = g.segments[k];
                const uint32_t n = ht_seg_flags(seg) & HT_SEG_TRIANGLE ? 3u : 2u;
                // the cells of the hull of the vertices' boxes, each box a cell wider for its
                // ends' rounding to cells: side² + side·(du + dv) for a capsule, the box for a
                // triangle
                double lo_u = HUGE_VAL, hi_u = -HUGE_VAL, lo_v = HUGE_VAL, hi_v = -HUGE_VAL, side = 0;
                for (uint32_t j = 0; j < n; ++j) {
                    const glm::dvec3 c = cells_of(seg.point + j);
                    lo_u = std::min(lo_u, c[0]), hi_u = std::max(hi_u, c[0]);
                    lo_v = std::min(lo_v, c[1]), hi_v = std::max(hi_v, c[1]);
                    side = std::max(side, c[2]);
                }
                const double du = hi_u - lo_u, dv = hi_v - lo_v;
                sum += n == 3 ? (du + side) * (dv + side) : side * side + side * (du + dv);
            }
            sums[size_t(t)] += sum;
        });
        for (const double x : sums) entries += x * double(g.segments.size()) / double(sampled);
    }
    return entries;
}

}  // namespace ht
