/* Chiang et al. 2016 energy-conserving hair model, with pbrt-v4 HairBxDF conventions
 * (docs/MODEL.md §9-11):
 *   value(wo, wi, h) = sum_{p<3} M_p(theta_i; theta_o tilted, v_p) A_p(h) N_p(phi) + M_3 A_3 / (2 pi)
 * which is pbrt's f(wo, wi) * |cos theta| (pbrt divides by AbsCosTheta(wi) and its integrator
 * multiplies it back).  M_p: d'Eon 2011 (log form, exact I0); A_p: exact Fresnel, chord absorption,
 * residual A_3 = A_2 F T / (1 - F T); N_p: logistic trimmed to [-pi, pi] around Phi(p, h);
 * scale tilt: R 2 alpha, TT alpha, TRT 4 alpha, rotating theta_o (pbrt-v3 PR #256 / pbrt-v4).
 * Sampling: lobe by A_p luminance, d'Eon 2013 theta sampling, logistic phi sampling. */
#ifndef HT_FIBER_CHIANG_H
#define HT_FIBER_CHIANG_H

#include "../types.h"
#include "azimuthal.h"
#include "lobes.h"

/* Per-query quantities shared by eval and sample. */
typedef struct {
    real sin_o, cos_o, gamma_o, gamma_t;
    real3 ap[4];
    real ap_pdf[4];
} HtChiangSetup;

HT_FIBER_FN void ht_chiang_setup_clear(HtChiangSetup* c) {
    c->sin_o = c->cos_o = c->gamma_o = c->gamma_t = HT_R(0);
    for (int p = 0; p < 4; ++p) {
        c->ap[p] = ht_splat(HT_R(0));
        c->ap_pdf[p] = HT_R(0);
    }
}

HT_FIBER_FN void ht_chiang_setup(const HtMaterial* m, real3 wo, real h, HtChiangSetup* c) {
    real eta = m->eta;
    h = ht_clamp(h, HT_R(-1), HT_R(1));
    ht_theta(wo, &c->sin_o, &c->cos_o);
    c->gamma_o = ht_asin(h);
    real sin_theta_t = c->sin_o / eta;
    real cos_theta_t = ht_safe_sqrt(HT_R(1) - sin_theta_t * sin_theta_t);
    real sin_gamma_t = h * ht_inv_eta_prime(eta, c->sin_o, c->cos_o);
    real cos_gamma_t = ht_safe_sqrt(HT_R(1) - sin_gamma_t * sin_gamma_t);
    c->gamma_t = ht_asin(sin_gamma_t);
    real3 T = ht_chord_transmittance(ht_load3(m->sigma_a), cos_gamma_t, cos_theta_t);
    real f = ht_fresnel_dielectric(c->cos_o * ht_safe_sqrt(HT_R(1) - h * h), eta);
    c->ap[0] = ht_splat(f);
    c->ap[1] = T * ((HT_R(1) - f) * (HT_R(1) - f));
    c->ap[2] = c->ap[1] * T * f;
    /* residual: A_2 F T / (1 - F T); 0/0 at h = +-1 with sigma_a = 0 (§14.3) -> denominator floor */
    real3 tf = T * f;
    c->ap[3] = ht_div3(c->ap[2] * tf, ht_max3s(ht_splat(HT_R(1)) - tf, HT_R(1e-7)));
    /* compiled-out lobes (lobes.h) carry nothing: not evaluated, never sampled */
    for (int p = 1; p < 4; ++p)
        if (!HT_LOBE_ON(p)) c->ap[p] = ht_splat(HT_R(0));
    real sum = HT_R(0);
    for (int p = 0; p < 4; ++p) {
        c->ap_pdf[p] = ht_max(ht_luminance(c->ap[p]), HT_R(0));
        sum += c->ap_pdf[p];
    }
    for (int p = 0; p < 4; ++p)
        c->ap_pdf[p] = sum > HT_R(0) ? c->ap_pdf[p] / sum : (HT_LOBE_ON(p) ? HT_R(1) / (real)HT_LOBES_ON : HT_R(0));
}

/* log normaliser of lobe p: exact from v on the host, precomputed (mp_c) in the float kernels. */
HT_FIBER_FN real ht_chiang_log_norm(const HtMaterial* m, int p) {
#ifdef HT_HOST
    return ht_mp_log_norm(m->v[p]);
#else
    return m->mp_c[p];
#endif
}

/* theta_o rotated by the scale tilt of lobe p (pbrt-v4 HairBxDF::f). */
HT_FIBER_FN void ht_chiang_tilt(const HtMaterial* m, int p, real sin_o, real cos_o, real* sp, real* cp) {
    real st, ct, s, c;
    if (p == 0) { st = m->sin_tilt[1]; ct = m->cos_tilt[1]; s = sin_o * ct - cos_o * st; c = cos_o * ct + sin_o * st; }
    else if (p == 1) { st = m->sin_tilt[0]; ct = m->cos_tilt[0]; s = sin_o * ct + cos_o * st; c = cos_o * ct - sin_o * st; }
    else if (p == 2) { st = m->sin_tilt[2]; ct = m->cos_tilt[2]; s = sin_o * ct + cos_o * st; c = cos_o * ct - sin_o * st; }
    else { s = sin_o; c = cos_o; }
    *sp = ht_clamp(s, HT_R(-1), HT_R(1));
    *cp = fabs(c);
}

/* M_p N_p of lobe p < 3 at (sin_i, cos_i, phi): the density with which the sampler's lobe p draws
 * that direction (it draws both factors exactly); lobe p's value is A_p times it. */
HT_FIBER_FN real ht_chiang_mn(const HtMaterial* m, const HtChiangSetup* c, int p, real sin_i, real cos_i, real phi) {
    real sp, cp;
    ht_chiang_tilt(m, p, c->sin_o, c->cos_o, &sp, &cp);
    real mp = ht_mp_n(cos_i, sin_i, cp, sp, m->v[p], ht_chiang_log_norm(m, p));
    real np = ht_trimmed_logistic(ht_wrap_pi(phi - ht_phi_path(p, c->gamma_o, c->gamma_t)), m->s);
    return mp * np;
}
/* The residual lobe's M_3 / (2 pi) (uniform in phi), likewise. */
HT_FIBER_FN real ht_chiang_residual_m(const HtMaterial* m, const HtChiangSetup* c, real sin_i, real cos_i) {
    return ht_mp_n(cos_i, sin_i, c->cos_o, c->sin_o, m->v[3], ht_chiang_log_norm(m, 3)) * HT_INV_TWO_PI;
}

/* value, pdf and the per-lobe values (R, TT, TRT, residual) for given setup. */
HT_FIBER_FN void ht_chiang_eval_setup(const HtMaterial* m, const HtChiangSetup* c, real3 wo, real3 wi,
                                real3* lobes, real3* value, real* pdf) {
    real sin_i, cos_i;
    ht_theta(wi, &sin_i, &cos_i);
    real phi = ht_relative_phi(wo, wi);
    real3 sum = ht_splat(HT_R(0));
    real pd = HT_R(0);
    for (int p = 0; p < 3; ++p) {
        if (!HT_LOBE_ON(p)) { lobes[p] = ht_splat(HT_R(0)); continue; }
        const real mn = ht_chiang_mn(m, c, p, sin_i, cos_i, phi);
        real3 l = c->ap[p] * mn;
        lobes[p] = l;
        sum += l;
        pd += mn * c->ap_pdf[p];
    }
#if HT_FEATURE_LOBE_TRT
    real m3 = ht_chiang_residual_m(m, c, sin_i, cos_i);
    lobes[3] = c->ap[3] * m3;
    sum += lobes[3];
    pd += m3 * c->ap_pdf[3];
#else
    lobes[3] = ht_splat(HT_R(0));
#endif
    *value = ht_sanitize3(sum);
    if (pdf) *pdf = ht_sanitize(pd);
}

HT_FIBER_FN void ht_chiang_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value, real* pdf) {
    HtChiangSetup c;
    ht_chiang_setup(m, wo, h, &c);
    ht_chiang_eval_setup(m, &c, wo, wi, lobes, value, pdf);
}

/* pbrt-v4's sampler: lobe p by ap_pdf, theta_i from M_p, phi from the trimmed logistic around
 * Phi(p, h) (uniform for the residual lobe).  Returns p. */
HT_FIBER_FN int ht_chiang_draw(const HtMaterial* m, const HtChiangSetup* c, real3 wo, real u0, real u1, real u2,
                               real u3, real3* w) {
    int p = 3;
    real acc = HT_R(0);
    for (int k = 0; k < 3; ++k) {
        acc += c->ap_pdf[k];
        if (u0 < acc) { p = k; break; }
    }
    /* rounding past the last compiled-in lobe's cumulative sum: take that lobe */
    while (p > 0 && !(c->ap_pdf[p] > HT_R(0)) && !HT_LOBE_ON(p)) --p;
    real sp, cp;
    ht_chiang_tilt(m, p, c->sin_o, c->cos_o, &sp, &cp);
    real sin_i, cos_i;
    ht_mp_sample(u1, u2, sp, cp, m->v[p], &sin_i, &cos_i);
    real dphi = p < 3 ? ht_phi_path(p, c->gamma_o, c->gamma_t) + ht_trimmed_logistic_sample(u3, m->s)
                      : HT_TWO_PI * (u3 - HT_R(0.5));
    *w = ht_dir_from(wo, sin_i, cos_i, dphi);
    return p;
}

/* The density with which lobe p draws wi (ht_chiang_mn, ht_chiang_residual_m). */
HT_FIBER_FN real ht_chiang_lobe_density(const HtMaterial* m, const HtChiangSetup* c, real3 wo, real3 wi, int p) {
    real sin_i, cos_i;
    ht_theta(wi, &sin_i, &cos_i);
    return p == 3 ? ht_chiang_residual_m(m, c, sin_i, cos_i) : ht_chiang_mn(m, c, p, sin_i, cos_i, ht_relative_phi(wo, wi));
}

/* c: ht_chiang_setup of m, wo and h (a shading point makes it once: kernels/fiber/bcsdf.h).
 * weight = value / pdf of all lobes at the drawn direction (MIS needs that pdf). */
HT_FIBER_FN int ht_chiang_sample_setup(const HtMaterial* m, const HtChiangSetup* c, real3 wo, real u0, real u1, real u2,
                                 real u3, real3* wi, real3* weight, real* pdf) {
    real3 w;
    ht_chiang_draw(m, c, wo, u0, u1, u2, u3, &w);
    real3 lobes[4];
    real3 value;
    real pd;
    ht_chiang_eval_setup(m, c, wo, w, lobes, &value, &pd);
    *wi = w;
    *pdf = pd;
    if (!(pd > HT_R(0))) {
        *weight = ht_splat(HT_R(0));
        return 0;
    }
    *weight = ht_sanitize3(value / pd);
    return 1;
}

/* For a caller without an MIS partner: the drawn lobe's value over its own density.  The sampler
 * draws M_p and N_p exactly, so that ratio is A_p / ap_pdf_p wherever the density is not 0: no
 * lobe is evaluated (the one-sample estimator over the lobes; zinke.h ht_zinke_sample_lobe_o). */
HT_FIBER_FN int ht_chiang_sample_lobe_setup(const HtMaterial* m, const HtChiangSetup* c, real3 wo, real u0, real u1,
                                            real u2, real u3, real3* wi, real3* weight) {
    const int p = ht_chiang_draw(m, c, wo, u0, u1, u2, u3, wi);
    *weight = ht_splat(HT_R(0));
    if (!(c->ap_pdf[p] > HT_R(0))) return 0;
    *weight = ht_sanitize3(c->ap[p] / c->ap_pdf[p]);
    return 1;
}

HT_FIBER_FN int ht_chiang_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3,
                           real3* wi, real3* weight, real* pdf) {
    HtChiangSetup c;
    ht_chiang_setup(m, wo, h, &c);
    return ht_chiang_sample_setup(m, &c, wo, u0, u1, u2, u3, wi, weight, pdf);
}

#endif
