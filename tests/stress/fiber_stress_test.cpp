// Numerical stress of every model: random and edge-case queries, host double and OpenCL float.
// Size: 10^7 random host queries x HT_STRESS_SCALE (default 0.02 for CI; the full run uses 1).
// Every value, pdf and sample weight must be finite and >= 0; sampled directions finite and unit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "cl/device.h"
#include "fiber/fiber_query_runner.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"
#include "kernels/fiber/query.h"

using namespace ht;

namespace {

double scale() {
    const char* s = std::getenv("HT_STRESS_SCALE");
    double v = s ? std::atof(s) : 0.02;
    return v > 0 ? v : 0.02;
}
double rnd(uint64_t& s) {
    s ^= s >> 12;
    s ^= s << 25;
    s ^= s >> 27;
    return (double)((s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}
const char* kModels[4] = {"kajiya", "marschner", "zinke", "chiang"};

// Material with parameters anywhere in the allowed ranges, extremes with probability ~1/4 each.
HairMaterialDesc random_desc(int model, uint64_t& s) {
    auto pick = [&](double lo, double hi) {
        double u = rnd(s);
        if (u < 0.15) return lo;
        if (u < 0.3) return hi;
        return lo + (hi - lo) * rnd(s);
    };
    HairMaterialDesc d;
    d.model = kModels[model];
    d.has_sigma_a = true;
    d.sigma_a = {(float)pick(0, 50), (float)pick(0, 50), (float)pick(0, 50)};
    d.eta = (float)pick(1.0001, 3.0);
    d.beta_m = (float)pick(0.01, 1.0);
    d.beta_n = (float)pick(0.01, 1.0);
    d.alpha_deg = (float)pick(-15, 15);
    d.alpha_r_deg = (float)pick(-20, 20);
    d.beta_r_deg = (float)pick(0.5, 45);
    d.caustic_wc_deg = (float)pick(1, 45);
    d.caustic_kg = (float)pick(0, 10);
    d.caustic_deta = (float)pick(0.01, 1);
    d.caustic_dhm = (float)pick(0, 1);
    d.eccentricity = (float)pick(0.5, 1);
    float kd = (float)pick(0, 1);
    d.kd = {kd, kd, kd};
    d.ks = {1 - kd, 1 - kd, 1 - kd};
    d.ks_exponent = (float)pick(1, 10000);
    return d;
}

std::vector<real3> edge_dirs() {
    std::vector<real3> v;
    const double e = 1e-7;
    double xs[] = {1.0, 1 - e, 0.9999, 0.7, 0.0, -0.7, -0.9999, -(1 - e), -1.0};
    for (double x : xs)
        for (double ph : {0.0, 1.5707963267948966, 3.14159265358979, -2.0}) {
            double r = std::sqrt(std::max(0.0, 1 - x * x));
            v.push_back(make_real3(x, r * std::cos(ph), r * std::sin(ph)));
        }
    return v;
}

bool finite_nonneg(real3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0 && v.y >= 0 && v.z >= 0;
}

}  // namespace

TEST(FiberStress, RandomQueriesHostDouble) {
    const long n = (long)(1e7 * scale());
    uint64_t s = 2024;
    long bad = 0, evals = 0, samples = 0, sampled_ok = 0;
    HtMaterial mats[64];
    for (int i = 0; i < 64; ++i) mats[i] = make_kernel_material(random_desc(i % 4, s));
    for (long i = 0; i < n; ++i) {
        if ((i & 4095) == 0) mats[(i >> 12) & 63] = make_kernel_material(random_desc((int)((i >> 12) & 3), s));
        const HtMaterial& m = mats[i & 63];
        double z1 = 2 * rnd(s) - 1, p1 = 6.283185307179586 * rnd(s), z2 = 2 * rnd(s) - 1, p2 = 6.283185307179586 * rnd(s);
        double r1 = std::sqrt(1 - z1 * z1), r2 = std::sqrt(1 - z2 * z2);
        real3 wo = make_real3(z1, r1 * std::cos(p1), r1 * std::sin(p1)), wi = make_real3(z2, r2 * std::cos(p2), r2 * std::sin(p2));
        double h = 2 * rnd(s) - 1;
        real3 v;
        real pdf;
        if (i & 1) {
            ht_bcsdf_eval(&m, wo, wi, h, &v, &pdf);
            ++evals;
            if (!finite_nonneg(v) || !std::isfinite(pdf) || pdf < 0) {
                if (++bad < 10) std::printf("bad eval model %u\n", m.model);
            }
        } else {
            real3 w, wsmp;
            ++samples;
            // every other sample asks for the drawn lobe's weight (bcsdf.h mixture 0)
            const double u0 = rnd(s), u1 = rnd(s), u2 = rnd(s), u3 = rnd(s);
            int ok = ht_bcsdf_sample_mode(&m, wo, h, u0, u1, u2, u3, int((i >> 1) & 1), &wsmp, &w, &pdf);
            sampled_ok += ok;
            if (!finite_nonneg(w) || !std::isfinite(pdf) || pdf < 0 || !std::isfinite(length(wsmp)) ||
                std::fabs(length(wsmp) - 1) > 1e-6) {
                if (++bad < 10) std::printf("bad sample model %u\n", m.model);
            }
        }
    }
    std::printf("host double random: %ld evals + %ld samples (%ld sampled a direction), %ld bad\n", evals, samples,
                sampled_ok, bad);
    EXPECT_EQ(bad, 0);
}

TEST(FiberStress, EdgeCasesHostDouble) {
    // theta -> +-90 deg, along the tangent, wo = wi, wo = -wi, h = +-1, h at the TRT caustic,
    // beta = 0.01 and 1, sigma_a = 0 and 50, eta = 1.0001 and 3, every model.
    std::vector<real3> dirs = edge_dirs();
    long count = 0, bad = 0;
    for (int model = 0; model < 4; ++model)
        for (double beta : {0.01, 1.0})
            for (double sa : {0.0, 50.0})
                for (double eta : {1.0001, 1.55, 3.0}) {
                    HairMaterialDesc d;
                    d.model = kModels[model];
                    d.has_sigma_a = true;
                    d.sigma_a = {(float)sa, (float)sa, (float)sa};
                    d.beta_m = d.beta_n = (float)beta;
                    d.eta = (float)eta;
                    d.beta_r_deg = beta < 0.5 ? 0.5f : 45.0f;
                    HtMaterial m = make_kernel_material(d);
                    double hc = eta < 2 ? std::sqrt((4 - eta * eta) / 3) : 0.0;
                    for (double h : {-1.0, -0.9999999, -hc, 0.0, hc, 0.5, 0.9999999, 1.0})
                        for (const real3& wo : dirs) {
                            for (const real3& wi0 : dirs)
                                for (int flip = 0; flip < 2; ++flip) {
                                    real3 wi = flip ? -wi0 : wi0;
                                    real3 v;
                                    real pdf;
                                    ht_bcsdf_eval(&m, wo, wi, h, &v, &pdf);
                                    ++count;
                                    if (!finite_nonneg(v) || !std::isfinite(pdf) || pdf < 0) ++bad;
                                }
                            for (double u : {0.0, 1e-7, 0.5, 0.9999999}) {
                                real3 w, wi;
                                real pdf;
                                for (int mixture = 0; mixture < 2; ++mixture) {
                                    ht_bcsdf_sample_mode(&m, wo, h, u, u, 1 - u, u, mixture, &wi, &w, &pdf);
                                    ++count;
                                    if (!finite_nonneg(w) || !std::isfinite(pdf) || pdf < 0) ++bad;
                                }
                            }
                        }
                }
    // garbage inputs: NaN / Inf / zero / non-unit directions and h
    const double nan = std::nan(""), inf = HUGE_VAL;
    real3 junk[] = {make_real3(nan, 0, 1), make_real3(0, inf, 0), make_real3(0, 0, 0), make_real3(3, 4, 0),
                    make_real3(-inf, nan, inf)};
    for (int model = 0; model < 4; ++model) {
        HairMaterialDesc d;
        d.model = kModels[model];
        HtMaterial m = make_kernel_material(d);
        for (const real3& a : junk)
            for (const real3& b : junk)
                for (double h : {nan, inf, -inf, 5.0, 0.3}) {
                    real3 v, w, wi;
                    real pdf;
                    ht_bcsdf_eval(&m, a, b, h, &v, &pdf);
                    ++count;
                    if (!finite_nonneg(v) || !std::isfinite(pdf) || pdf < 0) ++bad;
                    for (int mixture = 0; mixture < 2; ++mixture) {
                        ht_bcsdf_sample_mode(&m, a, h, 0.3, nan, 0.5, inf, mixture, &wi, &w, &pdf);
                        ++count;
                        if (!finite_nonneg(w) || !std::isfinite(pdf) || pdf < 0 || !std::isfinite(length(wi))) ++bad;
                    }
                }
    }
    std::printf("host double edge cases: %ld queries, %ld bad\n", count, bad);
    EXPECT_EQ(bad, 0);
}

TEST(FiberStress, RandomAndEdgeQueriesOpenClFloat) {
    // 10^6 x scale random queries + the edge set through fiber_query.cl (float).
    const long n = (long)(1e6 * scale());
    uint64_t s = 99;
    std::vector<HtMaterial> mats;
    std::vector<HtFiberQuery> qs;
    std::vector<real3> dirs = edge_dirs();
    for (long i = 0; i < n; ++i) {
        HtMaterial m = make_kernel_material(random_desc((int)(i & 3), s));
        HtFiberQuery q{};
        bool edge = (i % 4) == 3;
        real3 wo = dirs[(size_t)(rnd(s) * dirs.size()) % dirs.size()], wi = dirs[(size_t)(rnd(s) * dirs.size()) % dirs.size()];
        if (!edge) {
            double z1 = 2 * rnd(s) - 1, p1 = 6.283185307179586 * rnd(s), z2 = 2 * rnd(s) - 1, p2 = 6.283185307179586 * rnd(s);
            wo = make_real3(z1, std::sqrt(1 - z1 * z1) * std::cos(p1), std::sqrt(1 - z1 * z1) * std::sin(p1));
            wi = make_real3(z2, std::sqrt(1 - z2 * z2) * std::cos(p2), std::sqrt(1 - z2 * z2) * std::sin(p2));
        }
        if (i % 8 == 7) wi = wo;
        if (i % 16 == 15) wi = -wo;
        q.wo[0] = (float)wo.x; q.wo[1] = (float)wo.y; q.wo[2] = (float)wo.z;
        q.wi[0] = (float)wi.x; q.wi[1] = (float)wi.y; q.wi[2] = (float)wi.z;
        double hv[] = {-1.0, 1.0, 0.0, 2 * rnd(s) - 1};
        q.h = (float)(edge ? hv[i % 4] : 2 * rnd(s) - 1);
        if (i % 101 == 100) { q.wo[1] = NAN; q.h = NAN; }       // garbage inputs
        if (i % 103 == 102) { q.wi[0] = INFINITY; q.u2 = NAN; }
        if (i % 107 == 106) { q.wo[0] = q.wo[1] = q.wo[2] = 0.0f; }
        q.u0 = (float)rnd(s); q.u1 = (float)(edge ? 0.0 : rnd(s)); q.u3 = (float)(edge ? 0.99999994 : rnd(s));
        if (!(i % 103 == 102)) q.u2 = (float)rnd(s);
        q.lobe_weight = float((i >> 1) & 1);
        mats.push_back(m);
        qs.push_back(q);
    }
    // Both floating-point modes: the render program's (denormals flushed to zero, which PoCL
    // applies) and the default one with denormals kept, as a device that ignores the option runs.
    try {
        ClContext ctx;
        for (const std::string& options : {std::string(ht::base_kernel_options()), std::string("-cl-std=CL1.2")}) {
            long bad = 0;
            cl::Program prog = ctx.build("fiber/fiber_query.cl", options);
            for (const char* kname : {"fiber_eval", "fiber_sample"}) {
                const std::vector<HtFiberResult> out = run_fiber_queries(ctx, prog, kname, mats, qs);
                for (const HtFiberResult& r : out) {
                    bool ok = std::isfinite(r.pdf) && r.pdf >= 0;
                    for (int c = 0; c < 3; ++c) ok = ok && std::isfinite(r.value[c]) && r.value[c] >= 0 && std::isfinite(r.wi[c]);
                    for (int p = 0; p < 4; ++p)
                        for (int c = 0; c < 3; ++c) ok = ok && std::isfinite(r.lobes[p][c]) && r.lobes[p][c] >= 0;
                    if (!ok) ++bad;
                }
            }
            std::printf("OpenCL float (%s): %ld queries x (eval + sample), %ld bad\n", options.c_str(), n, bad);
            EXPECT_EQ(bad, 0) << options;
        }
    } catch (const DeviceError& e) {
        GTEST_SKIP() << "no OpenCL device: " << e.what();
    }
}
