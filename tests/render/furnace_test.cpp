// The white furnace for the whole path tracer: non-absorbing fibres with the energy-conserving
// model inside a uniform white environment, unlimited depth with Russian roulette.  Every pixel,
// hair or not, must converge to the environment's radiance (1): any energy gained or lost by
// the BCSDF, its sampling, MIS, ray spawning or self-intersection shows up here.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "io/image_io.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "cli_test_util.h"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace ht;

namespace {

// Non-absorbing chiang fibres (every sampling weight is 1 up to rounding), no lights, a
// uniform white environment.
Scene furnace_scene(const std::string& source) {
    Scene scene = load_scene(source);
    scene.lights.clear();
    scene.environment.color = {1, 1, 1};
    for (auto& m : scene.materials) {
        m.model = "chiang";
        m.set_sigma_a({0, 0, 0});
        m.beta_m = 0.3f;
        m.beta_n = 0.3f;
        m.alpha_deg = 2.0f;
    }
    ensure_camera_and_light(scene);
    return scene;
}

ClContext& shared_cl() {
    static ClContext cl;
    return cl;
}

// Per pixel, the mean over the channels.
std::vector<double> render_gray(const Scene& scene, const RenderSettings& rs, RenderStats* stats = nullptr) {
    Renderer r(shared_cl(), scene, rs);
    Film film;
    const RenderStats st = r.render(film);
    if (stats) *stats = st;
    std::vector<double> v(size_t(rs.width) * rs.height);
    for (size_t i = 0; i < v.size(); ++i) v[i] = (film.mean(i, 0) + film.mean(i, 1) + film.mean(i, 2)) / 3;
    return v;
}

// Pixels (nearly) fully covered by hair: with opaque fibres (sigma_a at its maximum, one bounce)
// in the white environment a covered pixel sees only the R lobe's reflection (~0.1), an empty
// one the environment (1); below 0.25 at least ~80 % of the pixel is hair.
std::vector<bool> covered_pixels(Scene scene, RenderSettings rs) {
    for (auto& m : scene.materials) m.sigma_a = {100, 100, 100};
    rs.max_depth = 1;
    rs.spp = 4;
    const std::vector<double> v = render_gray(scene, rs);
    std::vector<bool> covered(v.size());
    for (size_t i = 0; i < v.size(); ++i) covered[i] = v[i] < 0.25;
    return covered;
}

struct CoveredStats {
    size_t n = 0;
    double mean = 0, p01 = 0, p99 = 0;
};

CoveredStats covered_stats(const std::vector<double>& v, const std::vector<bool>& covered) {
    std::vector<double> c;
    for (size_t i = 0; i < v.size(); ++i)
        if (covered[i]) c.push_back(v[i]);
    CoveredStats s;
    s.n = c.size();
    if (c.empty()) return s;
    double sum = 0;
    for (double x : c) sum += x;
    s.mean = sum / double(c.size());
    std::sort(c.begin(), c.end());
    s.p01 = c[size_t(0.01 * double(c.size() - 1))];
    s.p99 = c[size_t(0.99 * double(c.size() - 1))];
    return s;
}

}  // namespace

TEST(RenderFurnace, NonAbsorbingHairInWhiteEnvironmentConvergesToOne) {
    const Scene scene = furnace_scene("builtin:strand?hairs=300&segments=16");
    ASSERT_TRUE(scene.lights.empty()) << "an environment-lit scene must not get an automatic light";
    RenderSettings rs;
    rs.width = 24;
    rs.height = 24;
    rs.spp = 64;
    rs.max_depth = 1000;  // no path of this thin lock gets near it
    const std::vector<bool> covered = covered_pixels(scene, rs);
    const std::vector<double> v = render_gray(scene, rs);
    double sum = 0, worst = 0;
    for (double x : v) {
        ASSERT_TRUE(std::isfinite(x));
        sum += x;
        worst = std::max(worst, std::fabs(x - 1));
    }
    const double mean = sum / double(v.size());
    RecordProperty("mean", std::to_string(mean));
    RecordProperty("worst_pixel_error", std::to_string(worst));
    EXPECT_GT(covered_stats(v, covered).n, v.size() / 16) << "the strand should cover a part of the image";
    // Every path's throughput stays 1 up to float rounding (weights f cos / pdf = 1 for
    // sigma_a = 0, roulette leaves full-energy paths alone, the uniform environment is not
    // sampled by next-event estimation), so every pixel is 1 to float precision.
    EXPECT_NEAR(mean, 1.0, 1e-4);
    EXPECT_LT(worst, 1e-3);
}

// The whole estimator where it is hardest: a dense lock (2,500 fibres) where light needs tens to
// hundreds of bounces to get out.  With sigma_a = 0 every path that escapes returns exactly the
// environment's 1 and every path cut by max_depth returns less, so the covered pixels measure
// what the path tracer loses or gains.  Russian roulette that lifted full-energy paths (survival
// capped at 0.95) put the 99th percentile at 2.3 and the mean at 0.93 (max depth 100) on a lock
// like this one; next-event estimation of the uniform environment added a spread of +-25 %.
TEST(RenderFurnace, DenseLockConservesEnergyPixelByPixel) {
    const Scene scene = furnace_scene("builtin:strand?hairs=2500&segments=40");
    RenderSettings rs;
    rs.width = 48;
    rs.height = 48;
    rs.spp = 4;
    rs.max_depth = 4000;  // deep enough that no path is cut (checked below)
    const std::vector<bool> covered = covered_pixels(scene, rs);
    RenderStats st;
    const std::vector<double> v = render_gray(scene, rs, &st);
    const CoveredStats s = covered_stats(v, covered);
    RecordProperty("covered_pixels", std::to_string(s.n));
    RecordProperty("mean", std::to_string(s.mean));
    RecordProperty("p01", std::to_string(s.p01));
    RecordProperty("p99", std::to_string(s.p99));
    RecordProperty("deepest_bounce", std::to_string(st.bounces.size()));
    ASSERT_GT(s.n, v.size() / 8) << "the lock should cover a good part of the image";
    EXPECT_EQ(st.cut_paths, 0u) << "max depth too low for the test's premise";
    // Float rounding of a weight of 1 over hundreds of bounces stays near 1e-5; the 1e-3 is the
    // issue's bar for the mean, 1.05 for single pixels of 4 samples.
    EXPECT_NEAR(s.mean, 1.0, 1e-3);
    EXPECT_LT(s.p99, 1.05);
    EXPECT_GT(s.p01, 0.95);
    EXPECT_GT(st.bounces.size(), 50u) << "the lock should need many bounces";
}

// A light that gives nothing (the furnace's energy stays the environment's) but that
// --light-guiding aims a share of every continuation at, from above and a little behind.
Light dark_guide_light() {
    Light l;
    l.type = LightType::Directional;
    l.direction = {0.3f, -0.9f, -0.3f};
    l.intensity = 0.0f;
    return l;
}

// The dense lock's furnace with continuations guided towards a light (kernels/integrator/
// light_guide.h): a guided path's weight is no longer 1 at each guided vertex (value over the
// mixture's density, 1 / (F r + 1 - F) here), so single pixels spread, but the mean must stay 1.
// Measured at 256 samples, seeds 1-3: means within 2e-3 of 1, 1st / 99th percentiles 0.82-0.84 /
// 1.18-1.19 (at 16 samples the means spread by ~1 % and the percentiles are 0.36 / 1.7: the noise
// that makes auto leave guiding off where an environment gives light, render/settings.h).  Weights
// of value / pdf_bsdf for guided directions (the guide's density left out of the mixture) put the
// mean percents off.
TEST(RenderFurnace, DenseLockWithGuidedContinuationsConservesEnergy) {
    Scene scene = furnace_scene("builtin:strand?hairs=2500&segments=40");
    scene.lights.push_back(dark_guide_light());
    RenderSettings rs;
    rs.width = 48;
    rs.height = 48;
    rs.spp = 256;
    rs.max_depth = 4000;
    rs.light_guiding = 0.3f;
    const std::vector<bool> covered = covered_pixels(scene, rs);
    RenderStats st;
    const CoveredStats s = covered_stats(render_gray(scene, rs, &st), covered);
    RecordProperty("mean", std::to_string(s.mean));
    RecordProperty("p01", std::to_string(s.p01));
    RecordProperty("p99", std::to_string(s.p99));
    ASSERT_GT(s.n, size_t(48 * 48 / 8));
    EXPECT_EQ(st.light_guiding, 0.3f) << "the render should guide";
    EXPECT_EQ(st.cut_paths, 0u);
    EXPECT_NEAR(s.mean, 1.0, 5e-3);
    EXPECT_LT(s.p99, 1.3);
    EXPECT_GT(s.p01, 0.7);
}

// A single fibre in an environment map of constant radiance 1: next-event estimation of the map
// and BCSDF sampling share every vertex by MIS.  At the last vertex the BCSDF half used to be
// dropped (no extension ray traced), so depth 1 gave ~0.21 instead of 1.  With --light-guiding
// (and a dark light to guide towards) the continuations' density is the guided mixture, which the
// map's next-event estimates must weigh themselves against instead of the BCSDF's alone.
void expect_single_fibre_in_white_map_is_one(float guiding) {
    clitest::TempDir dir("ht_furnace_");
    Film map;
    map.width = 16;
    map.height = 8;
    map.rgba.assign(4 * size_t(map.width) * map.height, 1.0f);
    const std::string map_path = dir / "white.exr";
    write_image(map_path, map, ImageMetadata{});
    // one straight fibre, thick enough to cover pixels: a convex capsule chain, so no ray that
    // leaves it can meet it again and every depth must give 1 (a wavy fibre shadows itself)
    Scene scene = furnace_scene("builtin:strand?hairs=1&segments=20&radius=3");
    for (size_t i = 0; i < scene.strands.points.size(); ++i)
        scene.strands.points[i] = {0.0f, 5.0f * float(i), 0.0f};
    scene.has_camera = false;
    ensure_camera_and_light(scene);
    scene.environment.color = {0, 0, 0};
    scene.environment.map_path = map_path;
    if (guiding > 0) scene.lights.push_back(dark_guide_light());
    RenderSettings rs;
    rs.width = 32;
    rs.height = 32;
    // guided weights spread more (the dense lock's guided furnace below): 256 samples keep the
    // same 2 % bound at about five standard errors (measured: 0.993-1.003 over seeds 2-4)
    rs.spp = guiding > 0 ? 256 : 64;
    rs.light_guiding = guiding;
    const std::vector<bool> covered = covered_pixels(scene, rs);
    for (int depth : {1, 2, 3}) {
        rs.max_depth = depth;
        const std::vector<double> v = render_gray(scene, rs);
        const CoveredStats s = covered_stats(v, covered);
        ::testing::Test::RecordProperty("mean_depth" + std::to_string(depth), std::to_string(s.mean));
        ASSERT_GT(s.n, 20u) << "the fibre should cover some pixels";
        // ~100 covered pixels x 64 samples of an MIS estimate whose per-sample spread is ~0.3:
        // the mean's standard error is ~4e-3; 2 % is five of them.
        EXPECT_NEAR(s.mean, 1.0, 0.02) << "depth " << depth << ", guiding " << guiding;
    }
}

TEST(RenderFurnace, SingleFibreWithEnvironmentMapIsOneAtEveryDepth) { expect_single_fibre_in_white_map_is_one(0.0f); }

TEST(RenderFurnace, SingleFibreWithEnvironmentMapAndGuidedContinuationsIsOne) {
    expect_single_fibre_in_white_map_is_one(0.3f);
}
