/* Environment light: evaluation, importance sampling and pdf (lat-long map or uniform).
 *
 * Tables (host/render/environment.cpp): texels = rgb radiance per pixel (float4, w unused);
 * marginal = CDF over rows (height + 1 entries, 0 .. 1) of row weight sum * sin(theta);
 * conditional = per row a CDF over columns (width + 1 entries each).  The pdf over the sphere is
 * p(u,v) / (2 pi^2 sin theta), p(u,v) = W H * f(u,v) / sum f. */
#ifndef HT_ENVIRONMENT_H
#define HT_ENVIRONMENT_H

#include "types.h"

HT_FN real3 ht_env_texel(const HtEnvironment* e, HT_CONST_GLOBAL float* texels, uint x, uint y) {
    uint i = 4u * (y * e->width + x);
    return make_real3(texels[i] * e->scale[0], texels[i + 1u] * e->scale[1], texels[i + 2u] * e->scale[2]);
}

HT_FN void ht_env_dir_to_pixel(const HtEnvironment* e, real3 d, uint* x, uint* y, real* sin_theta) {
    real u = HT_R(0.5) + atan2(d.x, -d.z) * HT_INV_TWO_PI;
    real cos_t = ht_clamp(d.y, HT_R(-1), HT_R(1));
    real v = ht_safe_acos(cos_t) * HT_INV_PI;
    *sin_theta = ht_safe_sqrt(HT_R(1) - cos_t * cos_t);
    uint xi = (uint)ht_max(HT_R(0), floor(u * (real)e->width));
    uint yi = (uint)ht_max(HT_R(0), floor(v * (real)e->height));
    *x = xi < e->width ? xi : e->width - 1u;
    *y = yi < e->height ? yi : e->height - 1u;
}

/* Radiance arriving from direction d (pointing away from the scene). */
HT_FN real3 ht_env_eval(const HtEnvironment* e, HT_CONST_GLOBAL float* texels, real3 d) {
    if (!e->enabled) return make_real3(0, 0, 0);
    if (!e->has_map) return make_real3(e->scale[0], e->scale[1], e->scale[2]);
    uint x, y;
    real st;
    ht_env_dir_to_pixel(e, d, &x, &y, &st);
    return ht_env_texel(e, texels, x, y);
}

/* Largest index i in [0, n) with cdf[i] <= u (cdf has n + 1 entries from 0 to 1). */
HT_FN uint ht_cdf_find(HT_CONST_GLOBAL float* cdf, uint n, real u) {
    uint lo = 0u, hi = n;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) >> 1;
        if ((real)cdf[mid] <= u) lo = mid; else hi = mid;
    }
    return lo;
}

HT_FN real ht_env_pdf(const HtEnvironment* e, HT_CONST_GLOBAL float* marginal,
                      HT_CONST_GLOBAL float* conditional, real3 d) {
    if (!e->enabled) return HT_R(0);
    if (!e->has_map) return HT_INV_FOUR_PI;
    uint x, y;
    real st;
    ht_env_dir_to_pixel(e, d, &x, &y, &st);
    if (!(st > HT_R(1e-6))) return HT_R(0);
    HT_CONST_GLOBAL float* row = conditional + y * (e->width + 1u);
    real p_row = (real)(marginal[y + 1u] - marginal[y]) * (real)e->height;
    real p_col = (real)(row[x + 1u] - row[x]) * (real)e->width;
    return p_row * p_col / (HT_R(2) * HT_PI * HT_PI * st);
}

HT_FN int ht_env_sample(const HtEnvironment* e, HT_CONST_GLOBAL float* texels,
                        HT_CONST_GLOBAL float* marginal, HT_CONST_GLOBAL float* conditional,
                        real u, real v, real3* wi, real3* le, real* pdf) {
    if (!e->enabled) return 0;
    if (!e->has_map) {
        real z = HT_R(1) - HT_R(2) * u;
        real r = ht_safe_sqrt(HT_R(1) - z * z);
        real phi = HT_TWO_PI * v;
        *wi = make_real3(r * cos(phi), z, r * sin(phi));
        *le = make_real3(e->scale[0], e->scale[1], e->scale[2]);
        *pdf = HT_INV_FOUR_PI;
        return 1;
    }
    uint y = ht_cdf_find(marginal, e->height, v);
    real r0 = (real)marginal[y], r1 = (real)marginal[y + 1u];
    real dv = r1 > r0 ? (v - r0) / (r1 - r0) : HT_R(0.5);
    HT_CONST_GLOBAL float* row = conditional + y * (e->width + 1u);
    uint x = ht_cdf_find(row, e->width, u);
    real c0 = (real)row[x], c1 = (real)row[x + 1u];
    real du = c1 > c0 ? (u - c0) / (c1 - c0) : HT_R(0.5);
    real fu = ((real)x + du) / (real)e->width;
    real fv = ((real)y + dv) / (real)e->height;
    real phi = (fu - HT_R(0.5)) * HT_TWO_PI;
    real theta = fv * HT_PI;
    real st = sin(theta);
    if (!(st > HT_R(1e-6))) return 0;
    /* inverse of u = 0.5 + atan2(d.x, -d.z) / 2pi */
    *wi = make_real3(st * sin(phi), cos(theta), -st * cos(phi));
    *le = ht_env_texel(e, texels, x, y);
    real p_row = (r1 - r0) * (real)e->height;
    real p_col = (c1 - c0) * (real)e->width;
    *pdf = p_row * p_col / (HT_R(2) * HT_PI * HT_PI * st);
    return *pdf > HT_R(0);
}

#endif
