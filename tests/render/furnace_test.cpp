// The white furnace for the whole path tracer: non-absorbing fibres with the energy-conserving
// model inside a uniform white environment, unlimited depth with Russian roulette.  Every pixel,
// hair or not, must converge to the environment's radiance (1): any energy gained or lost by
// the BCSDF, its sampling, MIS, ray spawning or self-intersection shows up here.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <cmath>

using namespace ht;

TEST(RenderFurnace, NonAbsorbingHairInWhiteEnvironmentConvergesToOne) {
    Scene scene = load_scene("builtin:strand?hairs=300&segments=16");
    scene.lights.clear();
    scene.environment.color = {1, 1, 1};
    for (auto& m : scene.materials) {
        m.model = "chiang";
        m.has_sigma_a = true;
        m.has_melanin = m.has_color = false;
        m.sigma_a = {0, 0, 0};
        m.beta_m = 0.3f;
        m.beta_n = 0.3f;
        m.alpha_deg = 0.0f;
    }
    ensure_camera_and_light(scene);
    ASSERT_TRUE(scene.lights.empty()) << "an environment-lit scene must not get an automatic light";
    RenderSettings rs;
    rs.width = 24;
    rs.height = 24;
    rs.spp = 64;
    rs.max_depth = 1000;  // Russian roulette ends the paths
    static ClContext cl;
    Renderer r(cl, scene, rs);
    Film film;
    r.render(film);
    double sum = 0, worst = 0;
    size_t n = size_t(rs.width) * rs.height, hair = 0;
    for (size_t i = 0; i < n; ++i) {
        double v = (film.mean(i, 0) + film.mean(i, 1) + film.mean(i, 2)) / 3;
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
        if (v != 1.0) ++hair;
        worst = std::max(worst, std::fabs(v - 1));
    }
    double mean = sum / double(n);
    RecordProperty("mean", std::to_string(mean));
    RecordProperty("worst_pixel_error", std::to_string(worst));
    EXPECT_GT(hair, n / 4) << "the strand should cover a good part of the image";
    // Per hair pixel the estimate is a mean of 64 paths whose throughput stays near 1 (weights
    // f cos / pdf = 1 for sigma_a = 0); Russian roulette adds variance (q >= ~0.95 at these
    // throughputs).  Measured pixel spread is a few percent; the image mean averages ~576 pixels.
    EXPECT_NEAR(mean, 1.0, 0.01);
    EXPECT_LT(worst, 0.25);
}
