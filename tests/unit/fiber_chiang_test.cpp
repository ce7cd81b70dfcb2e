// Chiang/pbrt model: white furnace, known values, sampling consistency.
#include <gtest/gtest.h>

#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

#include "fiber_test_util.h"

using namespace ht;

TEST(FiberChiang, RoughnessMappingsMatchPbrt) {
    // MODEL_NOTES §11 anchors
    EXPECT_NEAR(chiang_v_from_beta_m(0.3), 0.084611, 5e-7);
    EXPECT_NEAR(chiang_s_from_beta_n(0.3), 0.117160, 5e-7);
    auto s = sigma_a_from_color({0.5, 0.5, 0.5}, 0.3);
    EXPECT_NEAR(s[0], 0.013857, 2e-6);
}

TEST(FiberChiang, WhiteFurnaceIsOneOverBetaGrid) {
    // sigma_a = 0, alpha = 0: integral value dwi averaged over h must be 1 (pbrt: exact energy
    // conservation).  Tolerance 1e-3 as the brief; the quadrature (fibertest::albedo) error is < 1e-4.
    for (double bm : {0.1, 0.3, 0.6, 1.0})
        for (double bn : {0.1, 0.3, 0.6, 1.0}) {
            HairMaterialDesc d = fibertest::white("chiang", bm, bn);
            HtMaterial m = make_kernel_material(d);
            for (double th : {-80.0, -30.0, 0.0, 45.0, 85.0}) {
                double a = fibertest::albedo(m, th, 5);
                EXPECT_GE(a, 0.999) << "beta_m " << bm << " beta_n " << bn << " theta " << th;
                EXPECT_LE(a, 1.001) << "beta_m " << bm << " beta_n " << bn << " theta " << th;
            }
        }
}
