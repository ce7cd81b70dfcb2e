// The sparkle count of render --reference and converge (host/render/error_metrics.h): a pixel
// counts when its error exceeds 10x the reference's 3x3 local standard deviation (with a floor of
// 1 % of the reference's mean). Synthetic images whose local deviations are known exactly.
#include <gtest/gtest.h>

#include "render/error_metrics.h"

#include <cmath>
#include <limits>
#include <vector>

namespace {

// A w x h reference alternating 1 - a and 1 + a in a checkerboard, every channel alike: the
// 3x3 standard deviation of an interior pixel is a * sqrt(1 - (1/9)^2) (five of one value, four of
// the other: mean offset a/9).
std::vector<float> checker(int w, int h, float a) {
    std::vector<float> img(3 * size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img[3 * (size_t(y) * w + x) + c] = ((x + y) % 2 ? 1.0f - a : 1.0f + a);
    return img;
}

}  // namespace

TEST(ErrorMetrics, LocalNoiseIsTheNeighbourhoodDeviation) {
    const float a = 0.1f;
    const auto ref = checker(8, 8, a);
    const auto noise = ht::local_noise(ref, 8, 8);
    const double interior = a * std::sqrt(1.0 - 1.0 / 81.0);
    EXPECT_NEAR(noise[3 * (3 * 8 + 3)], interior, 1e-6);
    // a corner sees 2 x 2 pixels, two of each value: deviation a exactly
    EXPECT_NEAR(noise[0], a, 1e-6);
    // a flat reference has no deviation: the floor, 1 % of its mean
    const std::vector<float> flat(3 * 16, 2.0f);
    for (float n : ht::local_noise(flat, 4, 4)) EXPECT_FLOAT_EQ(n, 0.02f);
}

TEST(ErrorMetrics, CountsPixelsBeyondTenLocalDeviations) {
    const int w = 8, h = 8;
    const float a = 0.1f;
    const auto ref = checker(w, h, a);
    const double sigma = a * std::sqrt(1.0 - 1.0 / 81.0);
    auto img = ref;
    img[3 * (2 * w + 2) + 1] += float(10.5 * sigma);  // green of (2,2): a sparkle
    img[3 * (5 * w + 5) + 0] -= float(10.5 * sigma);  // below the reference too
    img[3 * (2 * w + 5) + 2] += float(9.5 * sigma);   // within 10 deviations: not one
    const auto m = ht::compare_images(img, ref, w, h);
    EXPECT_EQ(m.sparkles, 2u);
    EXPECT_DOUBLE_EQ(m.sparkle_share, 2.0 / 64.0);
    // non-finite values count their pixel as a sparkle
    img[3 * (6 * w + 1)] = std::numeric_limits<float>::quiet_NaN();
    const auto n = ht::compare_images(img, ref, w, h);
    EXPECT_EQ(n.sparkles, 3u);
    EXPECT_EQ(n.nonfinite, 1u);
    // the same image compared with itself has none
    EXPECT_EQ(ht::compare_images(ref, ref, w, h).sparkles, 0u);
}

TEST(ErrorMetrics, RefusesSizesThatDoNotMatch) {
    const std::vector<float> ref(3 * 12, 1.0f);
    EXPECT_THROW(ht::compare_images(ref, ref, 4, 4), std::invalid_argument);
}

TEST(ErrorMetrics, ChannelMeansLeaveOutNonFiniteValues) {
    // pixel 0 (1, 2, 4) against (2, 2, 2); pixel 1 (3, NaN, 0) against (2, 2, 2): red and blue
    // average both pixels, green only the finite one, on both sides.
    const std::vector<float> img{1, 2, 4, 3, std::numeric_limits<float>::quiet_NaN(), 0};
    const std::vector<float> ref{2, 2, 2, 2, 2, 2};
    const auto m = ht::compare_images(img, ref, 2, 1);
    EXPECT_DOUBLE_EQ(m.channel_mean[0], 2.0);
    EXPECT_DOUBLE_EQ(m.channel_mean[1], 2.0);
    EXPECT_DOUBLE_EQ(m.channel_mean[2], 2.0);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(m.ref_channel_mean[c], 2.0);
    EXPECT_DOUBLE_EQ(m.mean, 10.0 / 5.0);
}
