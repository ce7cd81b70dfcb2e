// Sampling of every model: weight == value/pdf, the returned pdf is the density eval reports, the
// sampled directions follow the pdf (chi-square), and the sampled estimator of the albedo agrees
// with the deterministic quadrature (uniform/deterministic estimator) -- also with the drawn lobe's
// weight (bcsdf.h mixture 0), whose formula is checked against eval's lobes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fiber_test_util.h"

using namespace ht;

namespace {

HtMaterial material(const char* model) {
    HairMaterialDesc d;
    d.model = model;
    d.has_sigma_a = true;
    d.sigma_a = {0.2f, 0.5f, 1.0f};
    return make_kernel_material(d);
}

struct Case {
    const char* model;
    double theta_deg, h;
};
const Case kCases[] = {{"kajiya", 20, 0.3},    {"chiang", 0, -0.4},    {"chiang", 60, 0.9},
                       {"marschner", 10, 0.0}, {"marschner", 55, 0.0}, {"zinke", 0, 0.2},
                       {"zinke", 45, -0.8},    {"zinke", 75, 0.95}};

}  // namespace

TEST(FiberSampling, WeightIsValueOverPdfAndPdfMatchesEval) {
    // Relative 1e-9: the sampled direction is re-evaluated exactly as eval does (double).
    for (const char* model : {"kajiya", "marschner", "zinke", "chiang"}) {
        HtMaterial m = material(model);
        uint64_t st = 3;
        int ok_count = 0;
        for (int i = 0; i < 3000; ++i) {
            real3 wo = fibertest::rand_dir(st), wi, w;
            double h = 2 * fibertest::rnd(st) - 1;
            double u[4];
            for (double& x : u) x = fibertest::rnd(st);
            real pdf;
            if (!ht_bcsdf_sample(&m, wo, h, u[0], u[1], u[2], u[3], &wi, &w, &pdf)) continue;
            ++ok_count;
            ASSERT_NEAR(length(wi), 1.0, 1e-9);
            real3 v;
            real p2;
            ht_bcsdf_eval(&m, wo, wi, h, &v, &p2);
            ASSERT_NEAR(p2, pdf, 1e-9 * pdf) << model;
            ASSERT_NEAR(w.x, v.x / pdf, 1e-9 * (w.x + 1e-300)) << model;
            ASSERT_NEAR(w.z, v.z / pdf, 1e-9 * (w.z + 1e-300)) << model;
        }
        EXPECT_GT(ok_count, 2500) << model;
    }
}

TEST(FiberSampling, ChiSquareOfSampledDirections) {
    // Bins: 12 in sin(theta_i) x 16 in phi_i - phi_o.  Expected counts = N x (pdf integrated over the bin
    // by a 24 x 24 midpoint rule); bins with expectation < 5 are pooled.  Threshold: chi-square quantile
    // at p = 1e-4 (Wilson-Hilferty), i.e. a correct sampler fails once in 10^4 runs (seeds are fixed).
    const int NZ = 12, NP = 16, SUB = 24, N = 100000;
    for (const Case& c : kCases) {
        HtMaterial m = material(c.model);
        real3 wo = fibertest::wo_at(c.theta_deg);
        std::vector<double> obs(NZ * NP, 0.0), expct(NZ * NP, 0.0);
        uint64_t st = 99;
        for (int i = 0; i < N; ++i) {
            double u[4];
            for (double& x : u) x = fibertest::rnd(st);
            real3 wi, w;
            real pdf;
            if (!ht_bcsdf_sample(&m, wo, c.h, u[0], u[1], u[2], u[3], &wi, &w, &pdf)) continue;
            double z = std::min(std::max(wi.x, -1.0), 1.0);
            double phi = std::atan2(wi.z, wi.y) - HT_PI / 2;  // phi_o = pi/2
            phi = phi - 2 * HT_PI * std::floor((phi + HT_PI) / (2 * HT_PI));
            int iz = std::min(NZ - 1, (int)((z + 1) / 2 * NZ)), ip = std::min(NP - 1, (int)((phi + HT_PI) / (2 * HT_PI) * NP));
            obs[iz * NP + ip] += 1;
        }
        for (int iz = 0; iz < NZ; ++iz)
            for (int ip = 0; ip < NP; ++ip) {
                double s = 0, dz = 2.0 / NZ / SUB, dp = 2 * HT_PI / NP / SUB;
                for (int a = 0; a < SUB; ++a)
                    for (int b = 0; b < SUB; ++b) {
                        double z = -1 + iz * 2.0 / NZ + (a + 0.5) * dz;
                        double phi = -HT_PI + ip * 2 * HT_PI / NP + (b + 0.5) * dp + HT_PI / 2;
                        double r = std::sqrt(std::max(0.0, 1 - z * z));
                        real3 v;
                        real pdf;
                        ht_bcsdf_eval(&m, wo, make_real3(z, r * std::cos(phi), r * std::sin(phi)), c.h, &v, &pdf);
                        s += pdf * dz * dp;
                    }
                expct[iz * NP + ip] = s * N;
            }
        double chi2 = 0, pool_o = 0, pool_e = 0;
        int dof = 0;
        for (size_t k = 0; k < obs.size(); ++k) {
            if (expct[k] < 5) {
                pool_o += obs[k];
                pool_e += expct[k];
                continue;
            }
            chi2 += (obs[k] - expct[k]) * (obs[k] - expct[k]) / expct[k];
            ++dof;
        }
        if (pool_e >= 5) {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            ++dof;
        }
        double k = dof - 1, zq = 3.719;
        double crit = k * std::pow(1 - 2 / (9 * k) + zq * std::sqrt(2 / (9 * k)), 3);
        EXPECT_LT(chi2, crit) << c.model << " theta " << c.theta_deg << " h " << c.h << " dof " << dof;
    }
}

TEST(FiberSampling, DrawnLobeWeightIsTheLobeOverItsDensity) {
    // ht_zinke_lobe_weight x (pr_p M_p(theta_i) D(phi - Phi_p)) == eval's lobe p, relative 1e-9
    // (double; the azimuthal Gaussian the weight leaves out is put back here).
    HtMaterial m = material("zinke");
    uint64_t st = 11;
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const real3 wo = fibertest::rand_dir(st), wi = fibertest::rand_dir(st);
        const double h = 1.98 * fibertest::rnd(st) - 0.99;
        HtMzWo o;
        ht_zinke_wo(&m, wo, h, &o);
        real3 lobes[4], value;
        ht_zinke_eval_o(&m, &o, wo, wi, h, lobes, &value, nullptr);
        HtMarschnerAngles a;
        ht_mz_angles(&o, wo, wi, &a);
        real3 wl[3];
        real phis[3];
        ht_zinke_w(&m, h, a.sin_d, a.cos_d, wl, phis);
        for (int p = 0; p < 3; ++p) {
            real3 w;
            if (!ht_zinke_lobe_weight(&m, &o, wo, wi, h, p, &w)) continue;
            const double density =
                o.pr[p] * ht_mz_theta_pdf(&o, p, a.sin_i, a.cos_i) * ht_wrapped_gaussian(a.phi - phis[p], m.azim_sigma);
            if (!(density > 1e-200)) continue;
            ++checked;
            ASSERT_NEAR(w.x * density, lobes[p].x, 1e-9 * lobes[p].x + 1e-300) << "p " << p;
            ASSERT_NEAR(w.z * density, lobes[p].z, 1e-9 * lobes[p].z + 1e-300) << "p " << p;
        }
    }
    EXPECT_GT(checked, 8000);
}

TEST(FiberSampling, DrawnLobeWeightSamplesTheSameDirections) {
    // mixture 0 and 1 draw the same direction from the same uniforms (every model); the models
    // without a drawn-lobe weight (kajiya, marschner) return the same weight as well.
    for (const char* model : {"kajiya", "marschner", "zinke", "chiang"}) {
        HtMaterial m = material(model);
        uint64_t st = 21;
        for (int i = 0; i < 2000; ++i) {
            const real3 wo = fibertest::rand_dir(st);
            const double h = 2 * fibertest::rnd(st) - 1;
            double u[4];
            for (double& x : u) x = fibertest::rnd(st);
            real3 wi0, wi1, w0, w1;
            real pdf0, pdf1;
            const int ok0 = ht_bcsdf_sample_mode(&m, wo, h, u[0], u[1], u[2], u[3], 0, &wi0, &w0, &pdf0);
            const int ok1 = ht_bcsdf_sample_mode(&m, wo, h, u[0], u[1], u[2], u[3], 1, &wi1, &w1, &pdf1);
            if (!ok0 || !ok1) continue;
            ASSERT_EQ(wi0.x, wi1.x) << model;
            ASSERT_EQ(wi0.z, wi1.z) << model;
            if (std::string(model) != "zinke" && std::string(model) != "chiang") {
                ASSERT_EQ(w0.y, w1.y) << model;
                ASSERT_EQ(pdf0, pdf1) << model;
            } else {
                ASSERT_EQ(pdf0, 0.0) << model;
            }
        }
    }
}

TEST(FiberSampling, SampledUniformAndQuadratureEstimatorsAgree) {
    // Mean sample weight vs the deterministic quadrature of integral value dwi: |diff| < 5 standard errors
    // + 2e-4 (quadrature error bound, the doubling check of fiber_furnace_test); for the drawn lobe's
    // weight (mixture 0) as well as for value / pdf.
    for (const Case& c : kCases) {
        HtMaterial m = material(c.model);
        real3 wo = fibertest::wo_at(c.theta_deg);
        double q = fibertest::albedo_at(m, wo, c.h);
        double mean = 0, se = 0;
        uint64_t st = 5;
        for (int mixture = 0; mixture < 2; ++mixture) {  // value / pdf last: its state goes on below
            st = 5;
            double s = 0, s2 = 0;
            const int N = 60000;
            for (int i = 0; i < N; ++i) {
                double u[4];
                for (double& x : u) x = fibertest::rnd(st);
                real3 wi, w;
                real pdf;
                if (!ht_bcsdf_sample_mode(&m, wo, c.h, u[0], u[1], u[2], u[3], mixture, &wi, &w, &pdf)) continue;
                s += w.x;
                s2 += w.x * w.x;
            }
            mean = s / N;
            se = std::sqrt(std::max(0.0, s2 / N - mean * mean) / N);
            EXPECT_NEAR(mean, q, 5 * se + 2e-4)
                << c.model << " theta " << c.theta_deg << " h " << c.h << " mixture " << mixture;
        }
        // uniform-sphere estimator 4 pi value(wi): agrees with the sampled one within 5 combined errors
        double us = 0, us2 = 0;
        const int NU = 200000;
        for (int i = 0; i < NU; ++i) {
            real3 wi = fibertest::rand_dir(st), v;
            real pdf;
            ht_bcsdf_eval(&m, wo, wi, c.h, &v, &pdf);
            double x = 4 * HT_PI * v.x;
            us += x;
            us2 += x * x;
        }
        double umean = us / NU, use = std::sqrt(std::max(0.0, us2 / NU - umean * umean) / NU);
        EXPECT_NEAR(umean, mean, 5 * std::sqrt(se * se + use * use)) << c.model << " uniform vs sampled";
    }
}
