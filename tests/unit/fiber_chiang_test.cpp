// Chiang/pbrt model: white furnace, known values, sampling consistency.
#include <gtest/gtest.h>

#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

#include "fiber_test_util.h"

using namespace ht;

TEST(FiberChiang, RoughnessMappingsMatchPbrt) {
    // docs/MODEL.md §11 anchors
    EXPECT_NEAR(chiang_v_from_beta_m(0.3), 0.084611, 5e-7);
    EXPECT_NEAR(chiang_s_from_beta_n(0.3), 0.117160, 5e-7);
    auto s = sigma_a_from_color({0.5, 0.5, 0.5}, 0.3);
    EXPECT_NEAR(s[0], 0.013857, 2e-6);
}

TEST(FiberChiang, WhiteFurnaceIsOneOverBetaGrid) {
    // sigma_a = 0, alpha = 0: integral value dwi averaged over h must be 1 (pbrt: exact energy
    // conservation).  Tolerance 1e-3 as the brief; the quadrature (fibertest::albedo) error is < 1e-4.
    for (double bm : {0.1, 0.4, 1.0})
        for (double bn : {0.1, 0.4, 1.0}) {
            HairMaterialDesc d = fibertest::white("chiang", bm, bn);
            HtMaterial m = make_kernel_material(d);
            for (double th : {-80.0, 0.0, 45.0, 85.0}) {
                double a = fibertest::albedo(m, th, 3);
                EXPECT_GE(a, 0.999) << "beta_m " << bm << " beta_n " << bn << " theta " << th;
                EXPECT_LE(a, 1.001) << "beta_m " << bm << " beta_n " << bn << " theta " << th;
            }
        }
}

TEST(FiberChiang, MpMatchesBesselFormAndIsNormalised) {
    // pbrt's direct form exp(-b) I0(a) / (2 v sinh(1/v)) with the C++17 std::cyl_bessel_i (exact).
    // Relative agreement 1e-12 (both double).  Normalisation by composite Simpson, 1e-6.
    for (double v : {0.15, 0.3, 1.0, 5.0, 27.0}) {
        for (double ti : {-1.2, -0.3, 0.0, 0.4, 1.5})
            for (double to : {-0.9, 0.0, 0.2, 1.4}) {
                double a = std::cos(ti) * std::cos(to) / v, b = std::sin(ti) * std::sin(to) / v;
                double ref = std::exp(-b) * std::cyl_bessel_i(0.0, a) / (2 * v * std::sinh(1 / v));
                double got = ht_mp(std::cos(ti), std::sin(ti), std::cos(to), std::sin(to), v);
                EXPECT_NEAR(got, ref, 1e-12 * ref) << v << " " << ti << " " << to;
            }
    }
    for (double v : {5e-4, 0.01, 0.084611, 1.0, 27.0})
        for (double to : {0.0, 0.7, 1.5}) {
            int n = 20000;
            double s = 0, d = HT_PI / n;
            for (int i = 0; i <= n; ++i) {
                double t = -HT_PI / 2 + i * d;
                double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                s += w * ht_mp(std::cos(t), std::sin(t), std::cos(to), std::sin(to), v) * std::cos(t);
            }
            EXPECT_NEAR(s * d / 3, 1.0, 1e-6) << "v " << v << " theta_o " << to;
        }
}

TEST(FiberChiang, ExactI0FixesPbrtSeriesSwitch) {
    // docs/MODEL.md §12.5: log I0(11.9) = 9.7538 exactly (pbrt's series gives 9.7347).
    EXPECT_NEAR(ht_log_i0(11.9), std::log(std::cyl_bessel_i(0.0, 11.9)), 1e-13);
    EXPECT_NEAR(ht_log_i0(11.9), 9.7538, 1e-4);
    for (double x : {0.0, 0.5, 3.7, 3.8, 14.9, 15.1, 50.0, 600.0})
        EXPECT_NEAR(ht_i0e(x), std::exp(-x) * std::cyl_bessel_i(0.0, x), 1e-12 * std::exp(-x) * std::cyl_bessel_i(0.0, x) + 1e-300);  // series summation rounding near x = 15
}

TEST(FiberChiang, ApSumsToOneAndWhiteSampleWeightIsOne) {
    // pbrt identities: with sigma_a = 0, sum_p A_p = 1 (A_3 = geometric residual), and sampling lobes
    // proportionally to A_p makes every sample weight exactly 1.  Tolerance 1e-12 (double rounding).
    HtMaterial m = make_kernel_material(fibertest::white("chiang", 0.3, 0.3));
    for (double th : {-1.4, -0.5, 0.0, 0.8, 1.5})
        for (double h : {-0.999, -0.5, 0.0, 0.3, 0.9}) {
            HtChiangSetup c;
            ht_chiang_setup(&m, fibertest::wo_at(th * 180 / HT_PI), h, &c);
            double s = 0;
            for (int p = 0; p < 4; ++p) s += c.ap[p].x;
            EXPECT_NEAR(s, 1.0, 1e-12);
        }
    uint64_t st = 7;
    for (int i = 0; i < 2000; ++i) {
        double u[6];
        for (double& x : u) x = fibertest::rnd(st);
        real3 wo = fibertest::dir(std::asin(2 * u[4] - 1), 0.3), wi, w;
        real pdf;
        if (!ht_bcsdf_sample(&m, wo, 2 * u[5] - 1, u[0], u[1], u[2], u[3], &wi, &w, &pdf)) continue;
        EXPECT_NEAR(w.x, 1.0, 1e-9);
    }
}

TEST(FiberChiang, ValuesAgainstPbrtFormula) {
    // Independent transcription of pbrt-v4 HairBxDF::f (direct Bessel form, exact I0, atan2 angles),
    // times |cos theta_i| (our `value`).  Agreement 1e-6 relative: HtMaterial stores sin/cos of the tilts as
    // float, rounded independently of the float alpha the reference rotates with (~1e-7 each).
    HairMaterialDesc d;
    d.model = "chiang";
    d.has_sigma_a = true;
    d.sigma_a = {0.3f, 0.7f, 1.4f};
    d.alpha_deg = 2.0f;
    HtMaterial m = make_kernel_material(d);
    uint64_t st = 11;
    for (int n = 0; n < 200; ++n) {
        real3 wo = fibertest::rand_dir(st), wi = fibertest::rand_dir(st);
        double h = 2 * fibertest::rnd(st) - 1;
        real3 v;
        real pdf;
        ht_bcsdf_eval(&m, wo, wi, h, &v, &pdf);
        double ref = fibertest::pbrt_value(m, wo, wi, h, 0);
        EXPECT_NEAR(v.x, ref, 1e-6 * ref + 1e-300) << n;
    }
}
