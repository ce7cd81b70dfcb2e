// Host (double) checks of the portable Lambertian BSDF (kernels/surface/lambert.h).
#include <gtest/gtest.h>

#include "kernels/surface/lambert.h"

#include <cmath>
#include <random>

namespace {

real3 v3(double x, double y, double z) { return make_real3(x, y, z); }

TEST(Lambert, BasisIsOrthonormal) {
    std::mt19937 rng(1);
    std::normal_distribution<double> g;
    for (int i = 0; i < 1000; ++i) {
        const real3 n = normalize(v3(g(rng), g(rng), g(rng)));
        real3 t, b;
        ht_onb(n, &t, &b);
        EXPECT_NEAR(dot(t, t), 1.0, 1e-12);
        EXPECT_NEAR(dot(b, b), 1.0, 1e-12);
        EXPECT_NEAR(dot(t, n), 0.0, 1e-12);
        EXPECT_NEAR(dot(b, n), 0.0, 1e-12);
        EXPECT_NEAR(dot(t, b), 0.0, 1e-12);
    }
}

// Samples follow cos/pi: the pdf the sampler reports equals the evaluation's, every sample is
// above the surface, and the estimate of a known integral (E[cos] = 2/3) comes out.
TEST(Lambert, SamplingMatchesEvaluation) {
    const real3 n = normalize(v3(0.3, 1.0, -0.2));
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(0, 1);
    double sum_cos = 0;
    int accepted = 0;
    const int N = 200000;
    for (int i = 0; i < N; ++i) {
        real3 wi;
        real pdf;
        if (!ht_lambert_sample(n, n, u(rng), u(rng), &wi, &pdf)) continue;
        ++accepted;
        real pe;
        const double f = ht_lambert_eval(n, n, wi, &pe);
        EXPECT_NEAR(pdf, pe, 1e-12);
        EXPECT_NEAR(f, pe, 1e-12);  // f cos / pdf = 1 per unit albedo
        EXPECT_NEAR(length(wi), 1.0, 1e-12);
        sum_cos += dot(wi, n);
    }
    EXPECT_GE(accepted, N - 10);
    EXPECT_NEAR(sum_cos / accepted, 2.0 / 3.0, 3e-3);
}

// Energy: the integral of f cos over the hemisphere is 1 per unit albedo (uniform sampling,
// independent of the cosine sampler).
TEST(Lambert, IntegratesToOne) {
    const real3 n = v3(0, 0, 1);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    double sum = 0;
    const int N = 400000;
    for (int i = 0; i < N; ++i) {
        const double z = u(rng), phi = 2 * M_PI * u(rng), r = std::sqrt(1 - z * z);
        real pdf;
        sum += ht_lambert_eval(n, n, v3(r * std::cos(phi), r * std::sin(phi), z), &pdf) * 2 * M_PI;
    }
    EXPECT_NEAR(sum / N, 1.0, 5e-3);
}

TEST(Lambert, FaceForwardAndGeometricNormalGuard) {
    // Viewer below the surface: both normals turn towards it.
    real3 ng = v3(0, 1, 0), ns = v3(0.1, 0.99, 0);
    ht_lambert_face_forward(v3(0, -1, 0), &ng, &ns);
    EXPECT_EQ(ng.y, -1.0);
    EXPECT_LT(ns.y, 0.0);
    EXPECT_NEAR(length(ns), 1.0, 1e-12);
    // A zero shading normal falls back to the geometric one.
    real3 g2 = v3(0, 0, 1), s2 = v3(0, 0, 0);
    ht_lambert_face_forward(v3(0, 0, 1), &g2, &s2);
    EXPECT_EQ(s2.z, 1.0);
    // A shading normal leaning past ng: directions below ng get nothing (no light leaks).
    const real3 lean = normalize(v3(1, 0, 0.2)), geo = v3(0, 0, 1);
    real pdf;
    EXPECT_EQ(ht_lambert_eval(lean, geo, normalize(v3(1, 0, -0.1)), &pdf), 0.0);
    EXPECT_EQ(pdf, 0.0);
    EXPECT_GT(ht_lambert_eval(lean, geo, normalize(v3(1, 0, 0.1)), &pdf), 0.0);
}

}  // namespace
