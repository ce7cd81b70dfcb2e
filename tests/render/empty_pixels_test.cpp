// RenderSettings::skip_empty_pixels: the pixels that see no geometry (render/pixel_footprint.h)
// are given the background without being traced, and the film must hold the very bits tracing
// them gives -- sums and sample counts, the --target-error half film too -- with a coloured
// background, splits and several bounces.  Where skipping cannot be exact it must not happen.
#include <gtest/gtest.h>

#include "render_test_util.h"

#include "cli_test_util.h"
#include "io/image_io.h"

using namespace rendertest;

// With the camera's lists the empty pixels are those with an empty list, without them those the
// images' 1-pixel margin leaves (render/pixel_footprint.h): both skip only pixels whose every bit
// the trace would give.
TEST(EmptyPixels, SkippedPixelsHoldTheTracedBitsAndAreNotTraced) {
    for (const bool lists : {true, false}) {
        SCOPED_TRACE(lists ? "empty pixels from the camera's lists" : "empty pixels from the images");
        const ht::Scene s = sparse_strand();
        ht::RenderSettings rs = small_settings(6, 11, 3);
        rs.camera_lists = lists ? ht::RenderSettings::ListChoice::Lists : ht::RenderSettings::ListChoice::Tree;
        rs.first_hit_splits = 2;
        rs.target_error = 0.01f;  // the even half film is filled too
        ht::RenderStats skipped, traced;
        ht::Film a, b;
        {
            ht::Renderer r(context(), s, rs);
            r.render(a);
            skipped = r.stats();
        }
        rs.skip_empty_pixels = false;
        {
            ht::Renderer r(context(), s, rs);
            r.render(b);
            traced = r.stats();
        }
        ASSERT_GT(skipped.empty_pixels, 0u) << "a sparse strand leaves pixels empty";
        EXPECT_EQ(skipped.background_samples, uint64_t(skipped.empty_pixels) * rs.spp);
        EXPECT_EQ(skipped.camera_rays + skipped.background_samples, traced.camera_rays);
        EXPECT_EQ(traced.background_samples, 0u);
        EXPECT_EQ(a.rgba, b.rgba);
        EXPECT_EQ(a.even, b.even);
        // and the background is in those pixels: the coloured environment, every sample
        size_t background_pixels = 0;
        for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
            if (std::fabs(a.mean(i, 0) - 0.3f) < 1e-6f && std::fabs(a.mean(i, 2) - 0.7f) < 1e-6f) ++background_pixels;
        EXPECT_GE(background_pixels, skipped.empty_pixels);
    }
}

// The camera turned away from the hair: every pixel empty, none traced, the same film.
TEST(EmptyPixels, NoPixelSeesGeometry) {
    ht::Scene s = sparse_strand();
    for (int i = 0; i < 3; ++i) s.camera.target[i] = 2 * s.camera.eye[i] - s.camera.target[i];
    ht::RenderSettings rs = small_settings(3, 5, 2);
    ht::RenderStats skipped, traced;
    const ht::Film a = render(s, rs, &skipped);
    rs.skip_empty_pixels = false;
    const ht::Film b = render(s, rs, &traced);
    EXPECT_EQ(skipped.empty_pixels, size_t(rs.width) * rs.height);
    EXPECT_EQ(skipped.camera_rays, 0u);
    EXPECT_EQ(traced.camera_rays, uint64_t(rs.width) * rs.height * rs.spp);
    EXPECT_EQ(a.rgba, b.rgba);
}

TEST(EmptyPixels, NotSkippedWhereTheyWouldDiffer) {
    ht::Scene s = sparse_strand();
    ht::RenderSettings rs = small_settings(1, 1, 1);
    rs.aovs = true;  // the AOVs of a miss are not filled in
    ht::RenderStats st;
    render(s, rs, &st);
    EXPECT_EQ(st.empty_pixels, 0u);
    EXPECT_EQ(st.background_samples, 0u);
    rs.aovs = false;
    render(s, rs, &st);
    EXPECT_GT(st.empty_pixels, 0u);
    // an environment map: the rays of one pixel see different texels
    clitest::TempDir dir("ht_empty_pixels_");
    ht::Film map;
    map.width = 16;
    map.height = 8;
    map.rgba.assign(4 * size_t(map.width) * map.height, 1.0f);
    map.rgba[0] = 5.0f;
    const std::string map_path = dir / "map.exr";
    ht::write_image(map_path, map, ht::ImageMetadata{});
    s.environment.color = {0, 0, 0};
    s.environment.map_path = map_path;
    render(s, rs, &st);
    EXPECT_EQ(st.empty_pixels, 0u);
    EXPECT_EQ(st.background_samples, 0u);
}

// On the command line: skip (the default) and trace write the same image, in chunks and on two
// devices too; bad values exit 2.
TEST(EmptyPixelsCli, SkipAndTraceWriteTheSameImage) {
    clitest::TempDir d("ht_empty_pixels_");
    const std::string render = clitest::kSmallStrandRender + " --background 0.2,0.3,0.4 --spp 3";
    clitest::expect_same_image_and_usage_errors(d, render, " --empty-pixels trace", "",
                                                {" --empty-pixels", " --empty-pixels none", " --empty-pixels 1"});
    ASSERT_EQ(clitest::run("POCL_DEVICES='pthread basic' " + render + " --chunk 2 --device 0,1 -o " + (d / "two.exr")), 0);
    EXPECT_EQ(clitest::image(d / "a.exr"), clitest::image(d / "two.exr"));
}
