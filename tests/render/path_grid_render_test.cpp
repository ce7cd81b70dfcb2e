// RenderSettings::path_rays: path rays walking the uniform grid (render/path_grid.h,
// kernels/geometry/path_grid.h) find the tree's hits, so the film is the same bits -- sparse and
// dense hair, splits, several bounces, directional and point lights; a scene with triangles and a
// render of depth 1 keep the tree; auto takes the grid once the path rays reach
// kPathGridRaysPerSegment per segment.
#include <gtest/gtest.h>

#include "render_test_util.h"

#include "cli_test_util.h"

#include <cmath>
#include <filesystem>

namespace {

using namespace rendertest;
using PathRays = ht::RenderSettings::PathRays;

ht::Scene scene(const std::string& name) {
    ht::Scene s = ht::load_scene(name);
    ht::ensure_camera_and_light(s);
    return s;
}

// the grid against the tree: the same film; returns the grid's statistics
ht::RenderStats expect_same_film(const ht::Scene& s, ht::RenderSettings rs, const char* what) {
    ht::RenderStats grid, tree;
    rs.path_rays = PathRays::Grid;
    const ht::Film a = render(s, rs, &grid);
    rs.path_rays = PathRays::Tree;
    const ht::Film b = render(s, rs, &tree);
    EXPECT_EQ(a.rgba, b.rgba) << what;
    EXPECT_EQ(tree.path_grid_entries, 0u) << what;
    EXPECT_EQ(grid.extension_rays, tree.extension_rays) << what;
    EXPECT_EQ(grid.shadow_rays, tree.shadow_rays) << what;
    return grid;
}

}  // namespace

TEST(PathGridRender, SameFilmAsTheTree) {
    ht::RenderSettings rs = small_settings(4, 31, 4);
    rs.first_hit_splits = 2;
    const ht::RenderStats sparse = expect_same_film(scene("builtin:strand?hairs=60&segments=12"), rs, "sparse strand, splits, depth 4");
    EXPECT_GT(sparse.path_grid_entries, 0u);
    EXPECT_GT(sparse.path_grid_cells, 0u);
    const ht::RenderStats dense = expect_same_film(scene("builtin:ball?hairs=1500&segments=16"), small_settings(3, 5, 6), "dense ball, depth 6");
    EXPECT_GT(dense.path_grid_entries, 0u);
    EXPECT_GT(dense.extension_rays, 0u);
}

TEST(PathGridRender, TrianglesAndDepthOneKeepTheTree) {
    ht::RenderSettings rs = small_settings(2, 9, 3);
    rs.path_rays = PathRays::Grid;
    const ht::Scene floor = scene(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_floor.gltf");
    EXPECT_FALSE(ht::prepare_scene(floor, rs).features[ht::Feature::PATH_GRID]);
    const ht::Scene s = scene("builtin:strand?hairs=60&segments=12");
    EXPECT_TRUE(ht::prepare_scene(s, rs).features[ht::Feature::PATH_GRID]);
    rs.max_depth = 1;
    EXPECT_FALSE(ht::prepare_scene(s, rs).features[ht::Feature::PATH_GRID]);
}

// auto: the grid once spp x the image's pixels x (depth - 1) reaches kPathGridRaysPerSegment per
// segment; grid and tree as asked whatever the count.
TEST(PathGridRender, AutoTakesTheGridWhereEnoughRaysUseIt) {
    const ht::Scene s = scene("builtin:ball?hairs=300&segments=8");
    ht::RenderSettings rs = small_settings(1, 7, 3);
    const double segments = double(ht::prepare_scene(s, rs).geometry.segments.size());
    const int spp_grid = int(std::ceil(ht::kPathGridRaysPerSegment * segments / (double(rs.width) * rs.height * 2)));
    ASSERT_GT(spp_grid, 1);
    const auto grid_at = [&](int spp, PathRays choice) {
        ht::RenderSettings r = rs;
        r.spp = spp;
        r.path_rays = choice;
        const ht::PreparedScene p = ht::prepare_scene(s, r);
        EXPECT_EQ(p.features[ht::Feature::PATH_GRID], !p.path_grid.empty());
        return p.features[ht::Feature::PATH_GRID];
    };
    EXPECT_FALSE(grid_at(spp_grid - 1, PathRays::Auto));
    EXPECT_TRUE(grid_at(spp_grid, PathRays::Auto));
    EXPECT_TRUE(grid_at(1, PathRays::Grid));
    EXPECT_FALSE(grid_at(4 * spp_grid, PathRays::Tree));
}

// auto's look at the grid it made: two copies of a lock in one box, far apart, leave most cells
// empty and the occupied ones too coarse: the tree; near each other, the grid; grid as asked.
TEST(PathGridRender, AutoKeepsTheTreeForClumpsFarApart) {
    const ht::Scene one = scene("builtin:strand?hairs=200&segments=12");
    const auto two_apart = [&](float dx) {
        ht::Scene s = one;
        ht::Strands& h = s.strands;
        const size_t points = h.points.size(), strands = h.strand_count();
        for (size_t i = 0; i < points; ++i) {
            h.points.push_back({h.points[i][0] + dx, h.points[i][1], h.points[i][2]});
            h.radius.push_back(h.radius[i]);
        }
        for (size_t k = 0; k < strands; ++k) {
            h.first_point.push_back(uint32_t(points) + h.first_point[k + 1]);
            h.material.push_back(h.material[k]);
        }
        return s;
    };
    ht::RenderSettings rs = small_settings(64, 3, 5);
    const auto occupied_share = [](const ht::PathGrid& g) { return double(g.occupied_cells()) / double(g.cells()); };
    const ht::Bounds box = ht::scene_bounds(one);
    const float width = box.hi[0] - box.lo[0];
    const ht::Scene near = two_apart(2.0f * width), far = two_apart(200.0f * width);
    const ht::PreparedScene a = ht::prepare_scene(near, rs);
    ASSERT_TRUE(a.features[ht::Feature::PATH_GRID]);
    EXPECT_GE(occupied_share(a.path_grid), ht::kPathGridMinOccupiedShare);
    const ht::PreparedScene b = ht::prepare_scene(far, rs);
    EXPECT_FALSE(b.features[ht::Feature::PATH_GRID]);
    EXPECT_TRUE(b.path_grid.empty());
    rs.path_rays = PathRays::Grid;
    const ht::PreparedScene c = ht::prepare_scene(far, rs);
    ASSERT_TRUE(c.features[ht::Feature::PATH_GRID]);
    EXPECT_LT(occupied_share(c.path_grid), ht::kPathGridMinOccupiedShare);
}

// On the command line: grid, tree and auto write the same image; bad values exit 2.
TEST(PathGridCli, GridAndTreeWriteTheSameImage) {
    clitest::TempDir d("ht_path_grid_");
    clitest::expect_same_image_and_usage_errors(d, clitest::kSmallStrandRender + " --spp 3", " --path-rays tree",
                                                " --path-rays grid",
                                                {" --path-rays", " --path-rays bvh", " --path-rays 1"});
    clitest::expect_same_image_and_usage_errors(d, clitest::kSmallStrandRender + " --spp 3", " --path-rays auto", "", {});
}

// A device that allocates less than one of the grid's arrays (HAIRTRACE_MAX_ALLOC lowers PoCL's
// limit): --path-rays grid exits 3 naming the sizes and writes nothing; auto, which chose the grid
// by the rays, takes the tree instead and says so (the same image); a scene whose geometry is paged
// while the grid fits walks the grid over the pages (the same image again).  The ball of 32,000
// segments: its largest grid array is 368 KB, its point array 544 KB.
TEST(PathGridCli, GridBeyondTheDevicesAllocationIsRefusedOrLeftOut) {
    clitest::TempDir d("ht_path_grid_");
    using clitest::image;
    using clitest::run;
    using clitest::slurp;
    const std::string render = std::string(HT_BINARY) + " render 'builtin:ball?hairs=2000&segments=16' --width 48 --height 48 --max-depth 4 --seed 3";
    // 40 spp: 48 x 48 x 40 x 3 path rays reach 8 per segment, so auto chooses the grid
    ASSERT_EQ(run(render + " --spp 40 --path-rays tree --quiet -o " + (d / "tree.exr")), 0);
    EXPECT_EQ(run("HAIRTRACE_MAX_ALLOC=128K " + render + " --spp 40 --path-rays grid -o " + (d / "x.exr") + " 2>" + (d / "err.txt")), 3);
    const std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("path rays' grid needs 367888 bytes in one buffer"), std::string::npos) << err;
    EXPECT_NE(err.find("--path-rays tree"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(d / "x.exr"));
    ASSERT_EQ(run("HAIRTRACE_MAX_ALLOC=128K " + render + " --spp 40 -o " + (d / "auto.exr") + " 2>" + (d / "log.txt")), 0);
    EXPECT_NE(slurp(d / "log.txt").find("path rays' grid left out"), std::string::npos) << slurp(d / "log.txt");
    EXPECT_EQ(image(d / "tree.exr"), image(d / "auto.exr"));
    // 512 KiB: the points take two pages, the grid's arrays one buffer each
    ASSERT_EQ(run(render + " --spp 3 --path-rays tree --quiet -o " + (d / "flat.exr")), 0);
    ASSERT_EQ(run("HAIRTRACE_MAX_ALLOC=512K " + render + " --spp 3 --path-rays grid --verbose -o " + (d / "paged.exr") + " 2>" +
                  (d / "paged.txt")), 0);
    const std::string log = slurp(d / "paged.txt");
    EXPECT_NE(log.find("geometry: 2 buffers per array"), std::string::npos) << log;
    EXPECT_NE(log.find("path rays from a uniform grid:"), std::string::npos) << log;
    EXPECT_EQ(image(d / "flat.exr"), image(d / "paged.exr"));
}
