// render/shadow_lists.h: a shadow ray toward a directional, point or spot light, answered from its cell's list
// (kernels/geometry/candidate_list.h), must be blocked exactly when the tree says so.  Checked
// in double precision against the tree and against brute force -- every primitive the ray meets
// must be in its cell's list and not skipped as lying behind the origin -- for rays from points
// on the fibres (as next-event estimation spawns them, blocked and clear) and from anywhere in
// the scene's box, with triangles, several lights, and a grid so coarse its cells keep the tree.
#include <gtest/gtest.h>

#include "../kernel/random_strands.h"
#include "bvh/bvh.h"
#include "kernels/geometry/candidate_list.h"
#include "render/candidate_lists.h"
#include "render/primitive_images.h"
#include "render/scene_upload.h"
#include "render/shadow_lists.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

namespace {

using namespace ht;

HtLight directional(float x, float y, float z) {
    Light l;
    l.type = LightType::Directional;
    const float n = std::sqrt(x * x + y * y + z * z);
    l.direction = {x / n, y / n, z / n};
    return make_kernel_lights({l})[0];
}

HtLight point_light(LightType type, float x, float y, float z) {
    Light l;
    l.type = type;
    l.position = {x, y, z};
    l.direction = {-x, -y, -z};  // a spot light aims at the origin
    return make_kernel_lights({l})[0];
}

// The ray's answer from the lists, as the stage finds it (kernels/stages/intersect_shadow_lists.cl);
// *grid_out: the grid that served it (grid count: none).
uint32_t from_lists(const SceneGeometry& geo, const ShadowLists& l, const HtRay& r, uint32_t* grid_out = nullptr,
                    uint32_t* cell_out = nullptr, real* limit_out = nullptr) {
    uint32_t cell;
    real limit;
    const uint32_t g = ht_shadow_grid_of(l.grids.data(), uint32_t(l.grids.size()), r, &cell, &limit);
    if (grid_out) *grid_out = g;
    if (cell_out) *cell_out = cell;
    if (limit_out) *limit_out = limit;
    const uint32_t n = g == l.grids.size() ? kCandidatesUseTree : cell == HT_NO_CELL ? 0u : l.count[cell];
    if (n == kCandidatesUseTree) return ht_trace_any(geo.nodes.data(), geo.segments.data(), geo.points.data(), r);
    if (n == 0) return 0;
    return ht_shadow_list_any(geo.segments.data(), geo.points.data(), &l.grids[g], l.primitive.data() + l.start[cell],
                              l.key.data() + l.start[cell], n, r, limit);
}

// n rays toward each grid's light: half from just outside random fibres' surfaces, as the shade
// stage spawns them (towards a point light: aimed from a point on the surface, spawned from the
// axis 1.01 radii towards the light's side, so the line passes up to two radii beside the light),
// half from random points of the box [-2, 2]^3; every answer the tree's, every primitive that
// the ray meets listed in its cell (unless the cell keeps the tree) and not skipped: reaching past
// the origin towards a directional light, no deeper than the ray's limit from a point light.
// *blocked_out: how many were blocked.
void expect_tree_answers(const SceneGeometry& geo, const ShadowLists& l, int n, const char* what, size_t* blocked_out = nullptr) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    size_t blocked = 0;
    for (size_t g = 0; g < l.grids.size(); ++g) {
        const HtShadowGrid& grid = l.grids[g];
        const bool along = grid.kind == HT_SHADOW_GRID_ALONG;
        const real3 light = make_real3(grid.dir[0], grid.dir[1], grid.dir[2]);
        for (int i = 0; i < n; ++i) {
            real3 o, d;
            double tmax = 1e30;
            if (i % 2 == 0) {
                const HtSegment& s = geo.segments[size_t(u(rng) * geo.segments.size()) % geo.segments.size()];
                const HtPoint& a = geo.points[s.point];
                const HtPoint& b = geo.points[s.point + 1];
                const double f = u(rng), radius = ht_hit_radius(a, b);
                const real3 axis = ht_point_pos(a) * (1 - f) + ht_point_pos(b) * f;
                if (along) {
                    d = light;
                    o = axis + d * (1.05 * radius);
                } else {
                    const real3 t = normalize(ht_point_pos(b) - ht_point_pos(a));
                    // a point on the surface, random around the axis
                    real3 side0 = cross(t, make_real3(0.3, 0.9, 0.1));
                    side0 = side0 * (1 / std::sqrt(dot(side0, side0)));
                    const real3 side1 = cross(t, side0);
                    const double phi = 6.283185307179586 * u(rng);
                    const real3 p = axis + (side0 * std::cos(phi) + side1 * std::sin(phi)) * radius;
                    const real3 to = light - p;
                    const double dist = std::sqrt(dot(to, to));
                    d = to * (1 / dist);
                    real3 side = d - t * dot(d, t);
                    side = side * (1 / std::sqrt(dot(side, side)));
                    o = axis + side * (radius * 1.01);
                    tmax = dist - radius * 1.01;
                }
            } else {
                o = make_real3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2);
                if (along) {
                    d = light;
                } else {
                    const real3 to = light - o;
                    tmax = std::sqrt(dot(to, to));
                    d = to * (1 / tmax);
                }
            }
            HtRay r;
            r.ox = float(o.x), r.oy = float(o.y), r.oz = float(o.z);
            r.dx = float(d.x), r.dy = float(d.y), r.dz = float(d.z);
            if (along) r.dx = grid.dir[0], r.dy = grid.dir[1], r.dz = grid.dir[2];
            r.tmin = 0.0f, r.tmax = float(tmax);
            const uint32_t tree = ht_trace_any(geo.nodes.data(), geo.segments.data(), geo.points.data(), r);
            uint32_t served, cell;
            real limit;
            ASSERT_EQ(from_lists(geo, l, r, &served, &cell, &limit), tree) << what << ": grid " << g << " ray " << i;
            // a ray may pass near another grid's point light, which then serves it (correctly:
            // its points beyond that light lie behind it, where no primitive is)
            ASSERT_LT(served, l.grids.size()) << what << ": ray " << i << " of grid " << g << " takes the tree";
            if (i % 2 == 0) {
                EXPECT_EQ(served, g) << what << ": ray " << i << " from a fibre, of grid " << g;
            }
            blocked += tree;
            if (cell != HT_NO_CELL && l.count[cell] == kCandidatesUseTree) continue;
            const real3 ro = make_real3(r.ox, r.oy, r.oz), rd = make_real3(r.dx, r.dy, r.dz);
            for (uint32_t k = 0; k < geo.segments.size(); ++k) {
                const HtSegment& s = geo.segments[k];
                double t;
                if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
                    real b1, b2;
                    t = ht_triangle_intersect(ro, rd, ht_point_pos(geo.points[s.point]), ht_point_pos(geo.points[s.point + 1]),
                                              ht_point_pos(geo.points[s.point + 2]), 0.0, r.tmax, &b1, &b2);
                } else {
                    const HtPoint& a = geo.points[s.point];
                    const HtPoint& b = geo.points[s.point + 1];
                    t = ht_capsule_intersect(ro, rd, ht_point_pos(a), ht_point_pos(b), ht_hit_radius(a, b), 1u, 0.0, r.tmax);
                }
                if (!(t < r.tmax)) continue;
                ASSERT_NE(cell, HT_NO_CELL) << what << ": a ray outside the grid meets primitive " << k;
                const uint32_t* list = l.primitive.data() + l.start[cell];
                const uint32_t* at = std::find(list, list + l.count[cell], k);
                ASSERT_NE(at, list + l.count[cell]) << what << ": primitive " << k << " missing from the ray's cell";
                const double key = l.key[l.start[cell] + size_t(at - list)];
                if (l.grids[served].kind == HT_SHADOW_GRID_ALONG) {
                    const double w = ro.x * rd.x + ro.y * rd.y + ro.z * rd.z;
                    EXPECT_GT(key, w) << what << ": primitive " << k << " reaches past the origin";
                } else {
                    EXPECT_LE(key, limit) << what << ": primitive " << k << " lies deeper than the ray's limit";
                }
            }
        }
    }
    if (blocked_out) *blocked_out = blocked;
}

}  // namespace

TEST(ShadowLists, AnswersAreTheTreesUnderBruteForce) {
    const SceneGeometry g = build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5));
    const std::vector<HtLight> lights = {directional(0.3f, -1, 0.2f), directional(-1, 0.1f, 0.4f)};
    const ShadowLists l = build_shadow_lists(g, lights);
    ASSERT_EQ(l.grids.size(), 2u);
    EXPECT_EQ(l.tree_cells, 0u);
    size_t blocked = 0;
    expect_tree_answers(g, l, 400, "two lights", &blocked);
    EXPECT_GT(blocked, 100u) << "rays from inside the tuft are mostly blocked";
    EXPECT_LT(blocked, 700u) << "and some are clear";
}

TEST(ShadowLists, TrianglesPointLightsAndCoarseGrids) {
    Mesh floor;
    floor.positions = {{-2, -1, -2}, {2, -1, -2}, {2, -1, 2}, {-2, -1, 2}};
    floor.indices = {0, 1, 2, 0, 2, 3};
    const SceneGeometry g =
        build_geometry(httest::random_strands(4, 100, 8, 0.08, 0.02, 0.4, 0.6), {floor}, {SurfaceMaterialDesc{}});
    Light point;  // at the origin, among the strands: no grid
    point.type = LightType::Point;
    std::vector<HtLight> lights = make_kernel_lights({point});
    lights.push_back(directional(0.2f, -1, -0.1f));
    const ShadowLists l = build_shadow_lists(g, lights);
    ASSERT_EQ(l.grids.size(), 1u) << "only the directional light gets a grid";
    EXPECT_EQ(l.grids[0].kind, HT_SHADOW_GRID_ALONG);
    expect_tree_answers(g, l, 400, "strands on a floor");
    // cells of 100 radii over 2,400 segments: the middle cells' lists pass the cap of 1,024
    const SceneGeometry dense = build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5));
    const ShadowLists coarse = build_shadow_lists(dense, {directional(0, -1, 0)}, 100.0);
    ASSERT_EQ(coarse.grids.size(), 1u);
    EXPECT_GT(coarse.tree_cells, 0u);
    expect_tree_answers(dense, coarse, 200, "coarse");
}

// Point and spot lights outside the hair get a grid of the image a camera there would see; rays
// toward them (whose lines pass up to two radii beside the light, as the shade stage spawns them)
// take it, and the answers are the tree's.  A light among the hair, or one that would need an
// image wider than 63 degrees from its axis, gets none.
TEST(ShadowLists, PointAndSpotLightsOutsideTheHair) {
    Mesh floor;
    floor.positions = {{-2, -1, -2}, {2, -1, -2}, {2, -1, 2}, {-2, -1, 2}};
    floor.indices = {0, 1, 2, 0, 2, 3};
    const SceneGeometry g =
        build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5), {floor}, {SurfaceMaterialDesc{}});
    const std::vector<HtLight> lights = {point_light(LightType::Point, 0.5f, 4.0f, 1.5f),
                                         point_light(LightType::Spot, -3.0f, 1.0f, -2.5f), directional(0.3f, -1, 0.2f),
                                         point_light(LightType::Point, 0.1f, 0.0f, 0.05f),
                                         point_light(LightType::Point, 0.0f, 1.3f, 0.0f)};
    const ShadowLists l = build_shadow_lists(g, lights);
    ASSERT_EQ(l.grids.size(), 3u) << "the two lights among or just above the hair get none";
    EXPECT_EQ(l.grids[0].kind, HT_SHADOW_GRID_FROM_POINT);
    EXPECT_EQ(l.grids[1].kind, HT_SHADOW_GRID_FROM_POINT);
    EXPECT_EQ(l.grids[2].kind, HT_SHADOW_GRID_ALONG);
    size_t blocked = 0;
    expect_tree_answers(g, l, 600, "point, spot and directional lights", &blocked);
    EXPECT_GT(blocked, 300u) << "rays from inside the tuft and below it are mostly blocked";
    EXPECT_LT(blocked, 1500u) << "and some are clear";
    // The edge the images are widened for: rays whose lines pass the light 0.99 x as far beside
    // it as the grid lets through, through a random point q of a fibre's surface, from just behind
    // q (seen from the light): every one is blocked, and its cell must list q's fibre although q
    // lies off the line from the light through the origin.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (size_t gi = 0; gi < 2; ++gi) {
        const HtShadowGrid& grid = l.grids[gi];
        const real3 light = make_real3(grid.dir[0], grid.dir[1], grid.dir[2]);
        size_t served = 0, blocked_edge = 0;
        for (int i = 0; i < 20000; ++i) {
            const HtSegment& s = g.segments[size_t(u(rng) * 2400) % 2400];  // the strands' capsules
            const HtPoint& a = g.points[s.point];
            const HtPoint& b = g.points[s.point + 1];
            const real3 pa = ht_point_pos(a), pb = ht_point_pos(b), t = normalize(pb - pa);
            real3 side0 = cross(t, make_real3(0.3, 0.9, 0.1));
            side0 = side0 * (1 / std::sqrt(dot(side0, side0)));
            const real3 side1 = cross(t, side0);
            const double phi = 6.283185307179586 * u(rng);
            const real3 q = pa + (pb - pa) * u(rng) + (side0 * std::cos(phi) + side1 * std::sin(phi)) * (0.999 * ht_hit_radius(a, b));
            // the ray's aim: the light moved across the line to q by 0.99 x the allowance
            real3 across = cross(q - light, make_real3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
            across = across * (0.99 * grid.dir[3] / std::sqrt(dot(across, across)));
            const real3 aim = light + across, back = normalize(q - aim);
            const real3 o = q + back * (0.05 + 1.5 * u(rng));
            const real3 to = aim - o;
            const double dist = std::sqrt(dot(to, to));
            HtRay r;
            r.ox = float(o.x), r.oy = float(o.y), r.oz = float(o.z);
            r.dx = float(to.x / dist), r.dy = float(to.y / dist), r.dz = float(to.z / dist);
            r.tmin = 0.0f, r.tmax = float(dist);
            const uint32_t tree = ht_trace_any(g.nodes.data(), g.segments.data(), g.points.data(), r);
            uint32_t by;
            ASSERT_EQ(from_lists(g, l, r, &by), tree) << "grid " << gi << " edge ray " << i;
            served += by == gi, blocked_edge += tree;
        }
        EXPECT_GT(served, 19000u) << "grid " << gi << ": the edge rays take the grid";
        EXPECT_GT(blocked_edge, 19000u) << "grid " << gi << ": and are blocked by q's fibre";
    }
    // coarse cells: the middle cells keep the tree
    const ShadowLists coarse = build_shadow_lists(g, {point_light(LightType::Point, 0.5f, 4.0f, 1.5f)}, 100.0);
    ASSERT_EQ(coarse.grids.size(), 1u);
    EXPECT_GT(coarse.tree_cells, 0u);
    expect_tree_answers(g, coarse, 200, "coarse");
    // the entries' estimate, made before any list, within 15 % of the lists made
    const ShadowLists one = build_shadow_lists(g, {lights[0]});
    const double estimate = estimate_shadow_list_entries(g, {lights[0]});
    EXPECT_NEAR(estimate, double(one.primitive.size()), 0.15 * double(one.primitive.size()));
    EXPECT_EQ(estimate_shadow_list_entries(g, {lights[3]}), 0.0) << "no grid, no entries";
}

TEST(ShadowLists, NoneForNonFiniteGeometry) {
    SceneGeometry g = build_geometry(httest::random_strands(9, 10, 4, 0.1, 0.01));
    g.points[3].x = NAN;
    EXPECT_FALSE(build_shadow_lists(g, {directional(0, -1, 0)}).enabled());
    EXPECT_FALSE(build_shadow_lists(build_geometry(Strands{}), {directional(0, -1, 0)}).enabled());
}

// Made on several threads: the same grids and lists on 1, 2, 3 and 8 (render/candidate_lists.h).
TEST(ShadowLists, SameListsOnAnyThreadCount) {
    const SceneGeometry g = build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5));
    const std::vector<HtLight> lights = {directional(0.3f, -1, 0.2f), directional(-1, 0.1f, 0.4f)};
    std::vector<ShadowLists> made;
    for (const int threads : {1, 2, 3, 8}) {
        set_host_threads(threads);
        made.push_back(build_shadow_lists(g, lights));
    }
    set_host_threads(0);
    ASSERT_EQ(made[0].grids.size(), 2u);
    ASSERT_GT(made[0].primitive.size(), 10000u);
    for (size_t k = 1; k < made.size(); ++k) {
        ASSERT_EQ(made[k].grids.size(), 2u);
        EXPECT_EQ(0, std::memcmp(made[k].grids.data(), made[0].grids.data(), 2 * sizeof(HtShadowGrid))) << k;
        EXPECT_EQ(made[k].start, made[0].start) << k;
        EXPECT_EQ(made[k].count, made[0].count) << k;
        EXPECT_TRUE(made[k].primitive == made[0].primitive) << k;
        EXPECT_TRUE(made[k].key == made[0].key) << k;
    }
}
