/* Zinke, Sobottka, Weber 2004 near-field model, simplified variant (no s-dependence) with the rough
 * lobes of the paper's §4 / Appendix 1 (docs/MODEL.md §6), evaluated at the hit's own offset h:
 *   value = sum_p 1/2 g(theta_h - alpha_p; beta_p) cos(theta_i)/cos^2(theta_d) * A_p(h) * D(phi - Phi(p, h); sigma_w)
 * A_p: exact Fresnel at cos theta_d cos gamma_i, absorption 2 cos gamma_t'/cos theta_t per chord,
 * eta' and theta_t at theta_d (Appendix 1).  D: wrapped Gaussian with the std of a logistic of scale
 * s(beta_n) (azim_sigma).  The 1/2 cos/cos^2 factor integrates to ~1 over theta_i (as for marschner).
 * h: the hit's own offset (exit azimuth Phi(p, h), pbrt's convention for gamma_o).
 *
 * Lobe weight A_p(h), not the paper's A_p(h) S'_p(h): radiance is conserved along a refracted ray
 * (up to Fresnel and absorption), so the light leaving the fibre at offset h in mode p is A_p(h) times
 * the radiance arriving along that one path.  The ray-density factor S'_p = 1/|dPhi_p/dh| converts a
 * density in h into one in phi; it belongs to the far field (marschner, where the h-integral becomes a
 * sum over roots) and to the paper's AFS^avg (afs.h keeps it, which reproduces the paper's 17 %).  As
 * an exit-radiance weight it is wrong twice over: the R lobe would carry S'_R = cos(gamma)/2 <= 1/2 of
 * its energy and TT 1.41x its energy at h = 0, so the near field would not average over h to the far
 * field (docs/PAPER.md, "Near vs far field energy").  With A_p the model conserves energy at every h
 * (sum_p A_p <= 1 for a white fibre), its h-average is the far field's int N_p dphi = 1/2 int A_p dh,
 * and the TRT caustic, a singularity of the phi-density only, is integrable: no Marschner caustic
 * removal or glint is needed (both stay in marschner.h, the far field that needs them).
 *
 * Sampling: lobe by luminance of A_p(h) at theta_d = theta_o (floored at 2 %), theta_i from the d'Eon
 * proxy of the theta_h Gaussian (ht_mz_theta_sample), phi = Phi(p, h) + sigma_w n (wrapped, n from u3 and
 * the remapped lobe uniform): pdf exact; weight = value/pdf stays close to sum_p A_p <= 1. */
#ifndef HT_FIBER_ZINKE_H
#define HT_FIBER_ZINKE_H

#include "marschner.h"

/* Lobe weights W_p(h) = A_p(h) and exit azimuths Phi(p, h) at theta_d; _g: given c = cos gamma_i
 * = sqrt(1 - h^2) and gi = gamma_i = asin h, which a shading point makes once (HtMzWo). */
HT_FIBER_FN void ht_zinke_w_g(const HtMaterial* m, real h, real c, real gi, real sin_d, real cos_d, real3* w,
                              real* phis) {
    real eta = m->eta;
    real inv_ep = ht_inv_eta_prime(eta, sin_d, cos_d), ctt = ht_cos_theta_t(eta, sin_d);
    real gt = ht_asin(h * inv_ep);
    for (int p = 0; p < 3; ++p) phis[p] = ht_phi_path(p, gi, gt);
    ht_marschner_ap3_k(m, h, c, eta, cos_d, inv_ep, ctt, w);
}
HT_FIBER_FN void ht_zinke_w(const HtMaterial* m, real h, real sin_d, real cos_d, real3* w, real* phis) {
    ht_zinke_w_g(m, h, ht_safe_sqrt(HT_R(1) - h * h), ht_asin(h), sin_d, cos_d, w, phis);
}

HT_FIBER_FN void ht_zinke_probs(const HtMaterial* m, real h, real c, real gi, real sin_o, real cos_o, real* pr) {
    real3 w[3];
    real phis[3];
    ht_zinke_w_g(m, h, c, gi, sin_o, cos_o, w, phis);
    real s = HT_R(0);
    for (int p = 0; p < 3; ++p) { pr[p] = HT_LOBE_ON(p) ? ht_max(ht_luminance(w[p]), HT_R(0)) : HT_R(0); s += pr[p]; }
    ht_lobe_probs_finish(pr, s);
}
HT_FIBER_FN void ht_zinke_wo(const HtMaterial* m, real3 wo, real h, HtMzWo* o) {
    ht_mz_wo_theta(m, wo, o);
    o->cos_gamma_i = ht_safe_sqrt(HT_R(1) - h * h);
    o->gamma_i = ht_asin(h);
    ht_zinke_probs(m, h, o->cos_gamma_i, o->gamma_i, o->sin_o, o->cos_o, o->pr);
}

/* o: ht_zinke_wo of this wo and h */
HT_FIBER_FN void ht_zinke_eval_o(const HtMaterial* m, const HtMzWo* o, real3 wo, real3 wi, real h, real3* lobes,
                           real3* value, real* pdf) {
    HtMarschnerAngles a;
    ht_mz_angles(o, wo, wi, &a);
    real3 w[3];
    real phis[3];
    ht_zinke_w_g(m, h, o->cos_gamma_i, o->gamma_i, a.sin_d, a.cos_d, w, phis);
    real geo = HT_R(0.5) * a.cos_i / ht_max(a.cos_d * a.cos_d, HT_R(1e-6));
    real ab[3] = {m->alpha_r, m->alpha_tt, m->alpha_trt};
    real bb[3] = {m->beta_r, m->beta_tt, m->beta_trt};
    real pd = HT_R(0);
    real3 sum = ht_splat(HT_R(0));
    for (int p = 0; p < 3; ++p) {
        if (!HT_LOBE_ON(p)) { lobes[p] = ht_splat(HT_R(0)); continue; }
        /* the longitudinal Gaussian, the azimuthal one and the proxy's M_p as factor * exp(exponent):
         * two exps per lobe for the value and the pdf instead of three */
        real eg, ed;
        const real g = ht_gaussian_parts(a.theta_h - ab[p], bb[p], &eg);
        const real d = ht_wrapped_gaussian_parts(a.phi - phis[p], m->azim_sigma, &ed);
        lobes[p] = ht_sanitize3(w[p] * (geo * g * d * exp(eg + ed)));
        sum += lobes[p];
        if (pdf) {
            real em;
            const real mp = ht_mz_theta_pdf_parts(o, p, a.sin_i, a.cos_i, &em);
            pd += o->pr[p] * mp * d * exp(em + ed);
        }
    }
    lobes[3] = ht_splat(HT_R(0));
    *value = sum;
    if (pdf) *pdf = ht_sanitize(pd);
}
HT_FIBER_FN void ht_zinke_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value, real* pdf) {
    HtMzWo o;
    ht_zinke_wo(m, wo, h, &o);
    ht_zinke_eval_o(m, &o, wo, wi, h, lobes, value, pdf);
}

/* The sampler's direction (the header's "Sampling"): returns the drawn lobe, with the drawn
 * angles (phi left 0) and 1/eta' at their theta_d. */
HT_FIBER_FN int ht_zinke_draw(const HtMaterial* m, const HtMzWo* o, real3 wo, real h, real u0, real u1, real u2,
                              real u3, real3* w, HtMarschnerAngles* a, real* inv_ep) {
    real ur;
    int p = ht_pick_lobe(o->pr, u0, &ur);
    real sin_i, cos_i;
    ht_mz_theta_sample(o, p, u1, u2, &sin_i, &cos_i);
    ht_mz_angles_drawn(o, sin_i, cos_i, a);
    real n2, n3;
    ht_normal_pair(u3, ur, &n2, &n3);
    *inv_ep = ht_inv_eta_prime(m->eta, a->sin_d, a->cos_d);
    real phi_p = ht_phi_path(p, o->gamma_i, ht_asin(h * *inv_ep));
    *w = ht_dir_from(wo, sin_i, cos_i, ht_wrap_pi(phi_p + m->azim_sigma * n2));
    return p;
}

/* weight = value / pdf of the whole model at the drawn direction (MIS needs that pdf) */
HT_FIBER_FN int ht_zinke_sample_o(const HtMaterial* m, const HtMzWo* o, real3 wo, real h, real u0, real u1, real u2,
                            real u3, real3* wi, real3* weight, real* pdf) {
    real3 w;
    HtMarschnerAngles drawn;
    real inv_ep;
    ht_zinke_draw(m, o, wo, h, u0, u1, u2, u3, &w, &drawn, &inv_ep);
    real3 lobes[4];
    real3 value;
    real pd;
    ht_zinke_eval_o(m, o, wo, w, h, lobes, &value, &pd);
    return ht_finish_sample(w, value, pd, wi, weight, pdf);
}

/* Lobe p's value over the density with which the sampler draws its direction as lobe p,
 * pr_p M_p(theta_i) D(phi - Phi(p, h)): the azimuthal Gaussian is the same function in both and
 * cancels, which leaves A_p(h) 1/2 cos(theta_i)/cos^2(theta_d) g(theta_h - alpha_p) / (pr_p M_p),
 * one exp.  _a: given the direction's angles (phi unused) and inv_ep = 1/eta' at their theta_d.
 * Returns 0 (weight 0) where that density is 0. */
HT_FIBER_FN int ht_zinke_lobe_weight_a(const HtMaterial* m, const HtMzWo* o, const HtMarschnerAngles* a,
                                       real inv_ep, real h, int p, real3* weight) {
    const real eta = m->eta;
    const real3 ap = ht_marschner_ap_k(m, p, h, o->cos_gamma_i, eta, a->cos_d, inv_ep, ht_cos_theta_t(eta, a->sin_d));
    const real geo = HT_R(0.5) * a->cos_i / ht_max(a->cos_d * a->cos_d, HT_R(1e-6));
    real alpha, beta, eg, em;
    ht_mz_lobe_ab(m, p, &alpha, &beta);
    const real g = ht_gaussian_parts(a->theta_h - alpha, beta, &eg);
    const real mp = o->pr[p] * ht_mz_theta_pdf_parts(o, p, a->sin_i, a->cos_i, &em);
    *weight = ht_splat(HT_R(0));
    if (!(mp > HT_R(0))) return 0;
    *weight = ht_sanitize3(ap * (geo * g / mp * exp(eg - em)));
    return 1;
}
HT_FIBER_FN int ht_zinke_lobe_weight(const HtMaterial* m, const HtMzWo* o, real3 wo, real3 wi, real h, int p,
                                     real3* weight) {
    HtMarschnerAngles a;
    ht_mz_angles(o, wo, wi, &a);
    return ht_zinke_lobe_weight_a(m, o, &a, ht_inv_eta_prime(m->eta, a.sin_d, a.cos_d), h, p, weight);
}

/* For a caller without an MIS partner: the drawn lobe's value over its own density
 * (ht_zinke_lobe_weight, from the angles the draw made), an unbiased weight for the same
 * directions as ht_zinke_sample_o's (the one-sample estimator over the lobes), without evaluating
 * the other lobes or the mixture pdf.  Where the lobes overlap it is noisier than value / pdf;
 * docs/ESTIMATOR.md "The drawn lobe's weight" has what that costs and buys. */
HT_FIBER_FN int ht_zinke_sample_lobe_o(const HtMaterial* m, const HtMzWo* o, real3 wo, real h, real u0, real u1,
                                       real u2, real u3, real3* wi, real3* weight) {
    HtMarschnerAngles a;
    real inv_ep;
    const int p = ht_zinke_draw(m, o, wo, h, u0, u1, u2, u3, wi, &a, &inv_ep);
    return ht_zinke_lobe_weight_a(m, o, &a, inv_ep, h, p, weight);
}
HT_FIBER_FN int ht_zinke_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3,
                          real3* wi, real3* weight, real* pdf) {
    HtMzWo o;
    ht_zinke_wo(m, wo, h, &o);
    return ht_zinke_sample_o(m, &o, wo, h, u0, u1, u2, u3, wi, weight, pdf);
}

#endif
