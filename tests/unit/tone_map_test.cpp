// The tone mapping of 8-bit outputs (host/io/image_io.h): the filmic curve is monotone and
// bounded, the filmic mapping keeps the hue of saturated colours, and no input gives NaN.
#include <gtest/gtest.h>

#include "io/image_io.h"

#include <algorithm>
#include <cmath>
#include <limits>

using namespace ht;

namespace {
// HSV hue in degrees; the colour must not be grey.
double hue_deg(const float c[3]) {
    const double r = c[0], g = c[1], b = c[2];
    const double hi = std::max({r, g, b}), lo = std::min({r, g, b}), d = hi - lo;
    double h = hi == r ? std::fmod((g - b) / d, 6.0) : hi == g ? (b - r) / d + 2.0 : (r - g) / d + 4.0;
    h *= 60.0;
    return h < 0 ? h + 360.0 : h;
}

double luminance(const float c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
}  // namespace

TEST(ToneMap, CurveIsMonotoneContinuousAndBelowOne) {
    float previous = 0.0f;
    for (float x = 0.0f; x < 50.0f; x += 0.001f) {
        const float y = filmic_curve(x);
        ASSERT_GE(y, previous) << x;
        ASSERT_LE(y, 1.0f) << x;
        ASSERT_LE(y - previous, 0.0011f) << x;  // slope <= 1: no jump at the knee
        previous = y;
    }
    EXPECT_FLOAT_EQ(filmic_curve(0.3f), 0.3f);  // identity below the knee
    EXPECT_NEAR(filmic_curve(0.8f), 0.757f, 1e-3f);
    EXPECT_NEAR(filmic_curve(2.0f), 0.988f, 1e-3f);
}

TEST(ToneMap, KeepsTheHueOfSaturatedColours) {
    // A golden blond (hue 36 deg) and a saturated red, from dark to 100x over white: the hue stays
    // within 0.5 deg (float rounding only), luminance follows the curve within 1e-4, and the
    // old per-channel clipping turns the same blond into yellow-white (hue moves by > 10 deg).
    for (const auto& base : {std::array<float, 3>{1.0f, 0.7f, 0.3f}, std::array<float, 3>{0.9f, 0.1f, 0.05f}}) {
        const double want = hue_deg(base.data());
        for (float k = 0.01f; k < 100.0f; k *= 1.25f) {
            const float in[3] = {base[0] * k, base[1] * k, base[2] * k};
            float out[3];
            tone_map_pixel(in, out, ToneMap::Filmic);
            for (float v : out) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << k;
            if (std::max({out[0], out[1], out[2]}) - std::min({out[0], out[1], out[2]}) > 1e-3f) {
                EXPECT_NEAR(hue_deg(out), want, 0.5) << "k = " << k;
            }
            EXPECT_NEAR(luminance(out), filmic_curve(float(luminance(in))), 1e-4) << "k = " << k;
        }
    }
    const float bright_blond[3] = {2.0f, 1.4f, 0.6f};
    float clipped[3];
    tone_map_pixel(bright_blond, clipped, ToneMap::Clip);
    EXPECT_GT(std::abs(hue_deg(clipped) - hue_deg(bright_blond)), 10.0);
}

TEST(ToneMap, DesaturatesOnlyWhereTheColourLeavesTheGamut) {
    // Below the gamut edge the colour is just scaled: channel ratios equal the input's.
    const float in[3] = {0.5f, 0.35f, 0.15f};
    float out[3];
    tone_map_pixel(in, out, ToneMap::Filmic);
    EXPECT_NEAR(out[1] / out[0], 0.7f, 1e-5f);
    EXPECT_NEAR(out[2] / out[0], 0.3f, 1e-5f);
}

TEST(ToneMap, NoNaNForZeroHugeInfiniteOrNaNInput) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float cases[][3] = {{0, 0, 0},       {-1, -2, -3},     {nan, nan, nan}, {nan, 0.5f, 0.2f},
                              {inf, inf, inf}, {inf, 0, 0},      {3e38f, 3e38f, 3e38f},
                              {1e-40f, 0, 0},  {-inf, 0.3f, 0.1f}};
    for (ToneMap mode : {ToneMap::Filmic, ToneMap::Clip})
        for (const auto& c : cases) {
            float out[3];
            tone_map_pixel(c, out, mode);
            for (float v : out) EXPECT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << c[0] << "," << c[1] << "," << c[2];
        }
    float out[3];
    const float white_hot[3] = {inf, inf, inf};
    tone_map_pixel(white_hot, out, ToneMap::Filmic);
    for (float v : out) EXPECT_FLOAT_EQ(v, 1.0f);
    EXPECT_EQ(filmic_curve(nan), 0.0f);
    EXPECT_EQ(filmic_curve(inf), 1.0f);
}

TEST(ToneMap, NamesRoundTrip) {
    for (const std::string& n : tone_map_names()) EXPECT_EQ(tone_map_name(tone_map_from_name(n)), n);
}
