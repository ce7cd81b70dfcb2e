/* Zinke 2004 averaged attenuation coefficients AFS^avg_p(theta; eta, sigma_a) (§5, Appendix 2;
 * docs/MODEL.md §7):   AFS_p = integral_0^1 A_p(h) S'_p(h) dh,  S'_p = 1/|dPhi_p/dh|,
 * theta_i = theta_r = theta (eta' and theta_t at theta), chord absorption 2 sigma_a cos gamma_t/cos theta_t
 * per internal segment, exact (= Bravais) Fresnel.  TRT: S''_TRT = S'_TRT x Marschner's removal factor at
 * phi = Phi(2, h) (reading (a), "TRT"), optionally + the glint term (reading (b), "TRT_glint"):
 * 2 t k_G A_TRT(h_c) dh [g(Phi - phi_c) + g(Phi + phi_c)].  Caustic parameters as in Fig. 4:
 * w_c = 15 deg, k_G = 2.5, delta eta' = 0.3, delta h_M = 0.5 (HtAfsParams).
 *
 * Reference: host/fiber/afs_quadrature.cpp (adaptive Gauss-Kronrod in u = asin h, split at the caustic,
 * double).  Fast kernel version ht_afs_fast: fixed 16-point Gauss-Legendre in u on [0, u_c] and
 * [u_c, pi/2] (one interval when there is no caustic).  Error vs the reference in double
 * (tests/unit/fiber_afs_test, theta in [0, 85] deg step 5, sigma_a in {0, 0.1, 1, 5}, eta in {1.3, 1.55, 2}):
 * R 1.2e-14, TT 6.1e-13, TRT 3.0e-10, glint 4.5e-11 absolute (the split at u_c removes the only kink).
 * In float (OpenCL kernel fiber_afs) the error is float rounding: 3.7e-7 absolute measured over eta in
 * {1.3, 1.55, 2}, sigma_a in {0, 0.1, 1}, theta 0..85 deg (tests/kernel/fiber_kernel_test). */
#ifndef HT_FIBER_AFS_H
#define HT_FIBER_AFS_H

#include "marschner.h"

typedef struct {
    real eta, sigma_a, sin_t, cos_t;
    real wc, kg, deta, dhm;
} HtAfsParams;

HT_FIBER_FN void ht_afs_params(HtAfsParams* a, real eta, real sigma_a, real theta) {
    a->eta = eta;
    a->sigma_a = sigma_a;
    ht_sincos(theta, &a->sin_t, &a->cos_t);
    a->cos_t = fabs(a->cos_t);
    a->wc = HT_R(15) * HT_PI / HT_R(180);
    a->kg = HT_R(2.5);
    a->deta = HT_R(0.3);
    a->dhm = HT_R(0.5);
}

/* Integrand of AFS_p at h in [0, 1): p = 0 R, 1 TT, 2 TRT (removal), 3 TRT glint term only. */
HT_FIBER_FN real ht_afs_integrand(const HtAfsParams* a, int p, real h) {
    real eta = a->eta;
    real inv_ep = ht_inv_eta_prime(eta, a->sin_t, a->cos_t);
    real f = ht_fresnel_dielectric(a->cos_t * ht_safe_sqrt(HT_R(1) - h * h), eta);
    if (p == 0) return f * ht_inv_dphi_dh(0, h, inv_ep);
    real hq = h * inv_ep;
    real cgt = ht_safe_sqrt(HT_R(1) - hq * hq);
    real T = exp(-a->sigma_a * HT_R(2) * cgt / ht_cos_theta_t(eta, a->sin_t));
    if (p == 1) return (HT_R(1) - f) * (HT_R(1) - f) * T * ht_inv_dphi_dh(1, h, inv_ep);
    /* caustic */
    real ep2 = HT_R(1) / ht_max(inv_ep * inv_ep, HT_R(1e-30));
    real phi_c, dh, t, hc;
    if (ep2 < HT_R(4)) {
        hc = sqrt((HT_R(4) - ep2) / HT_R(3));
        phi_c = fabs(ht_wrap_pi(ht_phi_path(2, ht_asin(hc), ht_asin(hc * inv_ep))));
        real aa = ht_max(ep2 - hc * hc, HT_R(1e-12)), bb = ht_max(HT_R(1) - hc * hc, HT_R(1e-12));
        real d2 = HT_R(4) * hc / (aa * sqrt(aa)) - HT_R(2) * hc / (bb * sqrt(bb));
        dh = ht_min(a->dhm, HT_R(2) * sqrt(HT_R(2) * a->wc / ht_max(fabs(d2), HT_R(1e-12))));
        t = HT_R(1);
    } else {
        real x = ht_clamp((sqrt(ep2) - HT_R(2)) / a->deta, HT_R(0), HT_R(1));
        hc = HT_R(0); phi_c = HT_R(0); dh = a->dhm;
        t = HT_R(1) - x * x * (HT_R(3) - HT_R(2) * x);
    }
    real phi = ht_phi_path(2, ht_asin(h), ht_asin(hq));
    real d1 = ht_wrap_pi(phi - phi_c), d2 = ht_wrap_pi(phi + phi_c);
    if (p == 2) {
        real r1 = exp(-HT_R(0.5) * d1 * d1 / (a->wc * a->wc)), r2 = exp(-HT_R(0.5) * d2 * d2 / (a->wc * a->wc));
        real rem = (HT_R(1) - t * r1) * (HT_R(1) - t * r2);
        /* S' diverges like 1/|h - h_c| where rem vanishes like (h - h_c)^4: evaluate S' unclamped */
        real c = ht_safe_sqrt(HT_R(1) - h * h), q = ht_safe_sqrt(ep2 - h * h);
        real den = fabs(HT_R(4) - ep2 - HT_R(3) * h * h);
        real sp = den > HT_R(0) ? c * q * (HT_R(2) * c + q) / (HT_R(2) * den) : HT_R(0);
        real v = (HT_R(1) - f) * (HT_R(1) - f) * f * T * T * sp * rem;
        return v == v ? v : HT_R(0);
    }
    /* glint term */
    real fc = ht_fresnel_dielectric(a->cos_t * ht_safe_sqrt(HT_R(1) - hc * hc), eta);
    real hcq = hc * inv_ep;
    real Tc = exp(-a->sigma_a * HT_R(2) * ht_safe_sqrt(HT_R(1) - hcq * hcq) / ht_cos_theta_t(eta, a->sin_t));
    real atrt = (HT_R(1) - fc) * (HT_R(1) - fc) * fc * Tc * Tc;
    return HT_R(2) * t * a->kg * atrt * dh * (ht_gaussian(d1, a->wc) + ht_gaussian(d2, a->wc));
}

/* Upper limit in u = asin h of the first sub-interval: the caustic u_c, or pi/2 without one. */
HT_FIBER_FN real ht_afs_split(const HtAfsParams* a) {
    real inv_ep = ht_inv_eta_prime(a->eta, a->sin_t, a->cos_t);
    real ep2 = HT_R(1) / ht_max(inv_ep * inv_ep, HT_R(1e-30));
    return ep2 < HT_R(4) ? ht_asin(sqrt((HT_R(4) - ep2) / HT_R(3))) : HT_HALF_PI;
}

/* 16-point Gauss-Legendre on [lo, hi] of integrand(sin u) cos u. */
HT_FIBER_FN real ht_afs_gl16(const HtAfsParams* a, int p, real lo, real hi) {
    const real x[8] = {HT_R(0.0950125098376374), HT_R(0.2816035507792589), HT_R(0.4580167776572274), HT_R(0.6178762444026438),
                       HT_R(0.7554044083550030), HT_R(0.8656312023878318), HT_R(0.9445750230732326), HT_R(0.9894009349916499)};
    const real w[8] = {HT_R(0.1894506104550685), HT_R(0.1826034150449236), HT_R(0.1691565193950025), HT_R(0.1495959888165767),
                       HT_R(0.1246289712555339), HT_R(0.0951585116824928), HT_R(0.0622535239386479), HT_R(0.0271524594117541)};
    real c = HT_R(0.5) * (lo + hi), r = HT_R(0.5) * (hi - lo), s = HT_R(0);
    for (int k = 0; k < 8; ++k)
        for (int sg = -1; sg <= 1; sg += 2) {
            real u = c + (real)sg * r * x[k];
            real su, cu;
            ht_sincos(u, &su, &cu);
            s += w[k] * ht_afs_integrand(a, p, ht_clamp(su, HT_R(0), HT_R(1))) * cu;
        }
    return s * r;
}

/* Fast AFS_p (p = 0..3 as ht_afs_integrand). */
HT_FIBER_FN real ht_afs_fast(real eta, real sigma_a, real theta, int p) {
    HtAfsParams a;
    ht_afs_params(&a, eta, sigma_a, theta);
    real uc = ht_afs_split(&a);
    real s = ht_afs_gl16(&a, p, HT_R(0), uc);
    if (uc < HT_HALF_PI) s += ht_afs_gl16(&a, p, uc, HT_HALF_PI);
    return s;
}

/* AFS_TT for three absorption coefficients at once: ht_afs_fast(eta, sigma_a[c], theta, 1) for each
 * channel, with the same nodes and the same arithmetic per node, sharing everything but the chord
 * transmittance (Fresnel, ray density, node angles), which is most of the work. */
HT_FIBER_FN real3 ht_afs_tt3(real eta, real3 sigma_a, real theta) {
    const real x[8] = {HT_R(0.0950125098376374), HT_R(0.2816035507792589), HT_R(0.4580167776572274), HT_R(0.6178762444026438),
                       HT_R(0.7554044083550030), HT_R(0.8656312023878318), HT_R(0.9445750230732326), HT_R(0.9894009349916499)};
    const real w[8] = {HT_R(0.1894506104550685), HT_R(0.1826034150449236), HT_R(0.1691565193950025), HT_R(0.1495959888165767),
                       HT_R(0.1246289712555339), HT_R(0.0951585116824928), HT_R(0.0622535239386479), HT_R(0.0271524594117541)};
    HtAfsParams a;
    ht_afs_params(&a, eta, HT_R(0), theta);
    const real inv_ep = ht_inv_eta_prime(eta, a.sin_t, a.cos_t);
    const real inv_ct = HT_R(1) / ht_cos_theta_t(eta, a.sin_t);
    const real uc = ht_afs_split(&a);
    real3 total = ht_splat(HT_R(0));
    for (int piece = 0; piece < 2; ++piece) {
        const real lo = piece == 0 ? HT_R(0) : uc, hi = piece == 0 ? uc : HT_HALF_PI;
        if (piece == 1 && !(uc < HT_HALF_PI)) break;
        const real c = HT_R(0.5) * (lo + hi), r = HT_R(0.5) * (hi - lo);
        real3 s = ht_splat(HT_R(0));
        for (int k = 0; k < 8; ++k)
            for (int sg = -1; sg <= 1; sg += 2) {
                real su, cu;
                ht_sincos(c + (real)sg * r * x[k], &su, &cu);
                const real h = ht_clamp(su, HT_R(0), HT_R(1));
                const real f = ht_fresnel_dielectric(a.cos_t * ht_safe_sqrt(HT_R(1) - h * h), eta);
                const real hq = h * inv_ep;
                const real chord = HT_R(2) * ht_safe_sqrt(HT_R(1) - hq * hq) * inv_ct;
                const real geo = (HT_R(1) - f) * (HT_R(1) - f) * ht_inv_dphi_dh(1, h, inv_ep);
                s += ht_exp3(sigma_a * (-chord)) * (w[k] * geo * cu);
            }
        total += s * r;
    }
    return total;
}

/* AFS_TT^avg(theta) tabulated for the --indirect afs shadow rays, which need it at every fibre
 * crossing: the 2 x 16-node quadrature per channel was ~80 % of that stage's time.  Per material
 * HT_AFS_TT_TABLE_N + 1 nodes theta_i = i (pi/2) / N, 4 floats each (r, g, b, 0), filled on the
 * host with ht_afs_tt3 in double (host/fiber/afs_quadrature.cpp); linear interpolation in theta.
 * 1024 intervals (0.09 deg; 16 KB per material): AFS_TT bends sharply toward 0 over the last
 * degrees before grazing, where 256 intervals left 1e-4 of interpolation error; 1024 leave < 1e-5
 * against ht_afs_fast (tests/unit/fiber_afs_test AfsTableInterpolationError). */
#define HT_AFS_TT_TABLE_N 1024
HT_FIBER_FN real3 ht_afs_tt_lookup(HT_CONST_GLOBAL float* table, uint material, real theta) {
    HT_CONST_GLOBAL float* t = table + material * (4u * (HT_AFS_TT_TABLE_N + 1u));
    const real x = ht_clamp(theta, HT_R(0), HT_HALF_PI) * ((real)HT_AFS_TT_TABLE_N / HT_HALF_PI);
    int i = (int)x;
    i = i < HT_AFS_TT_TABLE_N - 1 ? i : HT_AFS_TT_TABLE_N - 1;
    const real f = x - (real)i;
    const real3 a = make_real3(t[4 * i], t[4 * i + 1], t[4 * i + 2]);
    const real3 b = make_real3(t[4 * i + 4], t[4 * i + 5], t[4 * i + 6]);
    return a + (b - a) * f;
}

#endif
