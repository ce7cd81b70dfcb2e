// --first-hit-splits auto (render/split_choice.h): the pilot's estimators against processes whose
// variances are known, the cost from ray counts, and the choice against the model's own optimum.
#include "render/renderer.h"
#include "render/split_choice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace ht;

namespace {

// What pilot_accumulate (kernels/stages/split_pilot.cl) sums for one pilot pixel, from samples of
// a process with known parts: Y = F + (C_1 + C_2) / 2, F = mean_f + N(0, var_f) per channel with a
// first-vertex term shared by the continuations, m = N(0, var_m), C_j = m + N(0, var_c).  F and C
// are independent across samples (no stratification), so the truth is
//   split = 3 var_c, total = 3 (var_f + var_m + var_c / 2), stratification = 1.
struct Process {
    double mean_f = 0.5, var_f = 0.04, var_m = 0.01, var_c = 0.09;
};

std::vector<float> pilot_moments(const Process& p, size_t pixels, int samples_per_half, uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    std::vector<float> m(16 * pixels, 0.0f);
    for (size_t i = 0; i < pixels; ++i)
        for (int half = 0; half < 2; ++half)
            for (int s = 0; s < samples_per_half; ++s) {
                double y[3], f[3], c[2][3];
                for (int ch = 0; ch < 3; ++ch) {
                    f[ch] = p.mean_f + std::sqrt(p.var_f) * normal(rng);
                    const double mid = std::sqrt(p.var_m) * normal(rng);
                    for (int j = 0; j < 2; ++j) c[j][ch] = (mid + std::sqrt(p.var_c) * normal(rng)) / 2;
                    y[ch] = f[ch] + c[0][ch] + c[1][ch];
                }
                float* px = &m[16 * i];
                double yy = 0, ff = 0, spread = 0;
                for (int ch = 0; ch < 3; ++ch) {
                    px[ch] += float(y[ch]);
                    px[4 * (1 + half) + ch] += float(f[ch]);
                    yy += y[ch] * y[ch];
                    ff += f[ch] * f[ch];
                    const double mean = (c[0][ch] + c[1][ch]) / 2;
                    for (int j = 0; j < 2; ++j) spread += (c[j][ch] - mean) * (c[j][ch] - mean);
                }
                px[3] += float(yy);
                px[7] += float(ff);
                px[11] += float(4.0 / 1.0 * spread);  // N^2 / (N - 1), N = 2
                px[15] += 1.0f;
            }
    return m;
}

}  // namespace

TEST(SplitChoice, TheVariancesOfAProcessWithKnownParts) {
    // 4,096 pixels x 16 samples, as the pilot of a 256 x 256 image.  Tolerances: 4 % on the
    // variances (their relative standard errors are below 1 % here), 8 % on the stratification
    // (a ratio of a variance and a squared difference of means, each with 4,096 x 3 terms).
    const Process p;
    const SplitVariance v = split_variance(pilot_moments(p, 4096, kPilotSamples, 7));
    EXPECT_NEAR(v.split / (3 * p.var_c), 1.0, 0.04);
    EXPECT_NEAR(v.total / (3 * (p.var_f + p.var_m + p.var_c / 2)), 1.0, 0.04);
    EXPECT_NEAR(v.stratification, 1.0, 0.08);
    EXPECT_NEAR(v.fixed() / (3 * (p.var_f + p.var_m)), 1.0, 0.1);
}

TEST(SplitChoice, APixelThatWentNonFiniteIsLeftOut) {
    const Process p;
    std::vector<float> m = pilot_moments(p, 256, kPilotSamples, 3);
    const SplitVariance clean = split_variance(m);
    m.resize(m.size() + 16, 0.0f);
    m[m.size() - 13] = std::numeric_limits<float>::infinity();  // a pixel's sum of |Y|^2
    m.back() = float(2 * kPilotSamples);
    const SplitVariance v = split_variance(m);
    EXPECT_EQ(v.total, clean.total);
    EXPECT_EQ(v.split, clean.split);
    EXPECT_EQ(best_splits(split_variance(std::vector<float>(16, 0.0f)), SplitCost{1, 1}), kMinAutoSplits);
}

TEST(SplitChoice, TheChoiceIsTheModelsOptimum) {
    // (c0 + N c1)(V_fixed + V_split / N) is least at N* = sqrt((c0 / c1)(V_split / V_fixed)).
    SplitVariance v;
    v.stratification = 1;
    v.split = 16;
    v.total = 1 + v.split / kPilotSplits;  // V_fixed = 1
    EXPECT_EQ(best_splits(v, SplitCost{1, 1}), 4);
    EXPECT_EQ(best_splits(v, SplitCost{1, 0.25}), kMaxAutoSplits);  // N* = 8
    EXPECT_EQ(best_splits(v, SplitCost{1, 4}), 2);                  // N* = 2
    v.stratification = 4;                                          // V_fixed = 1 / 4: N* = 8
    EXPECT_EQ(best_splits(v, SplitCost{1, 1}), kMaxAutoSplits);
    v.stratification = 1e9;  // taken as kMaxStratification
    EXPECT_DOUBLE_EQ(v.fixed(), 1.0 / kMaxStratification);
    // nothing varies between continuations, nothing to continue, or nonsense: the smallest N
    v.stratification = 1;
    v.split = 0;
    EXPECT_EQ(best_splits(v, SplitCost{1, 1}), kMinAutoSplits);
    v.split = 16;
    EXPECT_EQ(best_splits(v, SplitCost{1, 0}), kMinAutoSplits);
    v.total = std::nan("");
    EXPECT_EQ(best_splits(v, SplitCost{1, 1}), kMinAutoSplits);
}

TEST(SplitChoice, CostFromRayCounts) {
    // 1000 camera rays, 400 of them on hair (800 continuations started with N = 2), 300 shadow
    // rays at the first vertex; later bounces 800 + 200 rays and 100 shadow rays.
    RenderStats s;
    s.bounces = {{1000, 300, 0, 0}, {800, 80, 0, 0}, {200, 20, 0, 0}};
    const SplitCost c = split_cost(s, 2);
    EXPECT_DOUBLE_EQ(c.c0, (kMissCost * 600 + 400 + kShadowCost * 300) / 1000);
    EXPECT_DOUBLE_EQ(c.c1, (kLaterHitCost * 1000 + kShadowCost * 100) / 2000);
    EXPECT_EQ(split_cost(RenderStats{}, 2).c1, 0.0);
}

TEST(SplitChoice, PilotPixelsAndSeeds) {
    for (auto [w, h] : {std::pair{1, 1}, {5, 3}, {128, 128}, {256, 256}, {512, 512}, {1920, 1080}}) {
        const std::vector<uint32_t> px = pilot_pixels(w, h);
        ASSERT_FALSE(px.empty());
        EXPECT_LE(px.size(), std::max<size_t>(size_t(w) * h / 16, 1) + size_t(w + h)) << w << "x" << h;
        EXPECT_LE(px.size(), size_t(kPilotPixels) + size_t(w + h) / 4) << w << "x" << h;
        for (size_t i = 0; i < px.size(); ++i) {
            EXPECT_LT(px[i], uint32_t(w * h));
            if (i) {
                EXPECT_GT(px[i], px[i - 1]);
            }
        }
    }
    EXPECT_EQ(pilot_pixels(128, 128).size(), 1024u);  // every fourth pixel of every fourth row
    EXPECT_EQ(pilot_pixels(256, 256).size(), 1024u);  // from here on about kPilotPixels
    EXPECT_EQ(pilot_stride(512, 512), 16);
    for (uint32_t seed : {0u, 1u, 12345u, 0x7FFFFFFFu}) {
        EXPECT_GE(pilot_seed(seed, 0), 0x80000000u);  // no --seed reaches it
        EXPECT_GE(pilot_seed(seed, 1), 0x80000000u);
        EXPECT_NE(pilot_seed(seed, 0), pilot_seed(seed, 1));
    }
}
