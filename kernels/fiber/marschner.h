/* Marschner et al. 2003 far-field model (docs/MODEL.md §2-5):
 *   S = sum_p M_p(theta_h) N_p(eta'(theta_d), phi) / cos^2 theta_d,   M_p = unit Gaussian(theta_h - alpha_p; beta_p)
 *   value = S cos(theta_i) / 2
 * The 1/2 is 1/D for a fibre of diameter D = 2 (units of the radius): the renderer's average over the
 * hit offset h plays the role of Marschner's D, so a white smooth fibre conserves energy exactly as
 * pbrt's h-averaged model does (far-field limit of value_chiang averaged over h).  h is not used.
 * N_p = sum over the exact roots h of Phi(p, h) = phi of A_p(h) / |2 dPhi/dh| (root finding:
 * monotone pieces split at the TRT caustics, Newton safeguarded by bisection); A_p with the exact
 * (= Bravais) Fresnel at cos theta_d cos gamma_i and the chord absorption 2 cos gamma_t / cos theta_t.
 * TRT: caustic removal + glints (w_c, k_G, delta eta', delta h_M) and eccentricity eta*(phi_h),
 * phi_h measured from the frame's y axis (taken as the major axis of the section).
 *
 * Sampling (exact pdf of what is sampled): lobe p by A_p luminance at h = 1/2 (floored at 2 %);
 * theta_i from the d'Eon proxy of the Gaussian (ht_mz_theta_sample: never fails); phi: R and TT: h uniform
 * in [-1, 1], phi = Phi(p, h) (density sum_roots 1/|2 dPhi/dh|); TRT: the same mixed with the glint
 * Gaussians at +-phi_c (15 % when glints are on) and a uniform (10 %).  eta (not eta*) in the proxy. */
#ifndef HT_FIBER_MARSCHNER_H
#define HT_FIBER_MARSCHNER_H

#include "../types.h"
#include "azimuthal.h"
#include "lobes.h"

typedef struct {
    real sin_o, cos_o, sin_i, cos_i, theta_o, theta_i, theta_h, sin_d, cos_d, phi;
} HtMarschnerAngles;

/* theta_i, theta_h and theta_d of a->sin_i and a->theta_o. */
HT_FIBER_FN void ht_marschner_angles_theta(HtMarschnerAngles* a) {
    a->theta_i = ht_asin(a->sin_i);
    a->theta_h = HT_R(0.5) * (a->theta_i + a->theta_o);
    ht_sincos(HT_R(0.5) * (a->theta_o - a->theta_i), &a->sin_d, &a->cos_d);
    a->cos_d = fabs(a->cos_d);
}
/* The wi-dependent half of the angles; a->sin_o, cos_o, theta_o already set. */
HT_FIBER_FN void ht_marschner_angles_i(real3 wo, real3 wi, HtMarschnerAngles* a) {
    ht_theta(wi, &a->sin_i, &a->cos_i);
    ht_marschner_angles_theta(a);
    a->phi = ht_relative_phi(wo, wi);
}
HT_FIBER_FN void ht_marschner_angles(real3 wo, real3 wi, HtMarschnerAngles* a) {
    ht_theta(wo, &a->sin_o, &a->cos_o);
    a->theta_o = ht_asin(a->sin_o);
    ht_marschner_angles_i(wo, wi, a);
}

/* Longitudinal sampling proxy shared by marschner and zinke: the d'Eon lobe M(theta_i; theta_o', v)
 * with theta_o' = theta_o - 2 alpha_p (cone at theta_h = alpha_p) and v = (2 beta_p)^2 (the Gaussian
 * in theta_h of std beta_p is a Gaussian in theta_i of std 2 beta_p).  It lives on the sphere, so no
 * sample is lost at grazing angles, and its solid-angle density is M (the cos theta_i cancels). */
HT_FIBER_FN void ht_mz_lobe_ab(const HtMaterial* m, int p, real* alpha, real* beta) {
    *alpha = p == 0 ? m->alpha_r : (p == 1 ? m->alpha_tt : m->alpha_trt);
    *beta = p == 0 ? m->beta_r : (p == 1 ? m->beta_tt : m->beta_trt);
}
HT_FIBER_FN void ht_mz_lobe_shape(const HtMaterial* m, int p, real* alpha, real* v) {
    real b;
    ht_mz_lobe_ab(m, p, alpha, &b);
    *v = HT_R(4) * b * b;
}
/* The proxy's per-material constants (sin, cos 2 alpha_p; the log normaliser of v): made by the
 * host once per material (host/fiber/material.cpp) and again where --regularize widens the betas
 * (kernels/integrator/shading_point.h), so a shading point does not redo three sincos, exps and
 * logs of the material alone (docs/PERFORMANCE.md §3). */
HT_FIBER_FN void ht_mz_prepare_material(HtMaterial* m) {
    for (int p = 0; p < 3; ++p) {
        real a, v, s2, c2;
        ht_mz_lobe_shape(m, p, &a, &v);
        ht_sincos(HT_R(2) * a, &s2, &c2);
        m->mz_sin_tilt[p] = (float)s2;
        m->mz_cos_tilt[p] = (float)c2;
        m->mz_log_norm[p] = (float)ht_mp_log_norm(v);
    }
    m->mz_sin_tilt[3] = m->mz_log_norm[3] = 0.0f;
    m->mz_cos_tilt[3] = 1.0f;
}
/* Lobe p's tilted cone (sin, cos theta_o'), v and log normaliser.  The host (double) derives the
 * constants from alpha_p, beta_p exactly; the float kernels read the material's. */
HT_FIBER_FN void ht_mz_tilt(const HtMaterial* m, int p, real sin_o, real cos_o, real* sp, real* cp, real* v,
                            real* log_norm) {
    real a, s2, c2;
    ht_mz_lobe_shape(m, p, &a, v);
#ifdef HT_HOST
    ht_sincos(HT_R(2) * a, &s2, &c2);
    *log_norm = ht_mp_log_norm(*v);
#else
    s2 = m->mz_sin_tilt[p];
    c2 = m->mz_cos_tilt[p];
    *log_norm = m->mz_log_norm[p];
#endif
    *sp = ht_clamp(sin_o * c2 - cos_o * s2, HT_R(-1), HT_R(1));
    *cp = fabs(cos_o * c2 + sin_o * s2);
}

/* What marschner and zinke need of wo (and, for zinke, h) alone: theta_o, each lobe's tilted cone
 * with its M_p log normaliser, and the lobe selection probabilities.  A shading point makes it
 * once (kernels/integrator/shading_point.h) for its next-event estimates and its samples, each of
 * which evaluates the model again: the shade kernel spent a quarter of its time redoing these per
 * call (docs/PERFORMANCE.md §3).  Lobes compiled out (lobes.h) are left 0 and never read. */
typedef struct {
    real sin_o, cos_o, theta_o;
    real tilt_s[3], tilt_c[3], tilt_v[3], tilt_n[3];
    real pr[3];
    real gamma_i, cos_gamma_i; /* zinke: asin h, sqrt(1 - h^2) of the hit's h (marschner: 0) */
} HtMzWo;

HT_FIBER_FN void ht_mz_wo_clear(HtMzWo* o) {
    o->sin_o = o->cos_o = o->theta_o = o->gamma_i = o->cos_gamma_i = HT_R(0);
    for (int p = 0; p < 3; ++p) o->tilt_s[p] = o->tilt_c[p] = o->tilt_v[p] = o->tilt_n[p] = o->pr[p] = HT_R(0);
}
HT_FIBER_FN void ht_mz_wo_theta(const HtMaterial* m, real3 wo, HtMzWo* o) {
    ht_mz_wo_clear(o);
    ht_theta(wo, &o->sin_o, &o->cos_o);
    o->theta_o = ht_asin(o->sin_o);
    for (int p = 0; p < 3; ++p) {
        if (!HT_LOBE_ON(p)) continue;
        ht_mz_tilt(m, p, o->sin_o, o->cos_o, &o->tilt_s[p], &o->tilt_c[p], &o->tilt_v[p], &o->tilt_n[p]);
    }
}
/* The proxy's density of theta_i for lobe p (per solid angle / dphi) and its sampler. */
HT_FIBER_FN real ht_mz_theta_pdf(const HtMzWo* o, int p, real sin_i, real cos_i) {
    return ht_mp_n(cos_i, sin_i, o->tilt_c[p], o->tilt_s[p], o->tilt_v[p], o->tilt_n[p]);
}
HT_FIBER_FN real ht_mz_theta_pdf_parts(const HtMzWo* o, int p, real sin_i, real cos_i, real* exponent) {
    return ht_mp_n_parts(cos_i, sin_i, o->tilt_c[p], o->tilt_s[p], o->tilt_v[p], o->tilt_n[p], exponent);
}
HT_FIBER_FN void ht_mz_theta_sample(const HtMzWo* o, int p, real u1, real u2, real* sin_i, real* cos_i) {
    ht_mp_sample(u1, u2, o->tilt_s[p], o->tilt_c[p], o->tilt_v[p], sin_i, cos_i);
}
/* The angles between wo and wi, the wo half taken from o. */
HT_FIBER_FN void ht_mz_angles(const HtMzWo* o, real3 wo, real3 wi, HtMarschnerAngles* a) {
    a->sin_o = o->sin_o;
    a->cos_o = o->cos_o;
    a->theta_o = o->theta_o;
    ht_marschner_angles_i(wo, wi, a);
}
/* The angles of a sampled theta_i (phi not drawn yet: 0): the azimuthal half of a sampler starts
 * from theta_d. */
HT_FIBER_FN void ht_mz_angles_drawn(const HtMzWo* o, real sin_i, real cos_i, HtMarschnerAngles* a) {
    a->sin_o = o->sin_o;
    a->cos_o = o->cos_o;
    a->theta_o = o->theta_o;
    a->sin_i = sin_i;
    a->cos_i = cos_i;
    ht_marschner_angles_theta(a);
    a->phi = HT_R(0);
}

/* A_p(h) at theta_d for index eta (p = 0, 1, 2), c = sqrt(1 - h^2); _k: given inv_ep = 1/eta' and
 * ctt = cos theta_t at theta_d, which every root and lobe at one theta_d shares. */
HT_FIBER_FN real3 ht_marschner_chord_k(const HtMaterial* m, real h, real inv_ep, real ctt) {
    real ht_ = h * inv_ep;
    real cgt = ht_safe_sqrt(HT_R(1) - ht_ * ht_);
    return ht_chord_transmittance(ht_load3(m->sigma_a), cgt, ctt);
}
HT_FIBER_FN real3 ht_marschner_ap_k(const HtMaterial* m, int p, real h, real c, real eta, real cos_d, real inv_ep, real ctt) {
    real f = ht_fresnel_dielectric(cos_d * c, eta);
    if (p == 0) return ht_splat(f);
    real3 T = ht_marschner_chord_k(m, h, inv_ep, ctt);
    real3 a = T * ((HT_R(1) - f) * (HT_R(1) - f));
    return p == 1 ? a : a * T * f;
}
/* All three at one h (zinke's lobe weights, the lobe probabilities): one Fresnel, one chord. */
HT_FIBER_FN void ht_marschner_ap3_k(const HtMaterial* m, real h, real c, real eta, real cos_d, real inv_ep, real ctt,
                              real3* a) {
    real f = ht_fresnel_dielectric(cos_d * c, eta);
    a[0] = ht_splat(f);
    real3 T = ht_marschner_chord_k(m, h, inv_ep, ctt);
    a[1] = T * ((HT_R(1) - f) * (HT_R(1) - f));
    a[2] = a[1] * T * f;
}
HT_FIBER_FN real3 ht_marschner_ap_c(const HtMaterial* m, int p, real h, real c, real eta, real sin_d, real cos_d) {
    return ht_marschner_ap_k(m, p, h, c, eta, cos_d, ht_inv_eta_prime(eta, sin_d, cos_d), ht_cos_theta_t(eta, sin_d));
}
HT_FIBER_FN real3 ht_marschner_ap(const HtMaterial* m, int p, real h, real eta, real sin_d, real cos_d) {
    return ht_marschner_ap_c(m, p, h, ht_safe_sqrt(HT_R(1) - h * h), eta, sin_d, cos_d);
}

/* Caustic parameters of TRT at 1/eta' = inv_ep: centre phi_c, glint interval dh, fade t, h_c. */
HT_FIBER_FN void ht_marschner_caustic(const HtMaterial* m, real inv_ep, real* phi_c, real* dh, real* t, real* hc) {
    real ep2 = HT_R(1) / ht_max(inv_ep * inv_ep, HT_R(1e-30));
    if (ep2 < HT_R(4)) {
        real h = sqrt((HT_R(4) - ep2) / HT_R(3));
        real gi = ht_asin(h), gt = ht_asin(h * inv_ep);
        *phi_c = fabs(ht_wrap_pi(ht_phi_path(2, gi, gt)));
        real a = ht_max(ep2 - h * h, HT_R(1e-12)), b = ht_max(HT_R(1) - h * h, HT_R(1e-12));
        real d2 = HT_R(4) * h / (a * sqrt(a)) - HT_R(2) * h / (b * sqrt(b));
        *dh = ht_min(m->caustic_dhm, HT_R(2) * sqrt(HT_R(2) * m->caustic_wc / ht_max(fabs(d2), HT_R(1e-12))));
        *t = HT_R(1);
        *hc = h;
    } else {
        real ep = sqrt(ep2);
        real x = ht_clamp((ep - HT_R(2)) / ht_max(m->caustic_deta, HT_R(1e-6)), HT_R(0), HT_R(1));
        *phi_c = HT_R(0);
        *dh = m->caustic_dhm;
        *t = HT_R(1) - x * x * (HT_R(3) - HT_R(2) * x);
        *hc = HT_R(0);
    }
}

/* sum over roots of A_p(h)/|2 dPhi/dh| (N_p, smooth circle) and of 1/|2 dPhi/dh| (h-uniform density). */
HT_FIBER_FN void ht_marschner_np_raw(const HtMaterial* m, int p, real phi, real eta, real sin_d, real cos_d,
                               real3* np, real* density) {
    real inv_ep = ht_inv_eta_prime(eta, sin_d, cos_d), ctt = ht_cos_theta_t(eta, sin_d);
    real hs[3], cs[3];
    int n = ht_phi_roots(p, phi, inv_ep, hs, cs);
    real3 acc = ht_splat(HT_R(0));
    real dens = HT_R(0);
    for (int k = 0; k < n; ++k) {
        real s = HT_R(0.5) * ht_inv_dphi_dh_c(p, hs[k], cs[k], inv_ep);
        acc += ht_marschner_ap_k(m, p, hs[k], cs[k], eta, cos_d, inv_ep, ctt) * s;
        dens += s;
    }
    *np = acc;
    *density = dens;
}

/* eta* for TRT (eccentricity a <= 1), cos2h = cos(2 phi_h). */
HT_FIBER_FN real ht_marschner_eta_star(const HtMaterial* m, real cos2h) {
    real a = m->eccentricity, eta = m->eta;
    if (!(a < HT_R(1))) return eta;
    real e1 = HT_R(2) * (eta - HT_R(1)) * a * a - eta + HT_R(2);
    real e2 = HT_R(2) * (eta - HT_R(1)) / (a * a) - eta + HT_R(2);
    return ht_max(HT_R(0.5) * ((e1 + e2) + cos2h * (e1 - e2)), HT_R(1.0001));
}

/* N'_TRT with caustic removal and glints; *dens_out = h-uniform density of the raw roots. */
HT_FIBER_FN real3 ht_marschner_ntrt(const HtMaterial* m, real phi, real eta, real sin_d, real cos_d, real* dens_out) {
    real3 n;
    real dens;
    ht_marschner_np_raw(m, 2, phi, eta, sin_d, cos_d, &n, &dens);
    *dens_out = dens;
    real inv_ep = ht_inv_eta_prime(eta, sin_d, cos_d);
    real phi_c, dh, t, hc;
    ht_marschner_caustic(m, inv_ep, &phi_c, &dh, &t, &hc);
    real wc = m->caustic_wc;
    real d1 = ht_wrap_pi(phi - phi_c), d2 = ht_wrap_pi(phi + phi_c);
    real r1 = exp(-HT_R(0.5) * d1 * d1 / (wc * wc)), r2 = exp(-HT_R(0.5) * d2 * d2 / (wc * wc));
    real3 glint = ht_marschner_ap(m, 2, hc, eta, sin_d, cos_d) *
                  (t * m->caustic_kg * dh * (ht_gaussian(d1, wc) + ht_gaussian(d2, wc)));
    return n * ((HT_R(1) - t * r1) * (HT_R(1) - t * r2)) + glint;
}

/* Normalises lobe weights pr[0..2] (sum s) into selection probabilities, each compiled-in lobe
 * floored at 2 % so that no lobe the model evaluates goes unsampled; compiled-out lobes get 0. */
HT_FIBER_FN void ht_lobe_probs_finish(real* pr, real s) {
    s = ht_max(s, HT_R(1e-12));
    real t = HT_R(0);
    for (int p = 0; p < 3; ++p) { pr[p] = HT_LOBE_ON(p) ? ht_max(pr[p] / s, HT_R(0.02)) : HT_R(0); t += pr[p]; }
    for (int p = 0; p < 3; ++p) pr[p] /= t;
}

/* Lobe for the uniform u0 and u0 remapped to [0, 1) within it.  Rounding can leave u0 past the
 * cumulative sum of the last compiled-in lobe: that lobe is taken then (never one with pr = 0). */
HT_FIBER_FN int ht_pick_lobe(const real* pr, real u0, real* ur) {
    int p = u0 < pr[0] ? 0 : (u0 < pr[0] + pr[1] ? 1 : 2);
    while (p > 0 && !(pr[p] > HT_R(0))) --p;
    real r = p == 0 ? u0 / pr[0] : (p == 1 ? (u0 - pr[0]) / pr[1] : (u0 - pr[0] - pr[1]) / pr[2]);
    *ur = ht_clamp(r, HT_R(0), HT_R(0.99999994));
    return p;
}

/* Lobe selection probabilities (depend on wo only). */
HT_FIBER_FN void ht_marschner_probs(const HtMaterial* m, real sin_o, real cos_o, real* pr) {
    real3 a[3];
    ht_marschner_ap3_k(m, HT_R(0.5), ht_safe_sqrt(HT_R(1) - HT_R(0.5) * HT_R(0.5)), m->eta, cos_o,
                       ht_inv_eta_prime(m->eta, sin_o, cos_o), ht_cos_theta_t(m->eta, sin_o), a);
    real s = HT_R(0);
    for (int p = 0; p < 3; ++p) {
        pr[p] = HT_LOBE_ON(p) ? ht_luminance(a[p]) : HT_R(0);
        s += pr[p];
    }
    ht_lobe_probs_finish(pr, s);
}
HT_FIBER_FN void ht_marschner_wo(const HtMaterial* m, real3 wo, HtMzWo* o) {
    ht_mz_wo_theta(m, wo, o);
    ht_marschner_probs(m, o->sin_o, o->cos_o, o->pr);
}

#define HT_MARSCHNER_TRT_UNIFORM HT_R(0.10)
#define HT_MARSCHNER_TRT_GLINT HT_R(0.15)

/* Solid-angle pdf of ht_marschner_sample.  dens[p] >= 0: the h-uniform density of lobe p at a->phi
 * (index eta) already known to the caller; < 0: computed here. */
HT_FIBER_FN real ht_marschner_pdf(const HtMaterial* m, const HtMzWo* o, const HtMarschnerAngles* a, const real* dens_in) {
    real pd = HT_R(0);
    for (int p = 0; p < 3; ++p) {
        if (!HT_LOBE_ON(p)) continue;
        real pth = ht_mz_theta_pdf(o, p, a->sin_i, a->cos_i); /* per solid angle / dphi */
        real dens = dens_in[p];
        if (dens < HT_R(0)) {
            real3 np;
            ht_marschner_np_raw(m, p, a->phi, m->eta, a->sin_d, a->cos_d, &np, &dens);
        }
        real pphi = dens;
        if (p == 2) {
            real inv_ep = ht_inv_eta_prime(m->eta, a->sin_d, a->cos_d);
            real phi_c, dh, t, hc;
            ht_marschner_caustic(m, inv_ep, &phi_c, &dh, &t, &hc);
            real eg = t > HT_R(0) ? HT_MARSCHNER_TRT_GLINT : HT_R(0);
            real g = HT_R(0.5) * (ht_wrapped_gaussian(a->phi - phi_c, m->caustic_wc) +
                               ht_wrapped_gaussian(a->phi + phi_c, m->caustic_wc));
            pphi = (HT_R(1) - eg - HT_MARSCHNER_TRT_UNIFORM) * dens + eg * g + HT_MARSCHNER_TRT_UNIFORM * HT_INV_TWO_PI;
        }
        pd += o->pr[p] * pth * pphi;
    }
    return pd;
}

/* o: ht_marschner_wo of this wo (h is not used by the far field) */
HT_FIBER_FN void ht_marschner_eval_o(const HtMaterial* m, const HtMzWo* o, real3 wo, real3 wi, real3* lobes, real3* value,
                               real* pdf) {
    HtMarschnerAngles a;
    ht_mz_angles(o, wo, wi, &a);
    real geo = HT_R(0.5) * a.cos_i / ht_max(a.cos_d * a.cos_d, HT_R(1e-6));
    real dens[3] = {HT_R(0), HT_R(0), HT_R(0)};
    real3 n0, n1 = ht_splat(HT_R(0)), n2 = ht_splat(HT_R(0));
    ht_marschner_np_raw(m, 0, a.phi, m->eta, a.sin_d, a.cos_d, &n0, &dens[0]);
#if HT_FEATURE_LOBE_TT
    ht_marschner_np_raw(m, 1, a.phi, m->eta, a.sin_d, a.cos_d, &n1, &dens[1]);
#endif
#if HT_FEATURE_LOBE_TRT
    real eta_trt = m->eta;
    if (m->eccentricity < HT_R(1)) {
        /* cos(2 phi_h) = cos(2 phi_o + phi), phi_h = (phi_i + phi_o)/2 */
        real yy = wo.y * wo.y, zz = wo.z * wo.z, r2 = yy + zz;
        real c2o = r2 > HT_R(1e-24) ? (yy - zz) / r2 : HT_R(1), s2o = r2 > HT_R(1e-24) ? HT_R(2) * wo.y * wo.z / r2 : HT_R(0);
        real sp, cp;
        ht_sincos(a.phi, &sp, &cp);
        eta_trt = ht_marschner_eta_star(m, c2o * cp - s2o * sp);
    }
    n2 = ht_marschner_ntrt(m, a.phi, eta_trt, a.sin_d, a.cos_d, &dens[2]);
    if (eta_trt != m->eta) dens[2] = HT_R(-1); /* the sampling proxy uses eta, not eta* */
#endif
    lobes[0] = n0 * (geo * ht_gaussian(a.theta_h - m->alpha_r, m->beta_r));
    lobes[1] = n1 * (geo * ht_gaussian(a.theta_h - m->alpha_tt, m->beta_tt));
    lobes[2] = n2 * (geo * ht_gaussian(a.theta_h - m->alpha_trt, m->beta_trt));
    lobes[3] = ht_splat(HT_R(0));
    for (int p = 0; p < 3; ++p) lobes[p] = ht_sanitize3(lobes[p]);
    *value = lobes[0] + lobes[1] + lobes[2];
    if (pdf) *pdf = ht_sanitize(ht_marschner_pdf(m, o, &a, dens));
}
HT_FIBER_FN void ht_marschner_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value, real* pdf) {
    HtMzWo o;
    ht_marschner_wo(m, wo, &o);
    ht_marschner_eval_o(m, &o, wo, wi, lobes, value, pdf);
}

/* The end of a sampler that draws from a proxy and then evaluates the model at the drawn
 * direction w: reports w, the model's pdf there and weight = value / pdf (0 if pdf is 0). */
HT_FIBER_FN int ht_finish_sample(real3 w, real3 value, real pd, real3* wi, real3* weight, real* pdf) {
    *wi = w;
    *pdf = pd;
    if (!(pd > HT_R(0))) return 0;
    *weight = ht_sanitize3(value / pd);
    return 1;
}


HT_FIBER_FN int ht_marschner_sample_o(const HtMaterial* m, const HtMzWo* o, real3 wo, real u0, real u1, real u2, real u3,
                                real3* wi, real3* weight, real* pdf) {
    real ur;
    int p = ht_pick_lobe(o->pr, u0, &ur);
    real sin_i, cos_i;
    ht_mz_theta_sample(o, p, u1, u2, &sin_i, &cos_i);
    HtMarschnerAngles a;
    ht_mz_angles_drawn(o, sin_i, cos_i, &a);
    real inv_ep = ht_inv_eta_prime(m->eta, a.sin_d, a.cos_d);
    real hh = HT_R(2) * u3 - HT_R(1);
    real dphi;
    if (p < 2) {
        dphi = ht_phi_path(p, ht_asin(hh), ht_asin(hh * inv_ep));
    } else {
        real phi_c, dh, t, hc;
        ht_marschner_caustic(m, inv_ep, &phi_c, &dh, &t, &hc);
        real eg = t > HT_R(0) ? HT_MARSCHNER_TRT_GLINT : HT_R(0);
        if (ur < HT_MARSCHNER_TRT_UNIFORM) {
            dphi = HT_TWO_PI * (u3 - HT_R(0.5));
        } else if (ur < HT_MARSCHNER_TRT_UNIFORM + eg) {
            /* glint: sign from the remapped lobe uniform, Gaussian from (u3, its remainder) */
            real ug = (ur - HT_MARSCHNER_TRT_UNIFORM) / eg;
            real sg = ug < HT_R(0.5) ? HT_R(1) : HT_R(-1);
            real ug2 = ht_clamp(ug < HT_R(0.5) ? HT_R(2) * ug : HT_R(2) * ug - HT_R(1), HT_R(0), HT_R(0.99999994));
            real n1, n2;
            ht_normal_pair(u3, ug2, &n1, &n2);
            dphi = sg * phi_c + m->caustic_wc * n1;
        } else {
            dphi = ht_phi_path(2, ht_asin(hh), ht_asin(hh * inv_ep));
        }
    }
    real3 w = ht_dir_from(wo, sin_i, cos_i, ht_wrap_pi(dphi));
    real3 lobes[4];
    real3 value;
    real pd;
    ht_marschner_eval_o(m, o, wo, w, lobes, &value, &pd);
    return ht_finish_sample(w, value, pd, wi, weight, pdf);
}
HT_FIBER_FN int ht_marschner_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3,
                              real3* wi, real3* weight, real* pdf) {
    HtMzWo o;
    ht_marschner_wo(m, wo, &o);
    return ht_marschner_sample_o(m, &o, wo, u0, u1, u2, u3, wi, weight, pdf);
}

#endif
