// --light-threshold T (kernels/integrator/roulette.h ht_light_roulette, kernels/stages/shade.cl):
// next-event estimates whose weight without the light is below T trace their shadow ray by Russian
// roulette.  The image converges to the same mean as without it, with far fewer shadow rays and
// little more error per sample; the command line turns it on, the library leaves it off.  That
// it stays a pure function of (seed, pixel, sample) -- chunks, one thread, two devices, render-farm
// parts and checkpoints giving the same bits -- is checked by FirstHitSplitsCli in
// first_hit_split_test.cpp, whose renders run with the command line's default threshold.
#include "render/renderer.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"
#include "render_test_util.h"

#include <string>

using namespace ht;
using rendertest::image_mean;
using rendertest::render;
using rendertest::rmse;
using rendertest::thick_strand;

namespace {

RenderSettings settings(float threshold, int spp, uint32_t seed, int depth = 3) {
    RenderSettings rs = rendertest::small_settings(spp, seed, depth);
    rs.light_threshold = threshold;
    return rs;
}

TEST(LightThreshold, TheLibrarysDefaultIsOff) { EXPECT_EQ(RenderSettings{}.light_threshold, 0.0f); }

TEST(LightThreshold, ConvergesToTheMeanWithoutItWithFewerShadowRays) {
    // Reference: no threshold, independent numbers, 1,024 spp.  Against it, other seeds at 256
    // spp: the command line's 0.1 and the largest threshold allowed, 1, which plays roulette with
    // nearly every estimate after the first vertex.  A survivor that were not divided by its
    // survival probability would lose most of the light of bounces 2 and 3 (the mean falls by
    // tens of percent); one divided twice would gain it.  Measured: means within 0.58 % (T = 0.1)
    // and 0.42 % (T = 1) of the reference (0.71 % without the threshold, seed 3); shadow rays
    // 0.42x and 0.37x of those without (the first vertex's, about a third here, are never
    // played for); RMSE at 32 spp 1.01x that without (T = 0.1, seed 5).
    const Scene scene = thick_strand();
    const Film ref = rendertest::independent_reference(scene, settings(0, 1024, 99));
    const double reference = image_mean(ref);
    ASSERT_GT(reference, 0.0);
    RenderStats off, on, high;
    render(scene, settings(0, 256, 3), &off);
    for (float t : {0.1f, 1.0f}) {
        const double mean = image_mean(render(scene, settings(t, 256, 3), t < 0.5f ? &on : &high));
        EXPECT_NEAR(mean / reference, 1.0, 0.02) << "T = " << t << ": " << mean << " against " << reference;
    }
    EXPECT_LT(double(on.shadow_rays), 0.55 * double(off.shadow_rays)) << on.shadow_rays << " / " << off.shadow_rays;
    EXPECT_LT(high.shadow_rays, on.shadow_rays);
    // the same camera samples, paths and extension rays at depth 3 (no roulette on continuations
    // before the fourth vertex): only shadow rays are played for
    EXPECT_EQ(on.extension_rays, off.extension_rays);
    const double e_off = rmse(render(scene, settings(0, 32, 5)), ref);
    const double e_on = rmse(render(scene, settings(0.1f, 32, 5)), ref);
    EXPECT_LT(e_on, 1.15 * e_off) << "T = 0.1: " << e_on << ", without: " << e_off;
}

TEST(LightThreshold, TheContinuationIntoTheLastVertexIsJudgedAtFourTimesItsThroughput) {
    // Depth 6: Russian roulette plays for the continuations from the fourth vertex on
    // (kernels/stages/shade.cl HT_RR_START_BOUNCE); with the threshold on, the one into the last
    // (sixth) vertex, whose next-event estimate the threshold's own roulette judges, is judged at
    // 4x its throughput (HT_RR_LAST_VERTEX_SCALE).  The paths of bounces 0-4 are the same with and
    // without the threshold (the roulettes draw numbers of their own), so with it more of them
    // reach the last vertex (cut there by the depth) and more extension rays are traced; unbiased
    // either way.  Measured at 64 spp: extension rays 1.02x, paths cut 1.39x (1.40x with no
    // roulette there at all: this strand's paths are bright); at 256 spp the mean 0.49 % above
    // the reference (tolerance as above).
    const Scene scene = thick_strand();
    const Film ref = rendertest::independent_reference(scene, settings(0, 1024, 99, 6));
    const double reference = image_mean(ref);
    ASSERT_GT(reference, 0.0);
    const double mean = image_mean(render(scene, settings(0.1f, 256, 3, 6)));
    EXPECT_NEAR(mean / reference, 1.0, 0.02) << mean << " against " << reference;
    RenderStats off, on64;
    render(scene, settings(0, 64, 3, 6), &off);
    render(scene, settings(0.1f, 64, 3, 6), &on64);
    EXPECT_GT(on64.extension_rays, off.extension_rays);
    EXPECT_GT(double(on64.cut_paths), 1.1 * double(off.cut_paths)) << on64.cut_paths << " / " << off.cut_paths;
}

TEST(LightThreshold, LeavesTheFirstVertexAlone) {
    // direct light is estimated at the first vertex only: with every later estimate's roulette
    // it is the same image to the bit, even at the largest threshold
    const Scene scene = thick_strand();
    EXPECT_EQ(render(scene, settings(1.0f, 4, 7, 1)).rgba, render(scene, settings(0, 4, 7, 1)).rgba);
    EXPECT_NE(render(scene, settings(1.0f, 4, 7, 2)).rgba, render(scene, settings(0, 4, 7, 2)).rgba);
}

}  // namespace

#ifdef HT_BINARY
TEST(LightThresholdCli, TheDefaultIsOnAndTheRangeIsChecked) {
    clitest::TempDir d("ht_light_threshold_");
    clitest::expect_option_default(d, clitest::kSmallStrandRender + " --spp 4", "--light-threshold 0.1",
                                   "--light-threshold off",
                                   {"--light-threshold 0", "--light-threshold 2", "--light-threshold -0.1",
                                    "--light-threshold none"});
}
#endif
