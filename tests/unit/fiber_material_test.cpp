// make_kernel_material: validation (errors name the parameter and the range), conversions.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fiber/material.h"

using namespace ht;

namespace {
std::string error_of(const HairMaterialDesc& d) {
    try {
        make_kernel_material(d);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(FiberMaterial, RejectsOutOfRangeNamingParameterAndRange) {
    struct Bad {
        const char* param;
        void (*set)(HairMaterialDesc&);
        const char* range;
    } bad[] = {
        {"eta", [](HairMaterialDesc& d) { d.eta = 1.0f; }, "[1.0001, 3]"},
        {"beta_m", [](HairMaterialDesc& d) { d.beta_m = 0.0f; }, "[0.01, 1]"},
        {"beta_n", [](HairMaterialDesc& d) { d.beta_n = 1.5f; }, "[0.01, 1]"},
        {"alpha_deg", [](HairMaterialDesc& d) { d.alpha_deg = 40.0f; }, "[-15, 15]"},
        {"sigma_a[1]", [](HairMaterialDesc& d) { d.has_sigma_a = true; d.sigma_a = {0.1f, -1.0f, 0.1f}; }, "[0, 100]"},
        {"eumelanin", [](HairMaterialDesc& d) { d.has_melanin = true; d.eumelanin = -2; }, "[0, 50]"},
        {"color[2]", [](HairMaterialDesc& d) { d.has_color = true; d.color = {0.5f, 0.5f, 0.0f}; }, "[1e-05, 1]"},
        {"beta_r_deg", [](HairMaterialDesc& d) { d.beta_r_deg = 0.0f; }, "[0.5, 45]"},
        {"caustic_wc_deg", [](HairMaterialDesc& d) { d.caustic_wc_deg = 90.0f; }, "[1, 45]"},
        {"eccentricity", [](HairMaterialDesc& d) { d.eccentricity = 1.2f; }, "[0.5, 1]"},
        {"ks_exponent", [](HairMaterialDesc& d) { d.ks_exponent = 0.0f; }, "[1, 10000]"},
        {"eta", [](HairMaterialDesc& d) { d.eta = NAN; }, "[1.0001, 3]"},
    };
    for (auto& b : bad) {
        HairMaterialDesc d;
        d.name = "m1";
        b.set(d);
        std::string e = error_of(d);
        EXPECT_NE(e.find(b.param), std::string::npos) << e;
        EXPECT_NE(e.find(b.range), std::string::npos) << e;
        EXPECT_NE(e.find("m1"), std::string::npos) << e;
    }
    HairMaterialDesc d;
    d.model = "blinn";
    EXPECT_NE(error_of(d).find("blinn"), std::string::npos);
    d = HairMaterialDesc();
    d.has_sigma_a = d.has_melanin = true;
    EXPECT_NE(error_of(d).find("only one"), std::string::npos);
    d = HairMaterialDesc();
    d.kd = {0.8f, 0.5f, 0.5f};
    d.ks = {0.3f, 0.3f, 0.3f};
    EXPECT_NE(error_of(d).find("kd[0] + ks[0]"), std::string::npos);
}

TEST(FiberMaterial, Conversions) {
    HairMaterialDesc d;
    d.model = "chiang";
    d.has_melanin = true;
    d.eumelanin = 1.3f;
    d.pheomelanin = 0.5f;
    d.alpha_deg = 2.0f;
    HtMaterial m = make_kernel_material(d);
    EXPECT_EQ(m.model, HT_MODEL_CHIANG);
    EXPECT_NEAR(m.sigma_a[0], 1.3 * 0.419 + 0.5 * 0.187, 1e-6);
    EXPECT_NEAR(m.sigma_a[2], 1.3 * 1.37 + 0.5 * 1.05, 1e-6);
    EXPECT_NEAR(m.alpha, 2.0 * 3.14159265358979 / 180, 1e-7);
    EXPECT_NEAR(m.sin_tilt[2], std::sin(8.0 * 3.14159265358979 / 180), 1e-7);
    EXPECT_NEAR(m.v[1], 0.25 * m.v[0], 1e-9);
    EXPECT_NEAR(m.v[2], 4 * m.v[0], 1e-7);
    EXPECT_NEAR(m.s, 0.117160, 1e-6);
    d = HairMaterialDesc();
    d.model = "marschner";
    d.alpha_r_deg = -8.0f;
    d.beta_r_deg = 6.0f;
    m = make_kernel_material(d);
    double deg = 3.14159265358979 / 180;
    EXPECT_NEAR(m.alpha_tt, 4 * deg, 1e-7);
    EXPECT_NEAR(m.alpha_trt, 12 * deg, 1e-7);
    EXPECT_NEAR(m.beta_tt, 3 * deg, 1e-7);
    EXPECT_NEAR(m.beta_trt, 12 * deg, 1e-7);
    EXPECT_NEAR(m.caustic_wc, 15 * deg, 1e-7);
    // the sampling proxy's per-lobe constants the float kernels read (kernels/fiber/marschner.h
    // ht_mz_tilt): sin, cos 2 alpha_p and d'Eon's log normaliser -log v - log(1 - e^{-2/v}) of
    // v = (2 beta_p)^2, to float rounding (relative 6e-8; 2e-7 allows for the float inputs)
    const double alphas[3] = {-8 * deg, 4 * deg, 12 * deg}, betas[3] = {6 * deg, 3 * deg, 12 * deg};
    for (int p = 0; p < 3; ++p) {
        const double v = 4 * betas[p] * betas[p];
        EXPECT_NEAR(m.mz_sin_tilt[p], std::sin(2 * alphas[p]), 2e-7) << p;
        EXPECT_NEAR(m.mz_cos_tilt[p], std::cos(2 * alphas[p]), 2e-7) << p;
        const double log_norm = -std::log(v) - std::log(1 - std::exp(-2 / v));
        EXPECT_NEAR(m.mz_log_norm[p], log_norm, 2e-7 * std::fabs(log_norm)) << p;
    }
    // Kajiya-Kay normaliser: p = 1 -> 1/(2 pi * pi/2) = 1/pi^2
    EXPECT_NEAR(kajiya_ks_norm(1.0), 1 / (3.14159265358979 * 3.14159265358979), 1e-12);
    // colour inversion round trip at beta_n = 0.3 (docs/MODEL.md §11: c = 0.5 -> 0.013857)
    d = HairMaterialDesc();
    d.has_color = true;
    d.color = {0.5f, 0.5f, 0.5f};
    EXPECT_NEAR(make_kernel_material(d).sigma_a[1], 0.013857, 2e-6);
}
