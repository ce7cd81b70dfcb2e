// Shared helpers of the fibre tests (header only: the test globs take *.cpp).
#pragma once

#include "fiber/afs_quadrature.h"
#include "fiber/furnace.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fibertest {

inline ht::HairMaterialDesc white(const std::string& model, double bm, double bn) {
    ht::HairMaterialDesc d;
    d.model = model;
    d.has_sigma_a = true;
    d.sigma_a = {0.f, 0.f, 0.f};
    d.beta_m = (float)bm;
    d.beta_n = (float)bn;
    d.alpha_deg = 0.f;
    d.alpha_r_deg = 0.f;
    return d;
}

inline real3 wo_at(double theta_deg) {
    double t = theta_deg * HT_PI / 180.0;
    return make_real3(std::sin(t), 0.0, std::cos(t));  // renderer convention: phi_o = pi/2
}

inline real3 dir(double theta, double phi) {
    return make_real3(std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi));
}

inline double albedo_at(const HtMaterial& m, real3 wo, double h, int c = 0, double refine = 1.0) {
    return ht::furnace_albedo_at(m, wo.x, wo.y, wo.z, h, c, refine);
}
inline double albedo(const HtMaterial& m, double theta_o_deg, int nh, int c = 0) {
    return ht::furnace_albedo(m, theta_o_deg, nh, c);
}

// xorshift64* uniform in [0, 1)
inline double rnd(uint64_t& s) {
    s ^= s >> 12;
    s ^= s << 25;
    s ^= s >> 27;
    return (double)((s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}
inline real3 rand_dir(uint64_t& s) {
    double z = 2 * rnd(s) - 1, p = 2 * HT_PI * rnd(s), r = std::sqrt(std::max(0.0, 1 - z * z));
    return make_real3(z, r * std::cos(p), r * std::sin(p));
}

// pbrt-v4 HairBxDF::f * |cos theta_i| written out independently (direct Bessel M_p, std::atan2).
inline double pbrt_value(const HtMaterial& m, real3 wo, real3 wi, double h, int c) {
    auto mp = [](double ci, double co, double si, double so, double v) {
        double a = ci * co / v, b = si * so / v;
        return std::exp(-b) * std::cyl_bessel_i(0.0, a) / (2 * v * std::sinh(1 / v));
    };
    auto fr = [](double ci, double eta) {
        double st = std::sqrt(std::max(0.0, 1 - ci * ci)) / eta, ct = std::sqrt(std::max(0.0, 1 - st * st));
        double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
        return 0.5 * (rs * rs + rp * rp);
    };
    double eta = m.eta, sa = m.sigma_a[c];
    double so = wo.x, co = std::sqrt(1 - so * so), phio = std::atan2(wo.z, wo.y);
    double si = wi.x, ci = std::sqrt(1 - si * si), phii = std::atan2(wi.z, wi.y);
    double stt = so / eta, ctt = std::sqrt(1 - stt * stt);
    double etap = std::sqrt(eta * eta - so * so) / co;
    double sgt = h / etap, cgt = std::sqrt(1 - sgt * sgt), gt = std::asin(sgt), go = std::asin(h);
    double T = std::exp(-sa * (2 * cgt / ctt));
    double f = fr(co * std::sqrt(1 - h * h), eta);
    double ap[4];
    ap[0] = f;
    ap[1] = (1 - f) * (1 - f) * T;
    ap[2] = ap[1] * T * f;
    ap[3] = ap[2] * f * T / (1 - T * f);
    double phi = phii - phio, sum = 0;
    double al[3] = {m.alpha, 2 * m.alpha, 4 * m.alpha};
    double s = m.s;
    for (int p = 0; p < 3; ++p) {
        double spo, cpo;
        if (p == 0) { spo = so * std::cos(al[1]) - co * std::sin(al[1]); cpo = co * std::cos(al[1]) + so * std::sin(al[1]); }
        else if (p == 1) { spo = so * std::cos(al[0]) + co * std::sin(al[0]); cpo = co * std::cos(al[0]) - so * std::sin(al[0]); }
        else { spo = so * std::cos(al[2]) + co * std::sin(al[2]); cpo = co * std::cos(al[2]) - so * std::sin(al[2]); }
        cpo = std::fabs(cpo);
        double dphi = phi - (2 * p * gt - 2 * go + p * HT_PI);
        while (dphi > HT_PI) dphi -= 2 * HT_PI;
        while (dphi < -HT_PI) dphi += 2 * HT_PI;
        auto logistic = [&](double x) { x = std::fabs(x); return std::exp(-x / s) / (s * (1 + std::exp(-x / s)) * (1 + std::exp(-x / s))); };
        auto cdf = [&](double x) { return 1 / (1 + std::exp(-x / s)); };
        double np = logistic(dphi) / (cdf(HT_PI) - cdf(-HT_PI));
        sum += mp(ci, cpo, si, spo, m.v[p]) * ap[p] * np;
    }
    sum += mp(ci, co, si, so, m.v[3]) * ap[3] / (2 * HT_PI);
    return sum;  // = f * |cos theta_i|
}

}  // namespace fibertest
