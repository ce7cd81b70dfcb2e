/* Azimuthal scattering: path geometry Phi(p, h), logistic lobes (Chiang/pbrt), wrapped Gaussians
 * (Zinke near-field blur, Marschner glints), and the exact root finder of Phi(p, h) = phi used by
 * the Marschner far field (docs/MODEL.md §3, §5, §11, §12.3-4, §12.6). */
#ifndef HT_FIBER_AZIMUTHAL_H
#define HT_FIBER_AZIMUTHAL_H

#include "fresnel.h"
#include "longitudinal.h"

/* Exit azimuth of the path with p internal segments: 2p gamma_t - 2 gamma_i + p pi. */
HT_FIBER_FN real ht_phi_path(int p, real gamma_i, real gamma_t) {
    return HT_R(2) * (real)p * gamma_t - HT_R(2) * gamma_i + (real)p * HT_PI;
}

/* 1/|dPhi/dh| in the cancellation-free forms of docs/MODEL.md §3 (inv_ep = 1/eta').
 * Clamped to 1e4 so that the TRT caustic (where it is infinite) stays finite. */
HT_FIBER_FN real ht_inv_dphi_dh_c(int p, real h, real c, real inv_ep) {
    real ep2 = HT_R(1) / ht_max(inv_ep * inv_ep, HT_R(1e-30));
    real q = ht_safe_sqrt(ep2 - h * h);
    real r;
    if (p == 0) {
        r = HT_R(0.5) * c;
    } else if (p == 1) {
        r = c * q * (q + c) / (HT_R(2) * ht_max(ep2 - HT_R(1), HT_R(1e-12)));
        /* ep2 huge (theta -> 90 deg): c q (q + c)/(2 ep2) -> c/2 ... bounded, fine */
    } else {
        r = c * q * (HT_R(2) * c + q) / (HT_R(2) * ht_max(fabs(HT_R(4) - ep2 - HT_R(3) * h * h), HT_R(1e-12)));
    }
    return ht_min(r, HT_R(1e4));
}
/* c = sqrt(1 - h^2) = cos gamma; pass it when known from gamma (no cancellation as |h| -> 1). */
HT_FIBER_FN real ht_inv_dphi_dh(int p, real h, real inv_ep) {
    return ht_inv_dphi_dh_c(p, h, ht_safe_sqrt(HT_R(1) - h * h), inv_ep);
}

/* ---------------------------------------------------------------- logistic (Chiang 2016) */

/* l(x; s) = e^{-|x|/s} / (s (1 + e^{-|x|/s})^2), evaluated with |x| so nothing overflows. */
HT_FIBER_FN real ht_logistic(real x, real s) {
    real e = exp(-fabs(x) / s);
    real d = HT_R(1) + e;
    return e / (s * d * d);
}
/* Logistic trimmed to [-pi, pi]: normaliser CDF(pi) - CDF(-pi) = tanh(pi/(2s)) = (1-e)/(1+e), e = e^{-pi/s}. */
HT_FIBER_FN real ht_trimmed_logistic(real x, real s) {
    real e = exp(-HT_PI / s);
    real k = (HT_R(1) - e) / (HT_R(1) + e);
    return ht_logistic(x, s) / k;
}
/* Inverse CDF of the trimmed logistic: y = CDF(-pi) + u k, x = s ln(y / (1 - y)), written around
 * u - 1/2 so that neither y nor 1 - y suffers cancellation (§14.6); clamped to [-pi, pi]. */
HT_FIBER_FN real ht_trimmed_logistic_sample(real u, real s) {
    real e = exp(-HT_PI / s);
    real k = (HT_R(1) - e) / (HT_R(1) + e);
    real d = (u - HT_R(0.5)) * k;
    real num = ht_max(HT_R(0.5) + d, HT_R(1e-30)), den = ht_max(HT_R(0.5) - d, HT_R(1e-30));
    real x = s * ht_log(num / den);
    return ht_clamp(x, -HT_PI, HT_PI);
}

/* ---------------------------------------------------------------- wrapped Gaussian */

/* Gaussian of std sigma wrapped onto the circle at x (any real), as factor * exp(*exponent): for
 * sigma < 1.6 the spatial sum over the images k = -2..2 (truncation < 1e-20), the exponent that of
 * the nearest image (x wrapped to [-pi, pi], the largest term) and the other images relative to it
 * (each <= 1: |x + 2 pi k| >= |x|), so that a caller multiplying by another exponential pays one
 * exp for both (kernels/fiber/zinke.h); above, the Fourier series n <= 6 (truncation < 1e-14) with
 * exponent 0.  In float an image whose relative exponent is below -110 is exactly 0 next to the
 * nearest one (exp underflows below -103.97), so the kernels skip it: for the narrow azimuthal lobes
 * of hair (zinke's sigma ~ 0.2 rad) only the nearest image is left. */
#define HT_WRAPPED_GAUSSIAN_SKIP HT_R(220) /* (d / sigma)^2 above it: exponent below -110 */
HT_FIBER_FN real ht_wrapped_gaussian_parts(real x, real sigma, real* exponent) {
    x = ht_wrap_pi(x);
    sigma = ht_max(sigma, HT_R(1e-6));
    if (!(sigma < HT_R(1.6))) {
        real sum = HT_R(1);
        for (int n = 1; n <= 6; ++n) {
            real s, c;
            ht_sincos((real)n * x, &s, &c);
            sum += HT_R(2) * exp(-HT_R(0.5) * (real)(n * n) * sigma * sigma) * c;
        }
        *exponent = HT_R(0);
        return ht_max(sum, HT_R(0)) * HT_INV_TWO_PI;
    }
    const real is = HT_R(1) / sigma;
    real images = HT_R(1);
    for (int k = -2; k <= 2; ++k) {
        if (k == 0) continue;
        /* (x + 2 pi k)^2 - x^2 without cancellation */
        const real dd = HT_TWO_PI * (real)k * (HT_R(2) * x + HT_TWO_PI * (real)k);
#ifdef HT_OPENCL
        if (dd > HT_WRAPPED_GAUSSIAN_SKIP * sigma * sigma) continue;
#endif
        images += exp(-HT_R(0.5) * dd * is * is);
    }
    *exponent = -HT_R(0.5) * x * x * is * is;
    return HT_R(0.39894228040143267794) * is * images;
}
HT_FIBER_FN real ht_wrapped_gaussian(real x, real sigma) {
    real e;
    const real f = ht_wrapped_gaussian_parts(x, sigma, &e);
    return f * exp(e);
}

/* ---------------------------------------------------------------- Marschner root finding */

/* Phi(p, gamma) for the far field with inv_ep = 1/eta'(theta_d), gamma = gamma_i' in [-pi/2, pi/2], and
 * dPhi/dgamma; the _sc forms take sg, cg = sin, cos gamma (the root finder needs both per step). */
HT_FIBER_FN real ht_phi_gamma_sc(int p, real gamma, real sg, real inv_ep) {
    return ht_phi_path(p, gamma, ht_asin(sg * inv_ep));
}
HT_FIBER_FN real ht_dphi_dgamma_sc(int p, real sg, real cg, real inv_ep) {
    real d = sqrt(ht_max(HT_R(1) - sg * sg * inv_ep * inv_ep, HT_R(1e-30)));
    return HT_R(2) * (real)p * cg * inv_ep / d - HT_R(2);
}
HT_FIBER_FN real ht_phi_gamma(int p, real gamma, real inv_ep) {
    real sg, cg;
    ht_sincos(gamma, &sg, &cg);
    return ht_phi_gamma_sc(p, gamma, sg, inv_ep);
}

/* Newton step size at which the root is accepted: ~4 ulp of the working precision. */
#ifdef HT_HOST
#define HT_ROOT_TOL HT_R(1e-14)
#else
#define HT_ROOT_TOL HT_R(5e-7)
#endif

/* Real roots of Marschner's cubic approximation (docs/MODEL.md §3)
 *   Phi^(p, gamma) = (6 p c/pi - 2) gamma - (8 p c/pi^3) gamma^3 + p pi = target,  c = asin(1/eta'),
 * written as gamma^3 + P gamma + Q = 0 (trigonometric form for three roots, Cardano for one).
 * Returns the count (0..3).  Used only as Newton starting points. */
HT_FIBER_FN int ht_phi_cubic_roots_c(int p, real target, real c, real* g) {
    if (p == 0) { g[0] = -HT_R(0.5) * target; return 1; }
    real A = -HT_R(8) * (real)p * c / (HT_PI * HT_PI * HT_PI);
    real B = HT_R(6) * (real)p * c / HT_PI - HT_R(2);
    real D = (real)p * HT_PI - target;
    real P = B / A, Q = D / A;
    real disc = Q * Q * HT_R(0.25) + P * P * P / HT_R(27);
    if (disc < HT_R(0) && P < HT_R(0)) {
        real r = sqrt(-P / HT_R(3));
        real x = ht_clamp(-Q * HT_R(0.5) / (r * r * r), HT_R(-1), HT_R(1)); /* cos(3 phi) */
        real th = ht_atan2(ht_safe_sqrt(HT_R(1) - x * x), x) / HT_R(3);
        for (int k = 0; k < 3; ++k) {
            real s, co;
            ht_sincos(th - HT_TWO_PI * (real)k / HT_R(3), &s, &co);
            g[k] = HT_R(2) * r * co;
        }
        return 3;
    }
    real sq = sqrt(ht_max(disc, HT_R(0)));
    real a = -Q * HT_R(0.5) + sq, b = -Q * HT_R(0.5) - sq;
    real ca = a >= HT_R(0) ? ht_pow(a, HT_R(1) / HT_R(3)) : -ht_pow(-a, HT_R(1) / HT_R(3));
    real cb = b >= HT_R(0) ? ht_pow(b, HT_R(1) / HT_R(3)) : -ht_pow(-b, HT_R(1) / HT_R(3));
    g[0] = ca + cb;
    return 1;
}
HT_FIBER_FN int ht_phi_cubic_roots(int p, real target, real inv_ep, real* g) {
    return ht_phi_cubic_roots_c(p, target, ht_asin(inv_ep), g);
}

/* Root of Phi(p, gamma) = target on the monotone bracket [a, b] (Phi(a) - target and Phi(b) - target
 * of opposite sign or zero): starts at the root gc[0..nc) of Marschner's cubic approximation that
 * lies inside the bracket and is closest in Phi (else the secant of the bracket ends), then Newton
 * steps safeguarded with bisection on the exact Phi.  Bisection alone would reach pi/2^40 ~ 1.4e-12
 * within the 40-iteration cap; Newton converges in 2-5 steps in practice.  Phi and its derivative
 * share one sincos per step, and the starting root's Phi is not computed twice: this loop was the
 * shade kernel's largest fibre-model cost (docs/PERFORMANCE.md §3). */
HT_FIBER_FN real ht_phi_root(int p, real target, real inv_ep, real a, real b, real phi_a, real phi_b, const real* gc,
                       int nc) {
    real fa = phi_a - target; /* Phi(a), Phi(b) known to the caller */
    real fb = phi_b - target;
    real x = HT_R(0.5) * (a + b);
    if (fabs(fb - fa) > HT_R(1e-30)) x = ht_clamp(a - fa * (b - a) / (fb - fa), a, b);
    real best = HT_REAL_MAX, f_best = HT_R(0);
    for (int k = 0; k < nc; ++k) {
        if (gc[k] >= a && gc[k] <= b) {
            real f = ht_phi_gamma(p, gc[k], inv_ep) - target;
            real d = fabs(f);
            if (d < best) { best = d; x = gc[k]; f_best = f; }
        }
    }
    int known = best < HT_REAL_MAX; /* Phi(x) - target is f_best */
    for (int it = 0; it < 40; ++it) {
        real sg, cg;
        ht_sincos(x, &sg, &cg);
        real fx = known ? f_best : ht_phi_gamma_sc(p, x, sg, inv_ep) - target;
        known = 0;
        if (fx == HT_R(0)) break;
        if ((fx < HT_R(0)) == (fa < HT_R(0))) { a = x; fa = fx; } else { b = x; }
        real d = ht_dphi_dgamma_sc(p, sg, cg, inv_ep);
        real xn = fabs(d) > HT_R(1e-12) ? x - fx / d : HT_R(0.5) * (a + b);
        if (!(xn > a && xn < b)) xn = HT_R(0.5) * (a + b);
        if (fabs(xn - x) < HT_ROOT_TOL * (HT_R(1) + fabs(x))) { x = xn; break; }
        x = xn;
    }
    return x;
}
/* Up to 3 roots h of Phi(p, h) = phi (mod 2 pi), with cs = cos(gamma) = sqrt(1 - h^2) computed from the
 * root angle (accurate where |h| -> 1); returns the count.  Monotone pieces:
 * R and TT: one piece [-pi/2, pi/2]; TRT with eta' < 2: split at the caustics +-gamma_c. */
HT_FIBER_FN int ht_phi_roots(int p, real phi, real inv_ep, real* hs, real* cs) {
    real ga[3], gb[3], pa[3], pb[3];
    int pieces = 1;
    /* ends in closed form: Phi(p, +-pi/2) = +-(2 p c - pi) + p pi, c = asin(1/eta') */
    real c = ht_asin(inv_ep);
    real pp = (real)p * HT_PI, e = HT_R(2) * (real)p * c - HT_PI;
    ga[0] = -HT_HALF_PI; gb[0] = HT_HALF_PI;
    pa[0] = pp - e; pb[0] = pp + e;
    if (p == 2) {
        real ep2 = HT_R(1) / ht_max(inv_ep * inv_ep, HT_R(1e-30));
        if (ep2 < HT_R(4)) {
            real hc = sqrt((HT_R(4) - ep2) / HT_R(3));
            real gc = ht_asin(hc);
            real fc = HT_R(4) * ht_asin(hc * inv_ep) - HT_R(2) * gc; /* Phi(2, gc) - 2 pi */
            ga[0] = -HT_HALF_PI; gb[0] = -gc; pb[0] = pp - fc;
            ga[1] = -gc; gb[1] = gc; pa[1] = pp - fc; pb[1] = pp + fc;
            ga[2] = gc; gb[2] = HT_HALF_PI; pa[2] = pp + fc; pb[2] = pp + e;
            pieces = 3;
        }
    }
    int n = 0;
    real gc[3], t_cubic = HT_REAL_MAX; /* the cubic's roots for target t_cubic, shared by the pieces */
    int nc = 0;
    for (int i = 0; i < pieces; ++i) {
        real fa = pa[i], fb = pb[i];
        real lo = ht_min(fa, fb), hi = ht_max(fa, fb);
        /* the range of one piece spans < 2 pi: at most one 2 pi-shift of phi lies in it */
        real t = phi + HT_TWO_PI * floor((lo - phi) * HT_INV_TWO_PI + HT_R(1));
        if (t - HT_TWO_PI >= lo) t -= HT_TWO_PI;
        if (t < lo || t > hi) continue;
        if (t != t_cubic) { nc = ht_phi_cubic_roots_c(p, t, c, gc); t_cubic = t; }
        real g = ht_phi_root(p, t, inv_ep, ga[i], gb[i], fa, fb, gc, nc);
        real sg, cg;
        ht_sincos(g, &sg, &cg);
        cs[n] = fabs(cg);
        hs[n++] = ht_clamp(sg, HT_R(-1), HT_R(1));
    }
    return n;
}

#endif
