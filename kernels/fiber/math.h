/* Elementary functions for the fibre models.
 *
 * Host (real = double): the C++ standard library, i.e. correctly rounded to ~1 ulp.
 * Kernels (real = float): hand-written approximations that PoCL can vectorise (docs/POCL.md §2:
 * pow/log/atan2/acos are scalar library calls there, 6-50 ns each).  Stated errors are the
 * approximation error of the formula; float rounding (~1.2e-7 relative per operation) comes on top.
 *
 *   ht_log    exponent split + atanh series to z^9 on [sqrt(1/2), sqrt(2)):  |err| < 1e-9 (abs)
 *   ht_exp    exp (vectorises on PoCL)
 *   ht_pow    exp(b * ht_log(a)) for a > 0, 0 for a <= 0
 *   ht_atan2  Abramowitz & Stegun 4.4.49 (degree-16 odd polynomial on [0,1]): |err| <= 2e-8 rad
 *   ht_asin   ht_atan2(x, sqrt(1 - x^2)) with the argument clamped to [-1, 1]
 *   ht_sincos reduction to [-pi, pi] then [-pi/2, pi/2]; Taylor to x^11 / x^12: |err| < 6e-8
 */
#ifndef HT_FIBER_MATH_H
#define HT_FIBER_MATH_H

#include "../compat.h"

#define HT_HALF_PI HT_R(1.57079632679489661923)
#define HT_LN2 HT_R(0.69314718055994530942)

HT_FIBER_FN real ht_log(real x) {
#ifdef HT_HOST
    return log(ht_max(x, HT_R(1e-300)));
#else
    x = fmax(x, 1.17549435e-38f); /* smallest normal float: no denormal bit patterns */
    uint b = as_uint(x);
    int e = (int)((b >> 23) & 0xffu) - 127;
    float m = as_float((b & 0x007fffffu) | 0x3f800000u); /* [1, 2) */
    int big = m > 1.41421356f;
    m = big ? m * 0.5f : m;
    e = big ? e + 1 : e;
    float z = (m - 1.0f) / (m + 1.0f); /* |z| <= 0.1716 */
    float z2 = z * z;
    float p = z * (2.0f + z2 * (0.66666666667f + z2 * (0.4f + z2 * (0.28571428571f + z2 * 0.22222222222f))));
    return p + (float)e * 0.69314718056f;
#endif
}

HT_FIBER_FN real ht_exp(real x) { return exp(x); }

/* a^b for a > 0; 0 for a <= 0 (b > 0 assumed by callers). */
HT_FIBER_FN real ht_pow(real a, real b) { return a > HT_R(0) ? exp(b * ht_log(a)) : HT_R(0); }

HT_FIBER_FN real ht_atan_unit(real z) { /* z in [0, 1] */
    real z2 = z * z;
    return z * (HT_R(1.0) + z2 * (HT_R(-0.3333314528) + z2 * (HT_R(0.1999355085) + z2 * (HT_R(-0.1420889944) +
               z2 * (HT_R(0.1065626393) + z2 * (HT_R(-0.0752896400) + z2 * (HT_R(0.0429096138) +
               z2 * (HT_R(-0.0161657367) + z2 * HT_R(0.0028662257)))))))));
}

HT_FIBER_FN real ht_atan2(real y, real x) {
#ifdef HT_HOST
    return atan2(y, x);
#else
    float ax = fabs(x), ay = fabs(y);
    float mx = fmax(ax, ay), mn = fmin(ax, ay);
    float z = mn / fmax(mx, 1e-30f);
    float a = ht_atan_unit(z);
    a = ay > ax ? HT_HALF_PI - a : a;
    a = x < 0.0f ? HT_PI - a : a;
    return y < 0.0f ? -a : a;
#endif
}

HT_FIBER_FN real ht_asin(real x) {
    x = ht_clamp(x, HT_R(-1), HT_R(1));
#ifdef HT_HOST
    return asin(x);
#else
    return ht_atan2(x, sqrt(fmax(1.0f - x * x, 0.0f)));
#endif
}

/* sin and cos of x (any finite x). */
HT_FIBER_FN void ht_sincos(real x, real* s, real* c) {
#ifdef HT_HOST
    *s = sin(x);
    *c = cos(x);
#else
    float k = floor(x * HT_INV_TWO_PI + 0.5f);
    float r = (x - k * 6.28318530718f); /* [-pi, pi] (float rounding of 2*pi k ignored) */
    float sg = 1.0f;
    /* fold to [-pi/2, pi/2]: sin(pi - r) = sin r, cos(pi - r) = -cos r */
    int hi = r > HT_HALF_PI, lo = r < -HT_HALF_PI;
    r = hi ? HT_PI - r : (lo ? -HT_PI - r : r);
    sg = (hi || lo) ? -1.0f : 1.0f;
    float r2 = r * r;
    float sn = r * (1.0f + r2 * (-1.6666666667e-1f + r2 * (8.3333333333e-3f + r2 * (-1.9841269841e-4f +
               r2 * (2.7557319224e-6f + r2 * -2.5052108385e-8f)))));
    float cs = 1.0f + r2 * (-0.5f + r2 * (4.1666666667e-2f + r2 * (-1.3888888889e-3f + r2 * (2.4801587302e-5f +
               r2 * (-2.7557319224e-7f + r2 * 2.0876756988e-9f)))));
    *s = sn;
    *c = sg * cs;
#endif
}

HT_FIBER_FN real3 ht_exp3(real3 a) { return make_real3(exp(a.x), exp(a.y), exp(a.z)); }
HT_FIBER_FN real3 ht_max3s(real3 a, real b) { return make_real3(ht_max(a.x, b), ht_max(a.y, b), ht_max(a.z, b)); }
HT_FIBER_FN real3 ht_div3(real3 a, real3 b) { return make_real3(a.x / b.x, a.y / b.y, a.z / b.z); }
/* The largest of the three channels: what roulette, the light threshold and the clamp judge. */
HT_FIBER_FN real ht_max_channel(real3 c) { return ht_max(c.x, ht_max(c.y, c.z)); }
HT_FIBER_FN real ht_luminance(real3 c) { return HT_R(0.2126) * c.x + HT_R(0.7152) * c.y + HT_R(0.0722) * c.z; }
HT_FIBER_FN real3 ht_splat(real a) { return make_real3(a, a, a); }
HT_FIBER_FN real3 ht_load3(const float* p) { return make_real3(p[0], p[1], p[2]); }
/* Replace NaN by 0 and clamp to [0, HT_REAL_MAX]: the last line of defence of every model. */
HT_FIBER_FN real ht_sanitize(real x) { return (x >= HT_R(0) && x <= HT_REAL_MAX) ? x : (x > HT_REAL_MAX ? HT_REAL_MAX : HT_R(0)); }
HT_FIBER_FN real3 ht_sanitize3(real3 a) { return make_real3(ht_sanitize(a.x), ht_sanitize(a.y), ht_sanitize(a.z)); }
/* Wrap an angle to [-pi, pi]. */
HT_FIBER_FN real ht_wrap_pi(real x) { return x - HT_TWO_PI * floor((x + HT_PI) * HT_INV_TWO_PI); }

/* Angles of a unit direction in the fibre frame (docs/MODEL.md §1): sin theta = w.x. */
HT_FIBER_FN void ht_theta(real3 w, real* sin_t, real* cos_t) {
    real s = ht_clamp(w.x, HT_R(-1), HT_R(1));
    *sin_t = s;
    *cos_t = ht_safe_sqrt(HT_R(1) - s * s);
}
/* phi_i - phi_o without two atan2 calls; 0 when either direction is along the tangent. */
HT_FIBER_FN real ht_relative_phi(real3 wo, real3 wi) {
    real y = wi.z * wo.y - wi.y * wo.z;
    real x = wi.y * wo.y + wi.z * wo.z;
    return ht_atan2(y, x);
}
/* Direction with sin theta = st, cos theta = ct and azimuth phi_o + dphi, given wo. */
HT_FIBER_FN real3 ht_dir_from(real3 wo, real st, real ct, real dphi) {
    real co = sqrt(wo.y * wo.y + wo.z * wo.z);
    real cpo = co > HT_R(1e-12) ? wo.y / co : HT_R(1);
    real spo = co > HT_R(1e-12) ? wo.z / co : HT_R(0);
    real sd, cd;
    ht_sincos(dphi, &sd, &cd);
    real cp = cpo * cd - spo * sd, sp = spo * cd + cpo * sd;
    return make_real3(st, ct * cp, ct * sp);
}

#endif /* HT_FIBER_MATH_H */
