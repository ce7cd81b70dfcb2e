// Shared helpers of the fibre tests (header only: the test globs take *.cpp).
#pragma once

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

// Gauss-Legendre nodes/weights on [-1, 1] (Newton on P_n, double precision).
inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(HT_PI * (i + 0.75) / (n + 0.5)), pp = 0;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1, p2 = 0;
            for (int j = 1; j <= n; ++j) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1);
            double z1 = z;
            z = z1 - p1 / pp;
            if (std::fabs(z - z1) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * pp * pp);
    }
}

// Narrowest longitudinal / azimuthal feature of a material (radians), to size quadratures.
inline void feature_widths(const HtMaterial& m, double& wth, double& wph) {
    switch (m.model) {
    case HT_MODEL_CHIANG: wth = std::sqrt(m.v[1]); wph = m.s * 2.0; break;
    case HT_MODEL_MARSCHNER: wth = 2.0 * m.beta_tt; wph = std::min(0.05, (double)m.caustic_wc); break;
    case HT_MODEL_ZINKE: wth = 2.0 * m.beta_tt; wph = std::min((double)m.azim_sigma, (double)m.caustic_wc); break;
    default: wth = 1.0 / std::sqrt((double)m.ks_exponent); wph = 1.0; break;
    }
    wth = std::max(wth, 1e-3);
    wph = std::max(wph, 1e-3);
}

// Deterministic quadrature of integral value dwi over the sphere for one (wo, h), channel c:
// composite 4-point Gauss-Legendre in theta_i (panel width <= width/2) x midpoint rule in phi_i
// (periodic, spacing <= width/4).  Relative error < 1e-5 for the smooth lobes (checked by doubling).
inline double albedo_at(const HtMaterial& m, real3 wo, double h, int c = 0, double refine = 1.0) {
    double wth, wph;
    feature_widths(m, wth, wph);
    int panels = std::min(4000, std::max(16, (int)std::ceil(HT_PI / (wth * 0.5) * refine)));
    int nph = std::min(20000, std::max(64, (int)std::ceil(2 * HT_PI / (wph * 0.25) * refine)));
    static std::vector<double> gx, gw;
    if (gx.empty()) gauss_legendre(4, gx, gw);
    double sum = 0, dth = HT_PI / panels, dph = 2 * HT_PI / nph;
    for (int i = 0; i < panels; ++i)
        for (int g = 0; g < 4; ++g) {
            double th = -HT_PI / 2 + dth * (i + 0.5 + 0.5 * gx[g]);
            double wt = 0.5 * dth * gw[g] * std::cos(th);
            double row = 0;
            for (int j = 0; j < nph; ++j) {
                real3 v;
                real pdf;
                ht_bcsdf_eval(&m, wo, dir(th, -HT_PI + dph * (j + 0.5)), h, &v, &pdf);
                row += c == 0 ? v.x : (c == 1 ? v.y : v.z);
            }
            sum += wt * row * dph;
        }
    return sum;
}

// Directional albedo at theta_o, averaged over h with nh-point Gauss-Legendre (h in [-1, 1]).
inline double albedo(const HtMaterial& m, double theta_o_deg, int nh, int c = 0) {
    std::vector<double> x, w;
    gauss_legendre(nh, x, w);
    double s = 0;
    for (int i = 0; i < nh; ++i) s += 0.5 * w[i] * albedo_at(m, wo_at(theta_o_deg), x[i], c);
    return s;
}

}  // namespace fibertest
