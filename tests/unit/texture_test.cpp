// Host (double) checks of the portable texture sampling (kernels/surface/texture.h) against
// texel values computed by hand: sRGB decode (formula and table), bilinear weights at and
// between texel centres, each wrap mode on both sides of the [0, 1] range.
#include <gtest/gtest.h>

#include "kernels/surface/texture.h"

#include <cmath>
#include <limits>
#include <vector>

namespace {

uint32_t rgb8(uint32_t r, uint32_t g, uint32_t b) { return r | g << 8 | b << 16; }

// The sRGB decode written out independently of the header (IEC 61966-2-1).
double srgb_formula(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// A texel buffer as the renderer builds it: the decode table, then the given texels.
std::vector<uint32_t> texel_buffer(const std::vector<uint32_t>& texels) {
    std::vector<uint32_t> b(HT_SRGB_TABLE_SIZE);
    ht_srgb_table(b.data());
    b.insert(b.end(), texels.begin(), texels.end());
    return b;
}

// The table holds floats: decoded values match the formula to float rounding.
constexpr double kFloat = 1e-7;

HtTexture header(uint32_t offset, uint32_t w, uint32_t h, uint32_t wrap_s, uint32_t wrap_t) {
    HtTexture t{};
    t.offset = offset;
    t.width = w;
    t.height = h;
    t.wrap_s = wrap_s;
    t.wrap_t = wrap_t;
    return t;
}

TEST(Texture, SrgbDecodeMatchesTheFormula) {
    for (int i = 0; i <= 255; ++i) {
        const double c = i / 255.0;
        EXPECT_NEAR(ht_srgb_to_linear(c), srgb_formula(c), 1e-12) << i;
    }
    // Anchors: black, white, the linear segment (10/255 < 0.04045), mid grey 128 -> 0.21586.
    EXPECT_EQ(ht_srgb_to_linear(0.0), 0.0);
    EXPECT_NEAR(ht_srgb_to_linear(1.0), 1.0, 1e-12);
    EXPECT_NEAR(ht_srgb_to_linear(10 / 255.0), 10 / 255.0 / 12.92, 1e-15);
    EXPECT_NEAR(ht_srgb_to_linear(128 / 255.0), 0.2158605, 1e-6);
    // The two pieces meet: continuous at the threshold within the standard's rounding (~1e-7).
    EXPECT_NEAR(0.04045 / 12.92, std::pow((0.04045 + 0.055) / 1.055, 2.4), 1e-7);
}

TEST(Texture, DecodeTableIsTheFormulaInFloat) {
    const std::vector<uint32_t> table = texel_buffer({});
    for (uint32_t i = 0; i < HT_SRGB_TABLE_SIZE; ++i)
        EXPECT_EQ(ht_as_float(table[i]), float(srgb_formula(i / 255.0))) << i;
}

TEST(Texture, TexelChannelsDecodeIndependently) {
    const std::vector<uint32_t> table = texel_buffer({});
    const real3 c = ht_texel_linear(table.data(), rgb8(255, 128, 0));
    EXPECT_EQ(c.x, 1.0);
    EXPECT_NEAR(c.y, srgb_formula(128 / 255.0), kFloat);
    EXPECT_EQ(c.z, 0.0);
    // The alpha byte (never stored by the loader) would not leak into any channel.
    const real3 d = ht_texel_linear(table.data(), rgb8(0, 0, 0) | 0xff000000u);
    EXPECT_EQ(d.x + d.y + d.z, 0.0);
}

// A 2 x 2 texture with a single white texel at (1, 0); everything else black.  In linear light
// a sample is then exactly the bilinear weight of that texel, easy to compute by hand.
class Bilinear : public ::testing::Test {
protected:
    // the texture starts 3 texels after the table, to check the header's offset is honoured
    std::vector<uint32_t> texels = texel_buffer({rgb8(9, 9, 9), rgb8(9, 9, 9), rgb8(9, 9, 9),
                                                 rgb8(0, 0, 0), rgb8(255, 255, 255), rgb8(0, 0, 0),
                                                 rgb8(0, 0, 0)});
    double at(uint32_t ws, uint32_t wt, double u, double v) const {
        return ht_texture_sample(header(HT_SRGB_TABLE_SIZE + 3, 2, 2, ws, wt), texels.data(), u, v).x;
    }
};

TEST_F(Bilinear, TexelCentresGiveTheTexel) {
    // Centres of a 2 x 2 texture: u, v in {0.25, 0.75}; row 0 is v < 0.5 (the image's top).
    for (uint32_t mode : {HT_WRAP_REPEAT, HT_WRAP_CLAMP, HT_WRAP_MIRROR}) {
        EXPECT_NEAR(at(mode, mode, 0.75, 0.25), 1.0, 1e-12) << mode;
        EXPECT_NEAR(at(mode, mode, 0.25, 0.25), 0.0, 1e-12) << mode;
        EXPECT_NEAR(at(mode, mode, 0.25, 0.75), 0.0, 1e-12) << mode;
        EXPECT_NEAR(at(mode, mode, 0.75, 0.75), 0.0, 1e-12) << mode;
    }
}

TEST_F(Bilinear, BetweenCentresTheWeightsAreLinear) {
    // Halfway between the centres of texels (0,0) and (1,0): x = 0.5*2 - 0.5 = 0.5 -> weight 0.5.
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.5, 0.25), 0.5, 1e-12);
    // The middle of the texture: weight 0.25 of each texel.
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.5, 0.5), 0.25, 1e-12);
    // u = 0.6, v = 0.35: x = 0.7 (fx 0.7), y = 0.2 (fy 0.2): weight of (1,0) = 0.7 * 0.8.
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.6, 0.35), 0.7 * 0.8, 1e-12);
}

TEST_F(Bilinear, ClampToEdgeHoldsTheEdgeTexel) {
    // Beyond the right edge the column stays 1: full weight at v = 0.25 for any u >= 0.75.
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.9, 0.25), 1.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 7.3, 0.25), 1.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.25, -5.0), 0.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, 0.75, -5.0), 1.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_CLAMP, -1e30, 0.25), 0.0, 1e-12);
}

TEST_F(Bilinear, RepeatWrapsAroundTheEdge) {
    // u = 0.9: x = 1.3, between column 1 (weight 0.7) and column 2 = column 0 (weight 0.3).
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, 0.9, 0.25), 0.7, 1e-12);
    // u = 0.1: x = -0.3, between column -1 = column 1 (weight 0.3) and column 0.
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, 0.1, 0.25), 0.3, 1e-12);
    // Whole periods do not matter, negative ones included.
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, 3.75, -1.75), 1.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, -4.1, 0.25), 0.7, 1e-9);  // = u 0.9
    // Across the v edge: v = 0.0 -> y = -0.5, rows -1 = 1 and 0 half each.
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, 0.75, 0.0), 0.5, 1e-12);
}

TEST_F(Bilinear, MirroredRepeatReflectsEveryOtherPeriod) {
    // In [1, 2) the texture is mirrored: u = 1.25 shows column 1 (u = 0.75's), u = 1.75 column 0.
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, 1.25, 0.25), 1.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, 1.75, 0.25), 0.0, 1e-12);
    // At the mirror line u = 1 the two neighbours are both column 1 (OpenGL's rule): weight 1.
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, 1.0, 0.25), 1.0, 1e-12);
    // Negative side: u = -0.25 mirrors to 0.25 (column 0), u = -0.75 to 0.75 (column 1).
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, -0.25, 0.25), 0.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, -0.75, 0.25), 1.0, 1e-12);
    // u = 0 under mirroring: x = -0.5, columns -1 -> 0 and 0: 0 (no wrap to column 1, unlike
    // REPEAT's 0.5).
    EXPECT_NEAR(at(HT_WRAP_MIRROR, HT_WRAP_MIRROR, 0.0, 0.25), 0.0, 1e-12);
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_REPEAT, 0.0, 0.25), 0.5, 1e-12);
}

TEST_F(Bilinear, WrapModesActPerAxis) {
    // u clamped, v repeated: v = 1.25 is row 0 again.
    EXPECT_NEAR(at(HT_WRAP_CLAMP, HT_WRAP_REPEAT, 5.0, 1.25), 1.0, 1e-12);
    // u repeated, v clamped: v = 1.25 holds row 1.
    EXPECT_NEAR(at(HT_WRAP_REPEAT, HT_WRAP_CLAMP, 0.75, 1.25), 0.0, 1e-12);
}

TEST_F(Bilinear, NonFiniteCoordinatesReadInsideTheTexture) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (uint32_t mode : {HT_WRAP_REPEAT, HT_WRAP_CLAMP, HT_WRAP_MIRROR}) {
        const double a = at(mode, mode, nan, inf), b = at(mode, mode, -inf, nan);
        EXPECT_TRUE(a >= 0.0 && a <= 1.0) << mode;
        EXPECT_TRUE(b >= 0.0 && b <= 1.0) << mode;
    }
}

TEST(Texture, FilteringHappensInLinearLight) {
    // Black and white neighbours: halfway is linear 0.5, not the decode of sRGB 127.5 (~0.21).
    const std::vector<uint32_t> texels = texel_buffer({rgb8(0, 0, 0), rgb8(255, 255, 255)});
    const real3 c = ht_texture_sample(header(HT_SRGB_TABLE_SIZE, 2, 1, HT_WRAP_CLAMP, HT_WRAP_CLAMP),
                                      texels.data(), 0.5, 0.5);
    EXPECT_NEAR(c.y, 0.5, 1e-12);
}

TEST(Texture, NonSquareTextureIndexesRowsByWidth) {
    // 3 x 2: texel (x, y) = x + 10 * y in red, decoded; checks row stride = width.
    std::vector<uint32_t> texels = texel_buffer({});
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x) texels.push_back(rgb8(x + 10 * y, 0, 0));
    const HtTexture h = header(HT_SRGB_TABLE_SIZE, 3, 2, HT_WRAP_CLAMP, HT_WRAP_CLAMP);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x) {
            const double u = (x + 0.5) / 3.0, v = (y + 0.5) / 2.0;
            EXPECT_NEAR(ht_texture_sample(h, texels.data(), u, v).x, srgb_formula((x + 10 * y) / 255.0), kFloat)
                << x << "," << y;
        }
}

}  // namespace
