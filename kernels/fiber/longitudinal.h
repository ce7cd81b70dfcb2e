/* Longitudinal scattering functions (docs/MODEL.md §9, §10, §12.5).
 *
 * d'Eon 2011 M_p in log form with an exponentially scaled Bessel function i0e(x) = e^-x I0(x):
 *   log M = log i0e(a) + (cos(theta_i + theta_o) - 1)/v - log v - log1p(-e^{-2/v}),
 *   a = cos theta_i cos theta_o / v.  Normalised: integral of M cos theta_i dtheta_i = 1.
 * The sign convention is pbrt's: the specular cone is theta_i = -theta_o.
 *
 * i0e: host = power series (x <= 15) / asymptotic series (x > 15), relative error < 1e-15.
 *      float = Abramowitz & Stegun 9.8.1 / 9.8.2: relative error < 1.6e-7 (x <= 3.75), < 4.8e-7 above. */
#ifndef HT_FIBER_LONGITUDINAL_H
#define HT_FIBER_LONGITUDINAL_H

#include "math.h"

#ifndef HT_HOST
/* The float i0e(x) (x >= 0) as factor * exp(*shift): I0(x) e^-x = P(x) e^-x for x <= 3.75, Q(x) / sqrt(x)
 * above, so *shift is -x or 0.  M_p folds the shift into its own exponent (ht_mp_n): one exp per
 * M_p instead of two, and no exp for the branch not taken. */
HT_FIBER_FN float ht_i0e_factor(float x, float* shift) {
    const float t = x * (1.0f / 3.75f);
    const float t2 = t * t;
    const float small = 1.0f + t2 * (3.5156229f + t2 * (3.0899424f + t2 * (1.2067492f + t2 * (0.2659732f +
                        t2 * (0.0360768f + t2 * 0.0045813f)))));
    const float u = 3.75f / fmax(x, 3.75f);
    const float large = (0.39894228f + u * (0.01328592f + u * (0.00225319f + u * (-0.00157565f + u * (0.00916281f +
                        u * (-0.02057706f + u * (0.02635537f + u * (-0.01647633f + u * 0.00392377f)))))))) *
                        rsqrt(fmax(x, 3.75f));
    *shift = x <= 3.75f ? -x : 0.0f;
    return x <= 3.75f ? small : large;
}
#endif
HT_FIBER_FN real ht_i0e(real x) {
    x = fabs(x);
#ifdef HT_HOST
    if (x <= 15.0) {
        double q = 0.25 * x * x, term = 1.0, sum = 1.0;
        for (int k = 1; k < 200; ++k) {
            term *= q / ((double)k * (double)k);
            sum += term;
            if (term < 1e-17 * sum) break;
        }
        return sum * std::exp(-x);
    }
    double inv8x = 1.0 / (8.0 * x), term = 1.0, sum = 1.0;
    for (int k = 1; k < 40; ++k) {
        double f = (2.0 * k - 1.0);
        term *= f * f * inv8x / k;
        sum += term;
        if (term < 1e-17 * sum) break;
    }
    return sum / std::sqrt(2.0 * HT_PI * x);
#else
    float shift;
    return ht_i0e_factor(x, &shift) * exp(shift);
#endif
}

/* log I0(x) for x >= 0. */
HT_FIBER_FN real ht_log_i0(real x) { return ht_log(ht_i0e(x)) + fabs(x); }

/* -log v - log1p(-e^{-2/v}): the log of M_p's normaliser 1/(2 v sinh(1/v)) without the e^{-1/v}. */
HT_FIBER_FN real ht_mp_log_norm(real v) {
    v = ht_max(v, HT_R(1e-7));
    real e2 = exp(-HT_R(2) / v);
#ifdef HT_HOST
    return -log(v) - log1p(-e2);
#else
    return -ht_log(v) - ht_log(HT_R(1) - e2);
#endif
}

/* d'Eon M_p(theta_i, theta_o; v) from sines/cosines (cosines >= 0), given log_norm = ht_mp_log_norm(v):
 *   M = i0e(a) exp((cos(theta_i + theta_o) - 1)/v + log_norm)   (no overflow: the exponent is <= log_norm).
 * Finite for v >= 1e-7.  _parts: M = returned factor * exp(*exponent), for a caller that multiplies
 * M by another exponential and pays one exp for both (kernels/fiber/zinke.h). */
HT_FIBER_FN real ht_mp_n_parts(real cos_i, real sin_i, real cos_o, real sin_o, real v, real log_norm, real* exponent) {
    v = ht_max(v, HT_R(1e-7));
    real inv_v = HT_R(1) / v;
    real a = cos_i * cos_o * inv_v;
    real C = cos_i * cos_o - sin_i * sin_o; /* cos(theta_i + theta_o) */
    real S = sin_i * cos_o + cos_i * sin_o; /* sin(theta_i + theta_o) */
    real cm1 = C > HT_R(0) ? -S * S / (HT_R(1) + C) : C - HT_R(1); /* cos - 1 without cancellation */
#ifdef HT_HOST
    *exponent = ht_min(cm1 * inv_v + log_norm, HT_R(80));
    return ht_i0e(a);
#else
    float shift;
    const float f = ht_i0e_factor(a, &shift);
    *exponent = ht_min(cm1 * inv_v + log_norm, HT_R(80)) + shift;
    return f;
#endif
}
HT_FIBER_FN real ht_mp_n(real cos_i, real sin_i, real cos_o, real sin_o, real v, real log_norm) {
    real e;
    const real f = ht_mp_n_parts(cos_i, sin_i, cos_o, sin_o, v, log_norm, &e);
    return f * exp(e);
}
HT_FIBER_FN real ht_mp(real cos_i, real sin_i, real cos_o, real sin_o, real v) {
    return ht_mp_n(cos_i, sin_i, cos_o, sin_o, v, ht_mp_log_norm(v));
}

/* d'Eon 2013 sampling of theta_i around the (tilted) cone of theta_o' in the stable form:
 * cos(vartheta) = 1 + v ln(u1 + (1 - u1) e^{-2/v}),  sin theta_i = -cos(vt) sin theta_o' + sin(vt) cos(2 pi u2) cos theta_o'.
 * Exactly distributed as M_p(., theta_o'; v) cos theta_i.  u1 = 0 is fine unless e^{-2/v} underflows
 * (v < 0.0027 double, 0.023 float): u1 is floored at 1e-30 (pbrt floors at 1e-5, which biases the
 * lowest 1e-5 of the cone-angle distribution). */
HT_FIBER_FN void ht_mp_sample(real u1, real u2, real sin_o, real cos_o, real v, real* sin_i, real* cos_i) {
    v = ht_max(v, HT_R(1e-7));
    u1 = ht_max(u1, HT_R(1e-30));
    real cvt = HT_R(1) + v * ht_log(u1 + (HT_R(1) - u1) * exp(-HT_R(2) / v));
    cvt = ht_clamp(cvt, HT_R(-1), HT_R(1));
    real svt = ht_safe_sqrt(HT_R(1) - cvt * cvt);
    real s2, c2;
    ht_sincos(HT_TWO_PI * u2, &s2, &c2);
    real si = ht_clamp(-cvt * sin_o + svt * c2 * cos_o, HT_R(-1), HT_R(1));
    *sin_i = si;
    *cos_i = ht_safe_sqrt(HT_R(1) - si * si);
}

/* Unit-area Gaussian with standard deviation sigma; _parts: as factor * exp(*exponent). */
HT_FIBER_FN real ht_gaussian_parts(real x, real sigma, real* exponent) {
    real is = HT_R(1) / ht_max(sigma, HT_R(1e-7));
    *exponent = -HT_R(0.5) * x * x * is * is;
    return HT_R(0.39894228040143267794) * is;
}
HT_FIBER_FN real ht_gaussian(real x, real sigma) {
    real e;
    const real f = ht_gaussian_parts(x, sigma, &e);
    return f * exp(e);
}

/* Standard normal deviate from two uniforms (Box-Muller). */
HT_FIBER_FN real ht_normal_from(real u1, real u2) {
    u1 = ht_max(u1, HT_R(1e-12));
    real s, c;
    ht_sincos(HT_TWO_PI * u2, &s, &c);
    return sqrt(-HT_R(2) * ht_log(u1)) * c;
}

/* Two independent standard normal deviates from two uniforms (Box-Muller). */
HT_FIBER_FN void ht_normal_pair(real u1, real u2, real* n1, real* n2) {
    u1 = ht_max(u1, HT_R(1e-12));
    real s, c;
    ht_sincos(HT_TWO_PI * u2, &s, &c);
    real r = sqrt(-HT_R(2) * ht_log(u1));
    *n1 = r * c;
    *n2 = r * s;
}

#endif
