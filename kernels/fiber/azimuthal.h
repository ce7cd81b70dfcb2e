/* Azimuthal scattering: path geometry Phi(p, h), logistic lobes (Chiang/pbrt), wrapped Gaussians
 * (Zinke near-field blur, Marschner glints), and the exact root finder of Phi(p, h) = phi used by
 * the Marschner far field (MODEL_NOTES §3, §5, §11, §14.3-4, §14.6). */
#ifndef HT_FIBER_AZIMUTHAL_H
#define HT_FIBER_AZIMUTHAL_H

#include "fresnel.h"
#include "longitudinal.h"

/* Exit azimuth of the path with p internal segments: 2p gamma_t - 2 gamma_i + p pi. */
HT_FN real ht_phi_path(int p, real gamma_i, real gamma_t) {
    return R(2) * (real)p * gamma_t - R(2) * gamma_i + (real)p * HT_PI;
}

/* 1/|dPhi/dh| in the cancellation-free forms of MODEL_NOTES §3 (inv_ep = 1/eta').
 * Clamped to 1e4 so that the TRT caustic (where it is infinite) stays finite. */
HT_FN real ht_inv_dphi_dh_c(int p, real h, real c, real inv_ep) {
    real ep2 = R(1) / ht_max(inv_ep * inv_ep, R(1e-30));
    real q = ht_safe_sqrt(ep2 - h * h);
    real r;
    if (p == 0) {
        r = R(0.5) * c;
    } else if (p == 1) {
        r = c * q * (q + c) / (R(2) * ht_max(ep2 - R(1), R(1e-12)));
        /* ep2 huge (theta -> 90 deg): c q (q + c)/(2 ep2) -> c/2 ... bounded, fine */
    } else {
        r = c * q * (R(2) * c + q) / (R(2) * ht_max(fabs(R(4) - ep2 - R(3) * h * h), R(1e-12)));
    }
    return ht_min(r, R(1e4));
}
/* c = sqrt(1 - h^2) = cos gamma; pass it when known from gamma (no cancellation as |h| -> 1). */
HT_FN real ht_inv_dphi_dh(int p, real h, real inv_ep) {
    return ht_inv_dphi_dh_c(p, h, ht_safe_sqrt(R(1) - h * h), inv_ep);
}

/* ---------------------------------------------------------------- logistic (Chiang 2016) */

/* l(x; s) = e^{-|x|/s} / (s (1 + e^{-|x|/s})^2), evaluated with |x| so nothing overflows. */
HT_FN real ht_logistic(real x, real s) {
    real e = exp(-fabs(x) / s);
    real d = R(1) + e;
    return e / (s * d * d);
}
/* Logistic trimmed to [-pi, pi]: normaliser CDF(pi) - CDF(-pi) = tanh(pi/(2s)) = (1-e)/(1+e), e = e^{-pi/s}. */
HT_FN real ht_trimmed_logistic(real x, real s) {
    real e = exp(-HT_PI / s);
    real k = (R(1) - e) / (R(1) + e);
    return ht_logistic(x, s) / k;
}
/* Inverse CDF of the trimmed logistic: y = CDF(-pi) + u k, x = s ln(y / (1 - y)), written around
 * u - 1/2 so that neither y nor 1 - y suffers cancellation (§14.6); clamped to [-pi, pi]. */
HT_FN real ht_trimmed_logistic_sample(real u, real s) {
    real e = exp(-HT_PI / s);
    real k = (R(1) - e) / (R(1) + e);
    real d = (u - R(0.5)) * k;
    real num = ht_max(R(0.5) + d, R(1e-30)), den = ht_max(R(0.5) - d, R(1e-30));
    real x = s * ht_log(num / den);
    return ht_clamp(x, -HT_PI, HT_PI);
}

/* ---------------------------------------------------------------- wrapped Gaussian */

/* Gaussian of std sigma wrapped onto the circle, evaluated at x (any real).  Spatial sum over
 * k = -2..2 for sigma < 1.6 (truncation < 1e-20), Fourier series n <= 6 above (truncation < 1e-14). */
HT_FN real ht_wrapped_gaussian(real x, real sigma) {
    x = ht_wrap_pi(x);
    sigma = ht_max(sigma, R(1e-6));
    if (sigma < R(1.6)) {
        real g = R(0);
        for (int k = -2; k <= 2; ++k) g += ht_gaussian(x + HT_TWO_PI * (real)k, sigma);
        return g;
    }
    real sum = R(1);
    for (int n = 1; n <= 6; ++n) {
        real s, c;
        ht_sincos((real)n * x, &s, &c);
        sum += R(2) * exp(-R(0.5) * (real)(n * n) * sigma * sigma) * c;
    }
    return ht_max(sum, R(0)) * HT_INV_TWO_PI;
}

/* ---------------------------------------------------------------- Marschner root finding */

/* Phi(p, gamma) for the far field with inv_ep = 1/eta'(theta_d), gamma = gamma_i' in [-pi/2, pi/2]. */
HT_FN real ht_phi_gamma(int p, real gamma, real inv_ep) {
    real sg, cg;
    ht_sincos(gamma, &sg, &cg);
    return ht_phi_path(p, gamma, ht_asin(sg * inv_ep));
}
HT_FN real ht_dphi_dgamma(int p, real gamma, real inv_ep) {
    real sg, cg;
    ht_sincos(gamma, &sg, &cg);
    real d = sqrt(ht_max(R(1) - sg * sg * inv_ep * inv_ep, R(1e-30)));
    return R(2) * (real)p * cg * inv_ep / d - R(2);
}

/* Newton step size at which the root is accepted: ~4 ulp of the working precision. */
#ifdef HT_HOST
#define HT_ROOT_TOL R(1e-14)
#else
#define HT_ROOT_TOL R(5e-7)
#endif

/* Root of Phi(p, gamma) = target on the monotone bracket [a, b] (Phi(a) - target and Phi(b) - target
 * of opposite sign or zero), by Newton steps safeguarded with bisection; returns gamma.
 * 40 iterations: bisection alone reaches pi/2^40 ~ 1.4e-12; Newton converges in < 8 in practice. */
HT_FN real ht_phi_root(int p, real target, real inv_ep, real a, real b) {
    real fa = ht_phi_gamma(p, a, inv_ep) - target;
    real x = R(0.5) * (a + b);
    /* secant start from the bracket ends */
    real fb = ht_phi_gamma(p, b, inv_ep) - target;
    if (fabs(fb - fa) > R(1e-30)) x = ht_clamp(a - fa * (b - a) / (fb - fa), a, b);
    for (int it = 0; it < 40; ++it) {
        real fx = ht_phi_gamma(p, x, inv_ep) - target;
        if (fx == R(0)) break;
        if ((fx < R(0)) == (fa < R(0))) { a = x; fa = fx; } else { b = x; }
        real d = ht_dphi_dgamma(p, x, inv_ep);
        real xn = fabs(d) > R(1e-12) ? x - fx / d : R(0.5) * (a + b);
        if (!(xn > a && xn < b)) xn = R(0.5) * (a + b);
        if (fabs(xn - x) < HT_ROOT_TOL * (R(1) + fabs(x))) { x = xn; break; }
        x = xn;
    }
    return x;
}

/* Up to 3 roots h of Phi(p, h) = phi (mod 2 pi), with cs = cos(gamma) = sqrt(1 - h^2) computed from the
 * root angle (accurate where |h| -> 1); returns the count.  Monotone pieces:
 * R and TT: one piece [-pi/2, pi/2]; TRT with eta' < 2: split at the caustics +-gamma_c. */
HT_FN int ht_phi_roots(int p, real phi, real inv_ep, real* hs, real* cs) {
    real ga[3], gb[3];
    int pieces = 1;
    ga[0] = -HT_HALF_PI; gb[0] = HT_HALF_PI;
    if (p == 2) {
        real ep2 = R(1) / ht_max(inv_ep * inv_ep, R(1e-30));
        if (ep2 < R(4)) {
            real hc = sqrt((R(4) - ep2) / R(3));
            real gc = ht_asin(hc);
            ga[0] = -HT_HALF_PI; gb[0] = -gc;
            ga[1] = -gc; gb[1] = gc;
            ga[2] = gc; gb[2] = HT_HALF_PI;
            pieces = 3;
        }
    }
    int n = 0;
    for (int i = 0; i < pieces; ++i) {
        real fa = ht_phi_gamma(p, ga[i], inv_ep), fb = ht_phi_gamma(p, gb[i], inv_ep);
        real lo = ht_min(fa, fb), hi = ht_max(fa, fb);
        /* the range of one piece spans < 2 pi: at most one 2 pi-shift of phi lies in it */
        real t = phi + HT_TWO_PI * floor((lo - phi) * HT_INV_TWO_PI + R(1));
        if (t - HT_TWO_PI >= lo) t -= HT_TWO_PI;
        if (t < lo || t > hi) continue;
        real g = ht_phi_root(p, t, inv_ep, ga[i], gb[i]);
        real sg, cg;
        ht_sincos(g, &sg, &cg);
        cs[n] = fabs(cg);
        hs[n++] = ht_clamp(sg, R(-1), R(1));
    }
    return n;
}

#endif
