// RenderSettings::camera_lists: camera rays test their pixel's candidate list
// (render/pixel_footprint.h, kernels/stages/intersect_camera.cl) instead of traversing the tree,
// and must find the very hits the tree finds -- so the film is the same bits, on sparse and
// dense hair, with triangles, with pixels that keep the tree beside pixels with lists, with splits
// and several bounces.  Where nothing can be proved there are no lists.
#include <gtest/gtest.h>

#include "render_test_util.h"

#include "cli_test_util.h"

namespace {

using namespace rendertest;

// lists against the tree: the same film; returns the lists' statistics
ht::RenderStats expect_same_film(const ht::Scene& s, ht::RenderSettings rs, const char* what) {
    ht::RenderStats lists, tree;
    rs.camera_lists = true;
    const ht::Film a = render(s, rs, &lists);
    rs.camera_lists = false;
    const ht::Film b = render(s, rs, &tree);
    EXPECT_EQ(a.rgba, b.rgba) << what;
    EXPECT_EQ(tree.candidate_entries, 0u) << what;
    EXPECT_EQ(lists.camera_rays, tree.camera_rays) << what;
    EXPECT_EQ(lists.shadow_rays, tree.shadow_rays) << what;
    EXPECT_EQ(lists.extension_rays, tree.extension_rays) << what;
    return lists;
}

ht::Scene scene(const std::string& name) {
    ht::Scene s = ht::load_scene(name);
    ht::ensure_camera_and_light(s);
    return s;
}

}  // namespace

TEST(CameraLists, SameFilmAsTheTree) {
    ht::Scene sparse = scene("builtin:strand?hairs=40&segments=12");
    sparse.environment.color = {0.3f, 0.45f, 0.7f};
    ht::RenderSettings rs = small_settings(4, 17, 3);
    rs.first_hit_splits = 2;
    EXPECT_GT(expect_same_film(sparse, rs, "sparse strand, splits, depth 3").candidate_entries, 0u);
    const ht::RenderStats dense = expect_same_film(scene("builtin:ball?hairs=2000&segments=16"), small_settings(3, 5, 2), "dense ball");
    EXPECT_GT(dense.candidate_entries, 48u * 48u) << "a dense ball puts several fibres under a pixel";
    EXPECT_GT(expect_same_film(scene(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_floor.gltf"), small_settings(3, 9, 3),
                               "strand on a floor (triangles)")
                  .candidate_entries,
              0u);
}

// A small cap: the ball's dense pixels traverse the tree beside pixels with lists, in one launch.
TEST(CameraLists, PixelsThatKeepTheTree) {
    ht::RenderSettings rs = small_settings(3, 23, 2);
    rs.camera_list_cap = 8;
    const ht::RenderStats st = expect_same_film(scene("builtin:ball?hairs=2000&segments=16"), rs, "cap 8");
    EXPECT_GT(st.candidate_tree_pixels, 0u);
    EXPECT_GT(st.candidate_entries, 0u);
}

// The eye among the strands: no projection bounds them, so there are no lists, and the film is
// the tree's.
TEST(CameraLists, NoListsWhenNothingCanBeProved) {
    ht::Scene s = scene("builtin:ball?hairs=300&segments=8");
    s.camera.eye = {0.0f, 0.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, -1.0f};
    const ht::RenderStats st = expect_same_film(s, small_settings(2, 3, 2), "eye inside");
    EXPECT_EQ(st.candidate_entries, 0u);
}

// On the command line: lists (the default) and tree write the same image; bad values exit 2.
TEST(CameraListsCli, ListsAndTreeWriteTheSameImage) {
    clitest::TempDir d("ht_camera_lists_");
    clitest::expect_same_image_and_usage_errors(d, clitest::kSmallStrandRender + " --spp 3", " --camera-rays tree", "",
                                                {" --camera-rays", " --camera-rays bvh", " --camera-rays 1"});
}
