/* Dielectric Fresnel and the Bravais projected indices (docs/MODEL.md §2).
 *
 * The Bravais 2-D Fresnel F(gamma'; eta', eta'') with both polarisations sharing gamma_t' from eta'
 * equals the exact unpolarised 3-D Fresnel at cos(incidence) = cos(theta) cos(gamma'), so that is
 * what every model calls.  No total internal reflection occurs on the internal paths (§2). */
#ifndef HT_FIBER_FRESNEL_H
#define HT_FIBER_FRESNEL_H

#include "math.h"

/* Unpolarised reflectance, vacuum -> index eta >= 1, cosine of incidence ci (clamped to [0,1]). */
HT_FIBER_FN real ht_fresnel_dielectric(real ci, real eta) {
    ci = ht_clamp(ci, HT_R(0), HT_R(1));
    real st2 = (HT_R(1) - ci * ci) / (eta * eta);
    real ct = ht_safe_sqrt(HT_R(1) - st2);
    real rs = (ci - eta * ct) / ht_max(ci + eta * ct, HT_R(1e-30));
    real rp = (eta * ci - ct) / ht_max(eta * ci + ct, HT_R(1e-30));
    real f = HT_R(0.5) * (rs * rs + rp * rp);
    return ht_clamp(f, HT_R(0), HT_R(1));
}

/* 1/eta'(theta) = cos theta / sqrt(eta^2 - sin^2 theta): finite for every theta (-> 0 at 90 deg). */
HT_FIBER_FN real ht_inv_eta_prime(real eta, real sin_t, real cos_t) {
    return cos_t / sqrt(ht_max(eta * eta - sin_t * sin_t, HT_R(1e-30)));
}
/* eta''(theta) = eta^2 cos theta / sqrt(eta^2 - sin^2 theta) (-> 0 at 90 deg, finite). */
HT_FIBER_FN real ht_eta_pp(real eta, real sin_t, real cos_t) { return eta * eta * ht_inv_eta_prime(eta, sin_t, cos_t); }

/* cos theta_t of the refracted ray: sqrt(eta^2 - sin^2 theta)/eta >= sqrt(eta^2-1)/eta (never 0 for eta > 1). */
HT_FIBER_FN real ht_cos_theta_t(real eta, real sin_t) {
    return sqrt(ht_max(eta * eta - sin_t * sin_t, HT_R(1e-30))) / eta;
}

/* Transmittance of one internal chord: exp(-sigma_a 2 cos gamma_t / cos theta_t) (§4). */
HT_FIBER_FN real3 ht_chord_transmittance(real3 sigma_a, real cos_gamma_t, real cos_theta_t) {
    real l = HT_R(2) * cos_gamma_t / ht_max(cos_theta_t, HT_R(1e-6));
    return ht_exp3(sigma_a * (-l));
}

#endif
