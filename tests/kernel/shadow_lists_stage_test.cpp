// The shadow lists' stage on the device (kernels/stages/intersect_shadow_lists.cl) answers several
// rays per work-item, finding all their cells before it tests any: every ray must get the tree's
// answer whatever its place in its work-item (first, last, alone in the last work-item) and
// whatever its neighbours are: rays served by a directional or a point light's list, rays that no
// grid serves (the tree), rays from outside a grid (nothing blocks them) and empty rays (tmax <=
// tmin: blocked, as intersect_shadow answers them).  The lists' own answers, ray by ray in double
// precision, are tests/unit/shadow_lists_test.cpp's.
#include <gtest/gtest.h>

#include "../render/render_test_util.h"
#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "kernels/geometry/candidate_list.h"
#include "random_strands.h"
#include "render/scene_upload.h"
#include "render/shadow_lists.h"

#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace ht;

HtLight kernel_light(LightType type, float x, float y, float z) {
    Light l;
    l.type = type;
    const float n = std::sqrt(x * x + y * y + z * z);
    if (type == LightType::Directional)
        l.direction = {x / n, y / n, z / n};
    else
        l.position = {x, y, z};
    return make_kernel_lights({l})[0];
}

// Ray i: towards the light of grid i % 3 from beside a random fibre (directional: along the grid's
// direction; point: to the light, stopping short of it) for i % 7 < 3; from a random point of the
// box towards grid 0's light; in a random direction (no grid serves it); empty (tmax = tmin); from
// far outside grid 1 along its direction.
std::vector<HtRay> mixed_rays(const SceneGeometry& geo, const ShadowLists& l, size_t n) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<HtRay> rays;
    for (size_t i = 0; i < n; ++i) {
        const size_t kind = i % 7;
        const HtShadowGrid& grid = l.grids[kind < 3 ? kind : kind == 6 ? 1 : 0];
        const bool along = grid.kind == HT_SHADOW_GRID_ALONG;
        const real3 light = make_real3(grid.dir[0], grid.dir[1], grid.dir[2]);
        real3 o = make_real3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2);
        if (kind < 3) {
            const HtSegment& s = geo.segments[size_t(u(rng) * double(geo.segments.size())) % geo.segments.size()];
            const HtPoint& a = geo.points[s.point];
            const HtPoint& b = geo.points[s.point + 1];
            const double f = u(rng);
            o = ht_point_pos(a) * (1 - f) + ht_point_pos(b) * f;
            const real3 away = along ? light : normalize(light - o);
            o = o + away * (1.05 * ht_hit_radius(a, b));
        }
        real3 d = along ? light : normalize(light - o);
        double tmax = along ? 1e30 : std::sqrt(dot(light - o, light - o)) * 0.999;
        if (kind == 4) {
            d = normalize(make_real3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
            tmax = 1e30;
        }
        if (kind == 6) o = o - d * 50.0;  // behind the hair as the light sees it: outside the grid
        HtRay r;
        r.ox = float(o.x), r.oy = float(o.y), r.oz = float(o.z);
        r.dx = float(d.x), r.dy = float(d.y), r.dz = float(d.z);
        if (along && kind != 4) r.dx = grid.dir[0], r.dy = grid.dir[1], r.dz = grid.dir[2];
        r.tmin = 0.0f;
        r.tmax = kind == 5 ? 0.0f : float(tmax);
        rays.push_back(r);
    }
    return rays;
}

}  // namespace

TEST(ShadowListsStage, EveryRayOfAWorkItemAnswersAsTheTree) {
    const SceneGeometry g = build_geometry(httest::random_strands(3, 300, 8, 0.08, 0.02, 0.4, 0.6, 0.5));
    const std::vector<HtLight> lights = {kernel_light(LightType::Directional, 0.3f, -1, 0.2f),
                                         kernel_light(LightType::Directional, -1, 0.1f, 0.4f),
                                         kernel_light(LightType::Point, 0.5f, 8, 1)};
    const ShadowLists l = build_shadow_lists(g, lights);
    ASSERT_EQ(l.grids.size(), 3u);
    ASSERT_EQ(l.grids[2].kind, HT_SHADOW_GRID_FROM_POINT);
    const std::vector<HtRay> all = mixed_rays(g, l, 1009);

    const DeviceGeometry geo = upload_geometry(rendertest::context(), g);
    DeviceTracer tracer(rendertest::context(), geo);
    tracer.set_shadow_lists(l.grids, l.start, l.count, l.primitive, l.key);
    // counts around the rays per work-item: one alone, a work-item short by one, exactly full, one
    // over, and many work-items with a partial last one
    const uint32_t per = HT_SHADOW_LIST_RAYS_PER_ITEM;
    for (const size_t n : {size_t(1), size_t(per - 1), size_t(per), size_t(per + 1), size_t(3 * per + 5), all.size()}) {
        const std::vector<HtRay> rays(all.begin(), all.begin() + std::ptrdiff_t(n));
        const std::vector<uint32_t> tree = tracer.trace_shadow(rays);
        // the output buffer left holding the opposite answers (an empty ray is blocked, a ray far
        // from the hair is clear), so a ray the stage skipped cannot pass with a stale answer
        std::vector<HtRay> opposite(n);
        for (size_t i = 0; i < n; ++i) opposite[i] = HtRay{100.0f, 100.0f, 100.0f, 0.0f, 1.0f, 0.0f, 0.0f, tree[i] ? 1.0f : 0.0f};
        const std::vector<uint32_t> stale = tracer.trace_shadow(opposite);
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(stale[i], 1u - tree[i]);
        tracer.set_rays(rays);
        tracer.use_shadow_lists();
        tracer.enqueue_shadow();
        tracer.finish();
        std::vector<uint32_t> lists;
        tracer.read_occluded(lists);
        ASSERT_EQ(lists.size(), n);
        for (size_t i = 0; i < n; ++i)
            EXPECT_EQ(lists[i], tree[i]) << "ray " << i << " (kind " << i % 7 << ") of " << n;
        if (n == all.size()) {
            size_t blocked = 0, empty_blocked = 0;
            for (size_t i = 0; i < n; ++i) {
                blocked += tree[i];
                if (i % 7 == 5) empty_blocked += tree[i];
            }
            EXPECT_EQ(empty_blocked, (n + 1) / 7) << "an empty ray counts as blocked";
            EXPECT_GT(blocked, n / 4) << "rays from the fibres are mostly blocked";
            EXPECT_LT(blocked, n * 3 / 4) << "and rays from outside the grid are clear";
        }
    }
}
