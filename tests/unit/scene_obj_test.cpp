// OBJ line elements through tinyobjloader (host/scene/obj_file.cpp).
#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

TEST(SceneObj, LineElementsAreStrands) {
    const std::string text =
        "# two polylines, one written segment by segment, and a face\n"
        "v 0 0 0\nv 0 1 0\nv 0 2 0\nv 1 0 0\nv 1 1 0\nv 1 2 0\nv 1 3 0\n"
        "l 1 2 3\n"
        "l 4 5\nl 5 6\nl -2 -1\n"
        "f 1 2 4\n";
    const Scene s = test::load_text_scene("hair.obj", text);
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.first_point, (std::vector<uint32_t>{0, 3, 7}));
    EXPECT_EQ(s.strands.points[6], (Vec3f{1, 3, 0}));
    EXPECT_FLOAT_EQ(s.strands.radius[0], 3.0f * 1e-3f);  // 1/1000 of the extent
    EXPECT_TRUE(test::any_warning_contains(s, "ignored 1 faces"));
    LoadOptions r;
    r.default_radius = 0.25f;
    EXPECT_FLOAT_EQ(test::load_text_scene("hair.obj", text, r).strands.radius[3], 0.25f);
}

TEST(SceneObj, RefusedInput) {
    test::TempDir dir;
    const std::string nan = dir.file("nan.obj");
    test::write_text(nan, "v 0 0 0\nv 0 1 0\nv 0 1e999 0\nl 1 2\nl 3 1\n");  // tinyobjloader reads nan as 0
    std::string msg = scene_error_of([&] { load_scene(nan); });
    test::expect_one_line_naming(msg, nan);
    EXPECT_TRUE(contains(msg, "line element 1 point 0")) << msg;

    const std::string range = dir.file("range.obj");
    test::write_text(range, "v 0 0 0\nv 0 1 0\nl 1 9\n");
    msg = scene_error_of([&] { load_scene(range); });
    EXPECT_TRUE(contains(msg, "index 9 is not in [1, 2]")) << msg;

    const std::string faces = dir.file("faces.obj");
    test::write_text(faces, "v 0 0 0\nv 0 1 0\nv 1 0 0\nf 1 2 3\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(faces); }), "no line elements"));

    const std::string big = dir.file("big.obj");
    std::string text;
    for (int i = 0; i < 500; ++i) text += "v " + std::to_string(i) + " 0 0\n";
    text += "l";
    for (int i = 1; i <= 500; ++i) text += " " + std::to_string(i);
    test::write_text(big, text + "\n");
    test::expect_refused_only_under_small_limit(big, 500);
}

}  // namespace
}  // namespace ht
