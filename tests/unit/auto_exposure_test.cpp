// --exposure auto: which pixels set the level, and that a few very bright ones do not.
#include <gtest/gtest.h>

#include "io/image_io.h"

using namespace ht;

namespace {
Film grey_ramp(int lit, int black) {
    Film f;
    f.width = lit + black;
    f.height = 1;
    f.rgba.assign(4 * size_t(f.width), 0.0f);
    for (int i = 0; i < lit; ++i) {
        for (int c = 0; c < 3; ++c) f.rgba[4 * i + c] = float(i + 1);  // luminance i + 1 (grey)
        f.rgba[4 * i + 3] = 1.0f;
    }
    return f;
}
}  // namespace

TEST(AutoExposure, MapsThe95thPercentileOfLitPixelsTo08) {
    // 100 lit pixels with luminance 1..100 and 300 black ones: element 95 of the sorted lit values
    // is 96, whatever the black background covers.
    EXPECT_FLOAT_EQ(auto_exposure(grey_ramp(100, 300)), 0.8f / 96.0f);
    EXPECT_FLOAT_EQ(auto_exposure(grey_ramp(100, 0)), 0.8f / 96.0f);
}

TEST(AutoExposure, SparklesDoNotMoveIt) {
    // Two of 100 pixels 1000x brighter (Monte Carlo sparkles) only shift the ranks by two (96 -> 98);
    // a 99.5th-percentile rule would have followed them to 1e5.
    Film f = grey_ramp(100, 0);
    for (int i : {10, 50})
        for (int c = 0; c < 3; ++c) f.rgba[4 * i + c] = 1e5f;
    EXPECT_FLOAT_EQ(auto_exposure(f), 0.8f / 98.0f);
}

TEST(AutoExposure, AllBlackIsOne) { EXPECT_EQ(auto_exposure(grey_ramp(0, 10)), 1.0f); }
