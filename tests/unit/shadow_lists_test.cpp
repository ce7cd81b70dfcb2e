// render/shadow_lists.h: a shadow ray toward a directional light, answered from its cell's list
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

// The ray's answer from the lists of grid g, as the kernel finds it.
uint32_t from_lists(const SceneGeometry& geo, const ShadowLists& l, size_t g, const HtRay& r) {
    const uint32_t cell = ht_shadow_cell(&l.grids[g], make_real3(r.ox, r.oy, r.oz));
    if (cell == HT_NO_CELL) return 0;
    if (l.count[cell] == kCandidatesUseTree) return ht_trace_any(geo.nodes.data(), geo.segments.data(), geo.points.data(), r);
    return ht_candidates_any(geo.segments.data(), geo.points.data(), l.primitive.data() + l.start[cell],
                             l.key.data() + l.start[cell], l.count[cell], r);
}

// n rays along each grid's direction: half from just outside random fibres' surfaces (the
// shade stage's spawn), half from random points of the box [-2, 2]^3; every answer the tree's,
// every primitive that the ray meets listed in its cell (unless the cell keeps the tree).
// *blocked_out: how many were blocked.
void expect_tree_answers(const SceneGeometry& geo, const ShadowLists& l, int n, const char* what, size_t* blocked_out = nullptr) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    size_t blocked = 0;
    for (size_t g = 0; g < l.grids.size(); ++g) {
        const real3 d = make_real3(l.grids[g].dir[0], l.grids[g].dir[1], l.grids[g].dir[2]);
        for (int i = 0; i < n; ++i) {
            real3 o;
            if (i % 2 == 0) {
                const HtSegment& s = geo.segments[size_t(u(rng) * geo.segments.size()) % geo.segments.size()];
                const HtPoint& a = geo.points[s.point];
                const HtPoint& b = geo.points[s.point + 1];
                const double f = u(rng);
                o = ht_point_pos(a) * (1 - f) + ht_point_pos(b) * f + d * (1.05 * ht_hit_radius(a, b));
            } else {
                o = make_real3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2);
            }
            HtRay r;
            r.ox = float(o.x), r.oy = float(o.y), r.oz = float(o.z);
            r.dx = l.grids[g].dir[0], r.dy = l.grids[g].dir[1], r.dz = l.grids[g].dir[2];
            r.tmin = 0.0f, r.tmax = 1e30f;
            const uint32_t tree = ht_trace_any(geo.nodes.data(), geo.segments.data(), geo.points.data(), r);
            ASSERT_EQ(from_lists(geo, l, g, r), tree) << what << ": grid " << g << " ray " << i;
            blocked += tree;
            const uint32_t cell = ht_shadow_cell(&l.grids[g], make_real3(r.ox, r.oy, r.oz));
            if (cell != HT_NO_CELL && l.count[cell] == kCandidatesUseTree) continue;
            const real3 ro = make_real3(r.ox, r.oy, r.oz), rd = make_real3(r.dx, r.dy, r.dz);
            for (uint32_t k = 0; k < geo.segments.size(); ++k) {
                const HtSegment& s = geo.segments[k];
                double t;
                if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
                    real b1, b2;
                    t = ht_triangle_intersect(ro, rd, ht_point_pos(geo.points[s.point]), ht_point_pos(geo.points[s.point + 1]),
                                              ht_point_pos(geo.points[s.point + 2]), 0.0, 1e30, &b1, &b2);
                } else {
                    const HtPoint& a = geo.points[s.point];
                    const HtPoint& b = geo.points[s.point + 1];
                    t = ht_capsule_intersect(ro, rd, ht_point_pos(a), ht_point_pos(b), ht_hit_radius(a, b), 1u, 0.0, 1e30);
                }
                if (!(t < 1e30)) continue;
                ASSERT_NE(cell, HT_NO_CELL) << what << ": a ray outside the grid meets primitive " << k;
                const uint32_t* list = l.primitive.data() + l.start[cell];
                const uint32_t* at = std::find(list, list + l.count[cell], k);
                ASSERT_NE(at, list + l.count[cell]) << what << ": primitive " << k << " missing from the ray's cell";
                const double w = ro.x * rd.x + ro.y * rd.y + ro.z * rd.z;
                EXPECT_GT(double(l.key[l.start[cell] + size_t(at - list)]), w) << what << ": primitive " << k << " reaches past the origin";
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
    Light point;
    point.type = LightType::Point;
    std::vector<HtLight> lights = make_kernel_lights({point});
    lights.push_back(directional(0.2f, -1, -0.1f));
    const ShadowLists l = build_shadow_lists(g, lights);
    ASSERT_EQ(l.grids.size(), 1u) << "only the directional light gets a grid";
    expect_tree_answers(g, l, 400, "strands on a floor");
    // cells of 100 radii over 2,400 segments: the middle cells' lists pass the cap of 1,024
    const SceneGeometry dense = build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5));
    const ShadowLists coarse = build_shadow_lists(dense, {directional(0, -1, 0)}, 100.0);
    ASSERT_EQ(coarse.grids.size(), 1u);
    EXPECT_GT(coarse.tree_cells, 0u);
    expect_tree_answers(dense, coarse, 200, "coarse");
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
