// Environment importance sampling, run in double on the host through the kernels' own header.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/environment.h"
#include "render/environment.h"

using namespace ht;

namespace {
// A small map with a bright sun, a sky gradient and a dark ground: strongly non-uniform.
EnvironmentTables test_map() {
    const int w = 64, h = 32;
    std::vector<float> rgb(3 * w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = y < h / 2 ? 0.5f + 0.5f * float(y) / h : 0.05f;
            if (std::abs(x - 40) <= 1 && std::abs(y - 8) <= 1) v = 500.0f;
            for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = v * (c == 2 ? 1.2f : 1.0f);
        }
    return build_environment_from_rgb(w, h, rgb, 1.0f, "test");
}
}  // namespace

TEST(Environment, PdfIntegratesToOneOverTheSphere) {
    EnvironmentTables t = test_map();
    // midpoint rule over (theta, phi), fine enough to resolve every texel
    const int nt = 512, np = 1024;
    double sum = 0;
    for (int i = 0; i < nt; ++i) {
        double th = (i + 0.5) / nt * HT_PI;
        for (int j = 0; j < np; ++j) {
            double ph = (j + 0.5) / np * 2 * HT_PI;
            real3 d = make_real3(std::sin(th) * std::sin(ph), std::cos(th), -std::sin(th) * std::cos(ph));
            sum += ht_env_pdf(&t.header, t.marginal.data(), t.conditional.data(), d) * std::sin(th);
        }
    }
    sum *= (HT_PI / nt) * (2 * HT_PI / np);
    EXPECT_NEAR(sum, 1.0, 2e-3);
}

TEST(Environment, SampledPdfMatchesEvaluatedPdfAndRadiance) {
    EnvironmentTables t = test_map();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0, 1);
    int bright = 0;
    for (int i = 0; i < 20000; ++i) {
        real3 wi, le;
        real pdf;
        if (!ht_env_sample(&t.header, t.texels.data(), t.marginal.data(), t.conditional.data(), U(rng), U(rng), &wi, &le, &pdf))
            continue;
        ASSERT_NEAR(length(wi), 1.0, 1e-9);
        real p2 = ht_env_pdf(&t.header, t.marginal.data(), t.conditional.data(), wi);
        ASSERT_NEAR(pdf, p2, 1e-6 * std::max(1.0, pdf));
        real3 l2 = ht_env_eval(&t.header, t.texels.data(), wi);
        ASSERT_NEAR(le.x, l2.x, 1e-6 * std::max(1.0, le.x));
        if (le.x > 100) ++bright;
    }
    // the 9 sun texels hold most of the power: importance sampling must find them often
    EXPECT_GT(bright, 20000 / 3);
}

TEST(Environment, ImportanceSampledEstimateMatchesUniformEstimate) {
    // E = integral of L over the sphere, by the sampler and by uniform directions
    EnvironmentTables t = test_map();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(0, 1);
    double is = 0, uni = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        real3 wi, le;
        real pdf;
        if (ht_env_sample(&t.header, t.texels.data(), t.marginal.data(), t.conditional.data(), U(rng), U(rng), &wi, &le, &pdf))
            is += le.x / pdf;
        double z = 1 - 2 * U(rng), r = std::sqrt(std::max(0.0, 1 - z * z)), ph = 2 * HT_PI * U(rng);
        uni += ht_env_eval(&t.header, t.texels.data(), make_real3(r * std::cos(ph), z, r * std::sin(ph))).x * 4 * HT_PI;
    }
    is /= n;
    uni /= n;
    EXPECT_NEAR(is / uni, 1.0, 0.03);  // the uniform estimator's own error dominates (~1.5% here)
}

TEST(Environment, UniformEnvironment) {
    Environment e;
    e.color = {0.5f, 0.5f, 0.5f};
    EnvironmentTables t = build_environment(e);
    real3 wi, le;
    real pdf;
    ASSERT_TRUE(ht_env_sample(&t.header, t.texels.data(), t.marginal.data(), t.conditional.data(), 0.3, 0.7, &wi, &le, &pdf));
    EXPECT_NEAR(pdf, 1 / (4 * HT_PI), 1e-12);
    EXPECT_NEAR(le.y, 0.5, 1e-7);
    EXPECT_EQ(build_environment(Environment{}).header.enabled, 0u);
}
