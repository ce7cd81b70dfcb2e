// Built-in procedural scenes: counts, determinism, order independence, parameters.
#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

TEST(SceneBuiltin, StrandCountsBoundsAndDeterminism) {
    const Scene a = load_scene("builtin:strand");
    EXPECT_EQ(a.strands.strand_count(), 2500u);
    EXPECT_EQ(a.strands.segment_count(), 250000u);
    EXPECT_EQ(a.strands.point_count(), 252500u);
    EXPECT_TRUE(a.warnings.empty());
    const Bounds b = scene_bounds(a);
    EXPECT_GT(b.lo[1], -50.2f);  // hangs from y = 50 down at most 100 units
    EXPECT_LT(b.hi[1], 50.2f);
    EXPECT_GT(b.hi[1], 49.9f);
    EXPECT_LT(b.hi[0] - b.lo[0], 45.0f);  // the 20-unit-wide lock fans out, waves a little
    EXPECT_LT(b.hi[2] - b.lo[2], 20.0f);
    EXPECT_FLOAT_EQ(a.strands.radius[12345], 0.1f);
    EXPECT_TRUE(a.has_camera);
    EXPECT_EQ(a.lights.size(), 1u);
    EXPECT_EQ(a.materials[0].model, "marschner");
    EXPECT_EQ(strands_content_hash(a.strands), strands_content_hash(make_builtin("strand").strands));
}

TEST(SceneBuiltin, BallCountsAndDeterminism) {
    const Scene a = load_scene("builtin:ball");
    EXPECT_EQ(a.strands.strand_count(), 10000u);
    EXPECT_EQ(a.strands.segment_count(), 300000u);
    EXPECT_EQ(strands_content_hash(a.strands), strands_content_hash(make_builtin("ball").strands));
    // Roots lie on the sphere of radius 20.
    for (size_t s = 0; s < a.strands.strand_count(); s += 997) {
        const Vec3f& p = a.strands.points[a.strands.first_point[s]];
        EXPECT_NEAR(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 20.0f, 1e-3f);
    }
    const Bounds b = scene_bounds(a);
    EXPECT_LT(b.hi[0], 55.0f);
    EXPECT_GT(b.lo[0], -55.0f);
}

TEST(SceneBuiltin, SlabCountsBoundsAndDeterminism) {
    const Scene a = load_scene("builtin:slab");
    EXPECT_EQ(a.strands.strand_count(), 8000u);
    EXPECT_EQ(a.strands.segment_count(), 160000u);
    EXPECT_TRUE(a.warnings.empty());
    EXPECT_EQ(strands_content_hash(a.strands), strands_content_hash(make_builtin("slab").strands));
    // straight hairs along -y, roots over the 40 x 10 footprint at y = 20
    for (size_t s = 0; s < a.strands.strand_count(); s += 401) {
        const uint32_t first = a.strands.first_point[s], last = a.strands.first_point[s + 1] - 1;
        const Vec3f &root = a.strands.points[first], &tip = a.strands.points[last];
        EXPECT_FLOAT_EQ(root[1], 20.0f);
        EXPECT_FLOAT_EQ(tip[1], -20.0f);
        EXPECT_EQ(root[0], tip[0]);
        EXPECT_EQ(root[2], tip[2]);
        EXPECT_LE(std::fabs(root[0]), 20.0f);
        EXPECT_LE(root[2], 0.0f);
        EXPECT_GE(root[2], -10.0f);
    }
    ASSERT_EQ(a.lights.size(), 1u);
    EXPECT_EQ(a.lights[0].type, LightType::Directional);
    EXPECT_NEAR(a.lights[0].direction[2], -std::sqrt(0.75f), 1e-6f);  // 30 degrees off the view axis
    EXPECT_EQ(a.lights[0].direction[1], 0.0f);                      // square to every fibre
    EXPECT_TRUE(a.has_camera);
}

TEST(SceneBuiltin, HairsDoNotDependOnHairCount) {
    // Each hair has its own random stream: the first 10 hairs of 20 equal the hairs of 10.
    const Scene small = make_builtin("ball?hairs=10&segments=8");
    const Scene larger = make_builtin("ball?hairs=20&segments=8");
    ASSERT_EQ(small.strands.point_count(), 90u);
    for (size_t i = 0; i < small.strands.point_count(); ++i)
        EXPECT_EQ(small.strands.points[i], larger.strands.points[i]);
    const Scene other_seed = make_builtin("ball?hairs=10&segments=8&seed=7");
    EXPECT_NE(strands_content_hash(other_seed.strands), strands_content_hash(small.strands));
}

TEST(SceneBuiltin, Parameters) {
    const Scene s = make_builtin("strand?hairs=100&segments=10&radius=0.5");
    EXPECT_EQ(s.strands.strand_count(), 100u);
    EXPECT_EQ(s.strands.segment_count(), 1000u);
    EXPECT_FLOAT_EQ(s.strands.radius[0], 0.5f);
    for (const char* bad : {"builtin:strand?hairs=0", "builtin:strand?hairs=-4", "builtin:strand?segments=x",
                            "builtin:strand?radius=-1", "builtin:strand?colour=red", "builtin:strand?hairs",
                            "builtin:wig"}) {
        const std::string msg = scene_error_of([&] { load_scene(bad); });
        test::expect_one_line_naming(msg, bad);
    }
    LoadOptions tiny;
    tiny.max_bytes = 1000;
    EXPECT_TRUE(contains(scene_error_of([&] { make_builtin("strand", tiny); }), "max_bytes"));
}

}  // namespace
}  // namespace ht
