/* Dual scattering (Zinke, Yuksel, Weber, Hauber 2008; docs/MODEL.md §13): multiple scattering in
 * hair split into a global part -- light that reached the shading point through n fibres, each
 * letting a_f(theta) of it through forwards and widening it longitudinally by beta_f^2 -- and a
 * local part, the back-scattering of the fibres around the shading point, closed forms in the
 * per-fibre averages a_f, a_b, alpha_f/b, beta_f/b.
 *
 * The per-fibre averages are the smooth-fibre energy partition of the material's own lobes: lobe p
 * leaves a fibre lit at inclination theta with A_p(h) (docs/MODEL.md §4; chiang's residual A_3 as
 * in §11) towards the exit azimuth Phi(p, h) (§3); "forward" is |Phi| > pi/2 (phi = 0 sends light
 * back to the light).  Per unit offset over h in [0, 1] (h and -h mirror each other):
 *     a_f,p(theta) = int_0^1 A_p(h) [|Phi(p, h)| > pi/2] dh,     a_b,p the rest,
 * chiang's residual half each way (its azimuth is uniform).  Azimuthal roughness, the marschner
 * caustic terms and eccentricity are left out of the averages: they move light within a lobe,
 * not between the halves, to first order.  The shifts and widths of the lobes are the model's own
 * (ht_dual_lobe_shape).  Tables: host/fiber/dual_scattering.cpp in double, read here by linear
 * interpolation in theta (and phi for N^G).
 *
 * Normalisation: every term is an azimuthal density that integrates to the energy it stands for
 * times a longitudinal function of unit integral (ht_dual_eval), so the back-scattering lobe
 * returns A_b and the forward-scattered lobe a_f + a_b of what arrives; the paper's constants
 * (2/pi, pi d_b, 1/cos^2 theta_d) belong to its own normalisation of N and M. */
#ifndef HT_FIBER_DUAL_H
#define HT_FIBER_DUAL_H

#include "../types.h"
#include "azimuthal.h"
#include "longitudinal.h"

/* Density factors d_f, d_b: the share of the light a neighbour scatters forward (backward) that
 * meets the next fibre.  The paper takes 0.7 (0.6-0.8 for human hair), with fibre counts from
 * deep opacity maps; here the shadow rays count the fibres they actually cross, and 1 is taken:
 * with 0.7 the image mean of builtin:strand was 18 % below exact depth-20 path tracing, with 1
 * 6 % (docs/MODEL.md §13).  The host tables use d_b too (sigma_b), so these are not options. */
#define HT_DUAL_DF HT_R(1.0)
#define HT_DUAL_DB HT_R(1.0)
#define HT_DUAL_LOBES 4 /* R, TT, TRT, residual (chiang) */

/* Table layout, float4 rows per material: HT_DUAL_HEAD_ROWS rows (alpha_p, beta_p^2, 0, 0), then
 * HT_DUAL_THETA_N + 1 nodes theta_i = i (pi/2) / HT_DUAL_THETA_N of HT_DUAL_NODE_ROWS rows each:
 * a_f, beta_f^2 (rows the shadow rays read), A_b, Delta_b, sigma_b^2, then N^G_p at phi_j =
 * j pi / HT_DUAL_PHI_N for each lobe p; rgb in xyz. */
#define HT_DUAL_THETA_N 90
#define HT_DUAL_PHI_N 36
#define HT_DUAL_HEAD_ROWS HT_DUAL_LOBES
#define HT_DUAL_ROW_AF 0
#define HT_DUAL_ROW_BETA_F2 1
#define HT_DUAL_ROW_AB 2
#define HT_DUAL_ROW_DELTA_B 3
#define HT_DUAL_ROW_SIGMA_B2 4
#define HT_DUAL_ROW_NG 5
#define HT_DUAL_NODE_ROWS (HT_DUAL_ROW_NG + HT_DUAL_LOBES * (HT_DUAL_PHI_N + 1))
#define HT_DUAL_MATERIAL_ROWS (HT_DUAL_HEAD_ROWS + (HT_DUAL_THETA_N + 1) * HT_DUAL_NODE_ROWS)

/* Longitudinal shift and variance of lobe p in theta_h (the cone theta_o = -theta_i at 0).
 * marschner/zinke: the material's alpha_p, beta_p.  chiang: d'Eon's M_p of variance v_p is, for
 * the small v of hair, a Gaussian of std sqrt(v_p) in theta_i around the tilted cone, i.e. of
 * std sqrt(v_p)/2 in theta_h; the tilt (pbrt's, kernels/fiber/chiang.h) puts R at +alpha, TT at
 * -alpha/2, TRT at -2 alpha.  No residual outside chiang. */
HT_FIBER_FN void ht_dual_lobe_shape(const HtMaterial* m, int p, real* alpha, real* beta2) {
    if (m->model == HT_MODEL_CHIANG) {
        const real a = m->alpha;
        *alpha = p == 0 ? a : p == 1 ? -HT_R(0.5) * a : p == 2 ? -HT_R(2) * a : HT_R(0);
        *beta2 = HT_R(0.25) * m->v[p];
        return;
    }
    *alpha = p == 0 ? m->alpha_r : p == 1 ? m->alpha_tt : p == 2 ? m->alpha_trt : HT_R(0);
    *beta2 = p == 0 ? m->beta_r * m->beta_r : p == 1 ? m->beta_tt * m->beta_tt
                                                     : p == 2 ? m->beta_trt * m->beta_trt : HT_R(0);
}

/* A_p(h) of one channel at inclination theta (sin_t, cos_t), and the exit azimuth Phi(p, h) in
 * (-pi, pi] (p = 3: chiang's residual, no azimuth; 0 elsewhere). */
HT_FIBER_FN real ht_dual_attenuation(const HtMaterial* m, int p, real sin_t, real cos_t, real sigma_a, real h,
                               real* phi) {
    const real eta = m->eta;
    const real inv_ep = ht_inv_eta_prime(eta, sin_t, cos_t);
    const real gi = ht_asin(h), gt = ht_asin(h * inv_ep);
    const real f = ht_fresnel_dielectric(cos_t * ht_safe_sqrt(HT_R(1) - h * h), eta);
    *phi = ht_wrap_pi(ht_phi_path(p < 3 ? p : 0, gi, gt));
    if (p == 0) return f;
    const real hq = h * inv_ep;
    const real T = exp(-sigma_a * HT_R(2) * ht_safe_sqrt(HT_R(1) - hq * hq) / ht_cos_theta_t(eta, sin_t));
    const real a1 = (HT_R(1) - f) * (HT_R(1) - f) * T;
    if (p == 1) return a1;
    const real a2 = a1 * f * T;
    if (p == 2) return a2;
    if (m->model != HT_MODEL_CHIANG) return HT_R(0);
    return a2 * f * T / ht_max(HT_R(1) - T * f, HT_R(1e-6));
}

/* Row `row` (xyz) of node theta (in [0, pi/2]) of material `material`, interpolated linearly. */
HT_FIBER_FN real3 ht_dual_row(HT_CONST_GLOBAL float* table, uint material, real theta, uint row) {
    HT_CONST_GLOBAL float* t = table + (size_t)material * (4u * HT_DUAL_MATERIAL_ROWS) + 4u * HT_DUAL_HEAD_ROWS;
    const real x = ht_clamp(theta, HT_R(0), HT_HALF_PI) * ((real)HT_DUAL_THETA_N / HT_HALF_PI);
    int i = (int)x;
    i = i < HT_DUAL_THETA_N - 1 ? i : HT_DUAL_THETA_N - 1;
    const real f = x - (real)i;
    HT_CONST_GLOBAL float* a = t + 4u * ((uint)i * HT_DUAL_NODE_ROWS + row);
    HT_CONST_GLOBAL float* b = a + 4u * HT_DUAL_NODE_ROWS;
    return make_real3(a[0], a[1], a[2]) + (make_real3(b[0], b[1], b[2]) - make_real3(a[0], a[1], a[2])) * f;
}

/* N^G_p at node theta and |phi| in [0, pi], bilinear. */
HT_FIBER_FN real3 ht_dual_ng(HT_CONST_GLOBAL float* table, uint material, real theta, int p, real phi) {
    const real y = ht_clamp(fabs(phi), HT_R(0), HT_PI) * ((real)HT_DUAL_PHI_N / HT_PI);
    int j = (int)y;
    j = j < HT_DUAL_PHI_N - 1 ? j : HT_DUAL_PHI_N - 1;
    const real g = y - (real)j;
    const uint row = HT_DUAL_ROW_NG + (uint)p * (HT_DUAL_PHI_N + 1u) + (uint)j;
    const real3 a = ht_dual_row(table, material, theta, row), b = ht_dual_row(table, material, theta, row + 1u);
    return a + (b - a) * g;
}

/* d'Eon's longitudinal function (kernels/fiber/longitudinal.h) per channel: variances v, the
 * lobe's cone moved by 2 shift in theta_o (a shift of theta_h by `shift`). */
HT_FIBER_FN real3 ht_dual_mp3(real theta_i, real theta_o, real3 shift, real3 v) {
    const real si = sin(theta_i), ci = fabs(cos(theta_i));
    const real ox = theta_o - HT_R(2) * shift.x, oy = theta_o - HT_R(2) * shift.y, oz = theta_o - HT_R(2) * shift.z;
    return make_real3(ht_mp(ci, si, fabs(cos(ox)), sin(ox), v.x), ht_mp(ci, si, fabs(cos(oy)), sin(oy), v.y),
                      ht_mp(ci, si, fabs(cos(oz)), sin(oz), v.z));
}

/* The dual-scattering value (the BCSDF times cos theta_i: what multiplies light / pdf), for
 * light arriving from inclination theta_i at a fibre seen from theta_o, relative azimuth phi,
 * after `crossings` fibres with forward transmittance tf = prod a_f and spread sigma_f2 =
 * sum beta_f^2:
 *   crossings = 0: the local back-scattering of the lit fibre's neighbours, d_b f_back (the
 *                  single scattering itself is the exact BCSDF, added by the caller);
 *   crossings > 0: the global part, d_f T_f (f_scatter + d_b f_back with the spread added):
 *                  f_scatter = sum_p N^G_p(phi) M(theta_h - alpha_p; beta_p^2 + sigma_f^2),
 *                  N^G_p the lobe's azimuthal density averaged over incoming azimuths spread over
 *                  the forward half circle;
 *   f_back(s2) = A_b / (2 pi) M(theta_h - Delta_b; sigma_b^2 + s2), uniform in phi.
 * M is d'Eon's longitudinal function of variance 4 x (the theta_h variance) in theta_i
 * (kernels/fiber/longitudinal.h): unlike a Gaussian in theta_h over cos^2 theta_d, it keeps its
 * unit integral on the sphere however wide the lobe (sigma_b reaches 0.3 rad), so f_back returns
 * A_b and f_scatter a_f + a_b of the light at any width (tests/unit/fiber_dual_test.cpp). */
HT_FIBER_FN real3 ht_dual_eval(HT_CONST_GLOBAL float* table, uint material, real theta_i, real theta_o, real phi,
                         uint crossings, real3 tf, real3 sigma_f2) {
    const real at = fabs(theta_i);
    const real3 ab = ht_dual_row(table, material, at, HT_DUAL_ROW_AB);
    const real3 db = ht_dual_row(table, material, at, HT_DUAL_ROW_DELTA_B);
    const real3 sb2 = ht_dual_row(table, material, at, HT_DUAL_ROW_SIGMA_B2);
    const real3 spread = crossings > 0u ? sigma_f2 : ht_splat(HT_R(0));
    const real3 back = ht_dual_mp3(theta_i, theta_o, db, (sb2 + spread) * HT_R(4)) * ab * (HT_DUAL_DB / HT_TWO_PI);
    if (crossings == 0u) return back;
    HT_CONST_GLOBAL float* head = table + (size_t)material * (4u * HT_DUAL_MATERIAL_ROWS);
    real3 fwd = ht_splat(HT_R(0));
    for (int p = 0; p < HT_DUAL_LOBES; ++p) {
        const real alpha = head[4 * p], beta2 = head[4 * p + 1];
        fwd += ht_dual_ng(table, material, at, p, phi) *
               ht_dual_mp3(theta_i, theta_o, ht_splat(alpha), (ht_splat(beta2) + sigma_f2) * HT_R(4));
    }
    return tf * (fwd + back) * HT_DUAL_DF;
}

#endif
