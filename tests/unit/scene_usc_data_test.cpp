// USC-HairSalon .data loader.
#include <gtest/gtest.h>

#include <limits>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

TEST(SceneUscData, LoadsStrandsAndSkipsEmptyRoots) {
    test::TempDir dir;
    auto strands = test::three_strands();
    strands.insert(strands.begin() + 1, {{9, 9, 9}});  // empty root
    strands.push_back({});                             // zero vertices: also an empty root
    const std::string path = dir.file("hair.data");
    test::write_file(path, test::make_usc_bytes(strands));
    const Scene s = load_scene(path);
    ASSERT_EQ(s.strands.strand_count(), 3u);
    EXPECT_EQ(s.strands.point_count(), 9u);
    EXPECT_EQ(s.strands.points[3], (Vec3f{1, 0, 0}));
    EXPECT_TRUE(test::any_warning_contains(s, "skipped 2 empty roots"));
    // No radius in the format: 1/1000 of the largest extent (y: -1..3 = 4).
    EXPECT_FLOAT_EQ(s.strands.radius[0], 0.004f);
    EXPECT_TRUE(test::any_warning_contains(s, "stores no radius"));

    LoadOptions opt;
    opt.default_radius = 0.02f;
    const Scene with_radius = load_usc_data(path, opt);
    EXPECT_FLOAT_EQ(with_radius.strands.radius[8], 0.02f);
    EXPECT_FALSE(test::any_warning_contains(with_radius, "stores no radius"));
}

TEST(SceneUscData, TruncatedAtEveryOffsetThrows) {
    test::TempDir dir;
    auto strands = test::three_strands();
    strands.push_back({{7, 7, 7}});
    const test::Bytes full = test::make_usc_bytes(strands);
    const std::string path = dir.file("cut.data");
    for (size_t n = 0; n < full.size(); ++n) {
        test::write_file(path, test::Bytes(full.begin(), full.begin() + n));
        test::expect_one_line_naming(scene_error_of([&] { load_usc_data(path, {}); }), path);
    }
}

TEST(SceneUscData, LyingAndNegativeCounts) {
    test::TempDir dir;
    const std::string path = dir.file("lie.data");
    test::Bytes b = test::make_usc_bytes(test::three_strands());
    test::Bytes lie = b;
    const int32_t many = 1000000;
    std::memcpy(lie.data(), &many, 4);
    test::write_file(path, lie);
    std::string msg = scene_error_of([&] { load_usc_data(path, {}); });
    EXPECT_TRUE(contains(msg, "header says 1000000 strands")) << msg;

    const int32_t negative = -3;
    lie = b;
    std::memcpy(lie.data(), &negative, 4);
    test::write_file(path, lie);
    msg = scene_error_of([&] { load_usc_data(path, {}); });
    EXPECT_TRUE(contains(msg, "negative")) << msg;

    lie = b;
    std::memcpy(lie.data() + 4, &negative, 4);  // first strand's vertex count
    test::write_file(path, lie);
    msg = scene_error_of([&] { load_usc_data(path, {}); });
    EXPECT_TRUE(contains(msg, "strand 0 has a negative vertex count")) << msg;

    const int32_t huge = 0x7FFFFFFF;
    lie = b;
    std::memcpy(lie.data() + 4, &huge, 4);
    test::write_file(path, lie);
    msg = scene_error_of([&] { load_usc_data(path, {}); });
    EXPECT_TRUE(contains(msg, "strand 0 says 2147483647 vertices")) << msg;
}

TEST(SceneUscData, NonFinitePointNamesTheFileStrandIndex) {
    test::TempDir dir;
    auto strands = test::three_strands();
    strands.insert(strands.begin(), {{0, 0, 0}});  // empty root shifts our indices, not the file's
    strands[2][1][2] = std::numeric_limits<float>::quiet_NaN();
    const std::string path = dir.file("nan.data");
    test::write_file(path, test::make_usc_bytes(strands));
    const std::string msg = scene_error_of([&] { load_usc_data(path, {}); });
    EXPECT_TRUE(contains(msg, "strand 2 point 1")) << msg;
}

TEST(SceneUscData, NoHairIsAnError) {
    test::TempDir dir;
    const std::string path = dir.file("empty.data");
    test::write_file(path, test::make_usc_bytes({{{1, 2, 3}}, {}}));
    EXPECT_TRUE(contains(scene_error_of([&] { load_usc_data(path, {}); }), "no strand"));
}

}  // namespace
}  // namespace ht
