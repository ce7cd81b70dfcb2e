// Scene-level pieces: dispatch, error format, hygiene rule, bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/hygiene.h"
#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

Strands make_strands(const std::vector<std::vector<Vec3f>>& strands, float radius = 0.5f) {
    Strands s;
    s.first_point.push_back(0);
    for (const auto& strand : strands) {
        for (const Vec3f& p : strand) s.points.push_back(p), s.radius.push_back(radius);
        s.first_point.push_back(static_cast<uint32_t>(s.points.size()));
        s.material.push_back(0);
    }
    return s;
}

TEST(SceneCommon, DispatchOnExtension) {
    test::TempDir dir;
    const std::string unknown = dir.file("hair.xyz");
    test::write_text(unknown, "v 0 0 0\n");
    std::string msg = scene_error_of([&] { load_scene(unknown); });
    test::expect_one_line_naming(msg, unknown);
    EXPECT_TRUE(contains(msg, "unknown scene type '.xyz'")) << msg;

    const std::string upper = dir.file("HAIR.HAIR");
    test::write_file(upper, test::make_hair_bytes(test::HairSpec{test::three_strands()}));
    EXPECT_EQ(load_scene(upper).strands.strand_count(), 3u);

    msg = scene_error_of([&] { load_scene(dir.file("nothing.data")); });
    EXPECT_TRUE(contains(msg, "cannot open")) << msg;
}

TEST(SceneCommon, HygieneRepairsAndCounts) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Strands s = make_strands({{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}},
                              {{5, 5, 5}},
                              {{2, 0, 0}, {2, 1e-30f, 0}, {2, 1, 0}},  // squared length underflows
                              {{3, 0, 0}, {3, 1, 0}}});
    s.material = {0, 1, 2, 3};
    const HygieneReport r = sanitize_strands(s, "x.hair");
    EXPECT_EQ(r.zero_length_segments, 2u);
    EXPECT_EQ(r.short_strands, 1u);
    EXPECT_EQ(s.first_point, (std::vector<uint32_t>{0, 2, 4, 6}));
    EXPECT_EQ(s.material, (std::vector<uint32_t>{0, 2, 3}));
    Scene scene;
    add_hygiene_warnings(scene, "x.hair", r);
    ASSERT_EQ(scene.warnings.size(), 2u);
    EXPECT_EQ(scene.warnings[0], "x.hair: dropped 2 duplicate points (zero-length segments)");

    Strands bad = make_strands({{{0, 0, 0}, {0, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {nan, 0, 0}}});
    const std::string msg = scene_error_of([&] {
        sanitize_strands(bad, "y.data", [](size_t i) { return "hair #" + std::to_string(i); });
    });
    EXPECT_TRUE(contains(msg, "y.data: hair #1 point 2: non-finite coordinate")) << msg;

    Strands all_short = make_strands({{{1, 1, 1}}, {}});
    sanitize_strands(all_short, "z");
    EXPECT_EQ(all_short.strand_count(), 0u);
    EXPECT_EQ(all_short.segment_count(), 0u);
}

TEST(SceneCommon, SizeLimits) {
    LoadOptions opt;
    EXPECT_NO_THROW(check_scene_size("f", "counts", 10, 100, opt));
    EXPECT_TRUE(contains(scene_error_of([&] { check_scene_size("f", "counts", 1, kMaxScenePoints + 1, opt); }),
                         "limit"));
    opt.max_bytes = 1000;
    EXPECT_TRUE(contains(scene_error_of([&] { check_scene_size("f", "counts", 1, 100, opt); }), "max_bytes"));
}

TEST(SceneCommon, BoundsIncludeRadius) {
    Scene s;
    s.strands = make_strands({{{0, 0, 0}, {2, 4, -1}}}, 0.5f);
    const Bounds b = scene_bounds(s);
    EXPECT_EQ(b.lo, (Vec3f{-0.5f, -0.5f, -1.5f}));
    EXPECT_EQ(b.hi, (Vec3f{2.5f, 4.5f, 0.5f}));
    EXPECT_EQ(s.strands.segment_count(), 1u);
}

}  // namespace
}  // namespace ht
