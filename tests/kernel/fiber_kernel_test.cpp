// Float OpenCL kernel (fiber_query.cl) vs the same headers in double on the host.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cl/device.h"
#include "fiber/afs_quadrature.h"
#include "fiber/fiber_query_runner.h"
#include "cli/fiber_command.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"
#include "kernels/fiber/query.h"

using namespace ht;

namespace {
double rnd(uint64_t& s) {
    s ^= s >> 12;
    s ^= s << 25;
    s ^= s >> 27;
    return (double)((s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}
float fl(double x) { return (float)x; }

struct QueryBatch {
    std::vector<HtMaterial> mats;
    std::vector<HtFiberQuery> qs;
    std::vector<HtFiberResult> out;
};

bool run_kernel(QueryBatch& r, const char* name) {
    try {
        ClContext ctx;
        cl::Program prog = ctx.build("fiber/fiber_query.cl", ht::base_kernel_options());  // the render program's floating-point mode
        r.out = run_fiber_queries(ctx, prog, name, r.mats, r.qs);
        return true;
    } catch (const DeviceError& e) {
        std::printf("no OpenCL device: %s\n", e.what());
        return false;
    }
}

HtMaterial random_material(uint32_t model, uint64_t& s) {
    HairMaterialDesc d;
    const char* names[4] = {"kajiya", "marschner", "zinke", "chiang"};
    d.model = names[model];
    d.has_sigma_a = true;
    d.sigma_a = {fl(2 * rnd(s)), fl(2 * rnd(s)), fl(2 * rnd(s))};
    d.beta_m = fl(0.1 + 0.8 * rnd(s));
    d.beta_n = fl(0.1 + 0.8 * rnd(s));
    d.eta = fl(1.3 + 0.5 * rnd(s));
    d.alpha_deg = fl(-4 + 8 * rnd(s));
    d.alpha_r_deg = fl(-10 + 5 * rnd(s));
    d.beta_r_deg = fl(5 + 5 * rnd(s));
    d.eccentricity = fl(0.85 + 0.15 * rnd(s));
    return make_kernel_material(d);
}
}  // namespace

TEST(FiberKernel, FloatEvalMatchesDoubleHost) {
    // Tolerance: |float - double| <= 1e-4 |double| + 1e-7 x (largest value of that model in the batch)
    // for all queries away from the fragile regions (docs/MODEL.md §12): directions within 2.5 deg of the
    // tangent, |h| > 0.995, and for marschner/zinke the TRT caustic (|phi -+ phi_c| < 0.02 or eta' in
    // [1.98, 2.02], where the two caustics merge).  Everywhere (fragile or not) both must be finite and >= 0.  The absolute floor covers
    // far-tail values (exp(-30) and below) whose exponent carries float rounding x 30.
    const int per_model = 4000;
    QueryBatch r;
    uint64_t s = 12345;
    for (uint32_t model = 0; model < 4; ++model)
        for (int i = 0; i < per_model; ++i) {
            HtMaterial m = random_material(model, s);
            HtFiberQuery q{};
            double z1 = 2 * rnd(s) - 1, p1 = 2 * HT_PI * rnd(s), z2 = 2 * rnd(s) - 1, p2 = 2 * HT_PI * rnd(s);
            double r1 = std::sqrt(1 - z1 * z1), r2 = std::sqrt(1 - z2 * z2);
            q.wo[0] = fl(z1); q.wo[1] = fl(r1 * std::cos(p1)); q.wo[2] = fl(r1 * std::sin(p1));
            q.wi[0] = fl(z2); q.wi[1] = fl(r2 * std::cos(p2)); q.wi[2] = fl(r2 * std::sin(p2));
            q.h = fl(2 * rnd(s) - 1);
            r.mats.push_back(m);
            r.qs.push_back(q);
        }
    if (!run_kernel(r, "fiber_eval")) GTEST_SKIP() << "no OpenCL device";
    double vmax[4] = {0, 0, 0, 0}, pmax[4] = {0, 0, 0, 0};
    std::vector<real3> dv(r.qs.size());
    std::vector<double> dp(r.qs.size());
    for (size_t i = 0; i < r.qs.size(); ++i) {
        const HtFiberQuery& q = r.qs[i];
        real3 wo = make_real3(q.wo[0], q.wo[1], q.wo[2]), wi = make_real3(q.wi[0], q.wi[1], q.wi[2]);
        real pdf;
        ht_bcsdf_eval(&r.mats[i], wo, wi, q.h, &dv[i], &pdf);
        dp[i] = pdf;
        uint32_t mo = r.mats[i].model;
        vmax[mo] = std::max({vmax[mo], dv[i].x, dv[i].y, dv[i].z});
        pmax[mo] = std::max(pmax[mo], pdf);
    }
    int checked = 0, bad = 0, significant = 0, over_sig = 0;
    double worst = 0, worst_sig = 0;
    for (size_t i = 0; i < r.qs.size(); ++i) {
        const HtFiberQuery& q = r.qs[i];
        const HtFiberResult& o = r.out[i];
        const HtMaterial& m = r.mats[i];
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(o.value[c]) && o.value[c] >= 0) << i;
        ASSERT_TRUE(std::isfinite(o.pdf) && o.pdf >= 0) << i;
        bool fragile = std::fabs(q.wo[0]) > 0.999 || std::fabs(q.wi[0]) > 0.999 || std::fabs(q.h) > 0.995;
        if (m.model == HT_MODEL_MARSCHNER || m.model == HT_MODEL_ZINKE) {
            real3 wo = make_real3(q.wo[0], q.wo[1], q.wo[2]), wi = make_real3(q.wi[0], q.wi[1], q.wi[2]);
            HtMarschnerAngles a;
            ht_marschner_angles(wo, wi, &a);
            for (double eta : {(double)m.eta, ht_marschner_eta_star(&m, -1.0), ht_marschner_eta_star(&m, 1.0)}) {
                double inv_ep = ht_inv_eta_prime(eta, a.sin_d, a.cos_d), ep = 1 / inv_ep;
                double phi_c, dh, t, hc;
                ht_marschner_caustic(&m, inv_ep, &phi_c, &dh, &t, &hc);
                double phi = m.model == HT_MODEL_ZINKE ? ht_phi_path(2, std::asin(q.h), std::asin(q.h * inv_ep)) : a.phi;
                if (std::fabs(ht_wrap_pi(phi - phi_c)) < 0.02 || std::fabs(ht_wrap_pi(phi + phi_c)) < 0.02) fragile = true;
                if (ep > 1.98 && ep < 2.02) fragile = true;
                if (m.model == HT_MODEL_ZINKE && std::fabs(q.h) > 0.98) fragile = true;
            }
        }
        if (fragile) continue;
        ++checked;
        double d[3] = {dv[i].x, dv[i].y, dv[i].z};
        for (int c = 0; c < 3; ++c) {
            double tol = 1e-4 * d[c] + 1e-7 * vmax[m.model];
            double e = std::fabs(o.value[c] - d[c]);
            worst = std::max(worst, e / (d[c] + 1e-7 * vmax[m.model]));
            if (d[c] >= 1e-4 * vmax[m.model]) {
                ++significant;
                worst_sig = std::max(worst_sig, e / d[c]);
                if (e > 1e-4 * d[c]) ++over_sig;
            }
            if (e > tol) {
                if (++bad < 10) {
                    real3 lo[4], vv;
                    real pp;
                    ht_bcsdf_eval_lobes(&m, make_real3(q.wo[0], q.wo[1], q.wo[2]), make_real3(q.wi[0], q.wi[1], q.wi[2]), q.h, lo, &vv, &pp);
                    std::printf("model %u query %zu ch %d: float %.9g double %.9g lobes f %g %g %g d %g %g %g\n", m.model, i, c, o.value[c], d[c],
                                o.lobes[0][c], o.lobes[1][c], o.lobes[2][c], c == 0 ? lo[0].x : lo[0].y, c == 0 ? lo[1].x : lo[1].y, c == 0 ? lo[2].x : lo[2].y);
                }
            }
        }
        double tp = 1e-4 * dp[i] + 1e-7 * pmax[m.model];
        if (std::fabs(o.pdf - dp[i]) > tp) {
            if (++bad < 10) std::printf("model %u query %zu pdf: float %.9g double %.9g\n", m.model, i, o.pdf, dp[i]);
        }
    }
    std::printf("float vs double: %d of %zu queries checked (rest fragile), worst relative (with floor) %.2e; "
                "%d values >= 1e-4 x max: worst pure relative %.2e, %d above 1e-4\n", checked, r.qs.size(), worst,
                significant, worst_sig, over_sig);
    EXPECT_EQ(bad, 0);
    EXPECT_GT(checked, (int)(0.8 * r.qs.size()));
}

TEST(FiberKernel, FloatSampleMatchesDoubleHost) {
    // Same uniforms: same lobe choice and direction (<= 1e-4 per component away from lobe-choice
    // boundaries and the fragile regions above); the float weight is finite and >= 0 everywhere.
    // Every other query asks for the drawn lobe's weight (bcsdf.h mixture 0); where the directions
    // agree that weight agrees to 1e-3 relative (float rounding of one exp of a difference of two
    // exponents up to ~30, as in the eval test) on 98 %.
    QueryBatch r;
    uint64_t s = 777;
    for (uint32_t model = 0; model < 4; ++model)
        for (int i = 0; i < 2000; ++i) {
            HtMaterial m = random_material(model, s);
            HtFiberQuery q{};
            double z1 = 1.9 * rnd(s) - 0.95, p1 = 2 * HT_PI * rnd(s), r1 = std::sqrt(1 - z1 * z1);
            q.wo[0] = fl(z1); q.wo[1] = fl(r1 * std::cos(p1)); q.wo[2] = fl(r1 * std::sin(p1));
            q.h = fl(1.9 * rnd(s) - 0.95);
            q.u0 = fl(rnd(s)); q.u1 = fl(rnd(s)); q.u2 = fl(rnd(s)); q.u3 = fl(rnd(s));
            q.lobe_weight = float(i & 1);
            r.mats.push_back(m);
            r.qs.push_back(q);
        }
    if (!run_kernel(r, "fiber_sample")) GTEST_SKIP() << "no OpenCL device";
    int same = 0, total = 0, lobe_same = 0, lobe_weight_same = 0;
    for (size_t i = 0; i < r.qs.size(); ++i) {
        const HtFiberQuery& q = r.qs[i];
        const HtFiberResult& o = r.out[i];
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(o.value[c]) && o.value[c] >= 0);
        ASSERT_TRUE(std::isfinite(o.pdf) && o.pdf >= 0);
        real3 wi, w;
        real pdf;
        const int mixture = q.lobe_weight != 0 ? 0 : 1;
        int ok = ht_bcsdf_sample_mode(&r.mats[i], make_real3(q.wo[0], q.wo[1], q.wo[2]), q.h, q.u0, q.u1, q.u2, q.u3,
                                      mixture, &wi, &w, &pdf);
        if (!ok || o.ok == 0) continue;
        ++total;
        if (std::fabs(wi.x - o.wi[0]) < 1e-4 && std::fabs(wi.y - o.wi[1]) < 1e-4 && std::fabs(wi.z - o.wi[2]) < 1e-4) {
            ++same;
            if (!mixture) {
                ++lobe_same;
                bool agree = true;
                for (int c = 0; c < 3; ++c) {
                    const double d = c == 0 ? w.x : (c == 1 ? w.y : w.z);
                    agree = agree && std::fabs(o.value[c] - d) <= 1e-3 * std::max(1.0, d);
                }
                lobe_weight_same += agree;
            }
        }
    }
    std::printf("float vs double sampling: %d of %d directions agree to 1e-4; drawn-lobe weights %d of %d\n", same,
                total, lobe_weight_same, lobe_same);
    EXPECT_GT(lobe_weight_same, (int)(0.98 * lobe_same));
    // Lobe choice and root/caustic branches can flip at float rounding; 98 % must agree.
    EXPECT_GT(same, (int)(0.98 * total));
}

TEST(FiberKernel, FloatAfsMatchesReference) {
    // ht_afs_fast in float vs the double adaptive reference: |error| < 2e-6 absolute for R, TT, TRT
    // (float rounding of the 32-node sum and of the integrand; measured 3.7e-7, printed).
    std::vector<cl_float4> in;
    std::vector<double> ref;
    for (double eta : {1.3, 1.55, 2.0})
        for (double sa : {0.0, 0.1, 1.0})
            for (double th = 0; th <= 85; th += 5) {
                AfsValues v = afs_reference(eta, sa, th * HT_PI / 180);
                double r[3] = {v.R, v.TT, v.TRT};
                for (int p = 0; p < 3; ++p) {
                    cl_float4 q;
                    q.s[0] = (float)eta; q.s[1] = (float)sa; q.s[2] = (float)(th * HT_PI / 180); q.s[3] = (float)p;
                    in.push_back(q);
                    ref.push_back(r[p]);
                }
            }
    std::vector<float> out(in.size());
    try {
        ClContext ctx;
        cl::Program prog = ctx.build("fiber/fiber_query.cl", ht::base_kernel_options());  // the render program's floating-point mode
        cl::Kernel k(prog, "fiber_afs");
        cl::Buffer bi(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(cl_float4), in.data());
        cl::Buffer bo(ctx.context(), CL_MEM_WRITE_ONLY, out.size() * sizeof(float));
        cl_uint n = (cl_uint)in.size();
        k.setArg(0, bi); k.setArg(1, bo); k.setArg(2, n);
        ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
        ctx.queue().enqueueReadBuffer(bo, CL_TRUE, 0, n * sizeof(float), out.data());
    } catch (const DeviceError& e) {
        GTEST_SKIP() << "no OpenCL device";
    }
    double worst = 0;
    for (size_t i = 0; i < out.size(); ++i) worst = std::max(worst, std::fabs(out[i] - ref[i]));
    std::printf("AFS float kernel max |error| %.2e\n", worst);
    EXPECT_LT(worst, 2e-6);
}

TEST(FiberKernel, CliFloatPrecisionMatchesDouble) {
    // `hairtrace fiber eval --precision float` (one kernel launch for all lines) vs the default double path.
    std::string q =
        "{\"model\":\"chiang\",\"wo\":[0.3,0,0.9539392014169456],\"wi\":[-0.2,0.5,-0.8426149773176358],\"h\":0.1,\"sigma_a\":[0.2,0.4,0.8]}\n"
        "{\"model\":\"zinke\",\"wo\":[0.3,0,0.9539392014169456],\"wi\":[-0.2,0.5,-0.8426149773176358],\"h\":0.1,\"eumelanin\":0.3}\n"
        "{\"model\":\"marschner\",\"wo\":[0.3,0,0.9539392014169456],\"wi\":[-0.2,0.5,-0.8426149773176358]}\n"
        "{\"model\":\"kajiya\",\"wo\":[0.3,0,0.9539392014169456],\"wi\":[-0.2,0.5,-0.8426149773176358]}\n"
        "{\"model\":\"nope\"}\n";
    std::istringstream i1(q), i2(q);
    std::ostringstream o1, o2, e1, e2;
    int rc1 = fiber_main({"eval"}, i1, o1, e1);
    int rc2 = fiber_main({"eval", "--precision", "float"}, i2, o2, e2);
    if (rc2 == 3) GTEST_SKIP() << e2.str();
    EXPECT_EQ(rc1, 2);
    EXPECT_EQ(rc2, 2);
    std::istringstream a(o1.str()), b(o2.str());
    std::string la, lb;
    int n = 0;
    while (std::getline(a, la) && std::getline(b, lb)) {
        auto ja = nlohmann::json::parse(la), jb = nlohmann::json::parse(lb);
        ++n;
        if (ja.contains("error")) {
            EXPECT_TRUE(jb.contains("error"));
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            double x = ja["value"][c].get<double>(), y = jb["value"][c].get<double>();
            EXPECT_NEAR(y, x, 1e-4 * x + 1e-12) << la;
        }
        EXPECT_NEAR(jb["pdf"].get<double>(), ja["pdf"].get<double>(), 1e-4 * ja["pdf"].get<double>());
    }
    EXPECT_EQ(n, 5);
}
