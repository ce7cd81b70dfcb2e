/* Kajiya-Kay 1989 (docs/MODEL.md §8), normalised so kd and ks are albedos:
 *   value = kd cos(theta_i) / pi^2 + ks ks_norm max(0, cos(theta_i + theta_o))^p
 * cos(theta_i) = sin(t, l) (diffuse term); cos(theta_i + theta_o) = sin(t,l) sin(t,v) - (t.l)(t.v) is the
 * cosine to the nearest direction of the mirror cone theta_i = -theta_o (l, v pointing away from the
 * fibre; the "+" form in the literature uses the eye-ray direction).  The integral over the sphere of
 * the diffuse term is kd (dw = cos theta dtheta dphi); ks_norm = 1/(2 pi int cos^{p+1}) makes the
 * specular integral ks at theta_o = 0 and <= ks elsewhere.  No dependence on h or phi.
 * Sampling: mixture (by luminance) of the diffuse density cos theta_i / pi^2 (sin theta_i = x of a
 * uniform disk point) and a d'Eon lobe with v = 1/p around the mirror cone, phi uniform. */
#ifndef HT_FIBER_KAJIYA_H
#define HT_FIBER_KAJIYA_H

#include "../types.h"
#include "longitudinal.h"

HT_FIBER_FN real ht_kajiya_spec_v(const HtMaterial* m) { return HT_R(1) / ht_max(m->ks_exponent, HT_R(1e-3)); }

HT_FIBER_FN void ht_kajiya_probs(const HtMaterial* m, real* pd, real* ps) {
    real ld = ht_max(ht_luminance(ht_load3(m->kd)), HT_R(0)), ls = ht_max(ht_luminance(ht_load3(m->ks)), HT_R(0));
    real t = ld + ls;
    *pd = t > HT_R(0) ? ld / t : HT_R(1);
    *ps = t > HT_R(0) ? ls / t : HT_R(0);
}

HT_FIBER_FN void ht_kajiya_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value, real* pdf) {
    real sin_o, cos_o, sin_i, cos_i;
    ht_theta(wo, &sin_o, &cos_o);
    ht_theta(wi, &sin_i, &cos_i);
    real3 diff = ht_load3(m->kd) * (cos_i * (HT_INV_PI * HT_INV_PI));
    real c = cos_i * cos_o - sin_i * sin_o;
    real sp = ht_pow(c, m->ks_exponent) * m->ks_norm;
    real3 spec = ht_load3(m->ks) * sp;
    lobes[0] = spec;
    lobes[1] = ht_splat(HT_R(0));
    lobes[2] = ht_splat(HT_R(0));
    lobes[3] = diff;
    *value = ht_sanitize3(diff + spec);
    real pd, ps;
    ht_kajiya_probs(m, &pd, &ps);
    real pdf_d = cos_i * (HT_INV_PI * HT_INV_PI);
    real pdf_s = ht_mp(cos_i, sin_i, cos_o, sin_o, ht_kajiya_spec_v(m)) * HT_INV_TWO_PI;
    if (pdf) *pdf = ht_sanitize(pd * pdf_d + ps * pdf_s);
}

HT_FIBER_FN int ht_kajiya_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3,
                           real3* wi, real3* weight, real* pdf) {
    real pd, ps;
    ht_kajiya_probs(m, &pd, &ps);
    real sin_i, cos_i;
    if (u0 < pd) {
        real s, c;
        ht_sincos(HT_TWO_PI * u2, &s, &c);
        sin_i = ht_clamp(sqrt(u1) * c, HT_R(-1), HT_R(1));
        cos_i = ht_safe_sqrt(HT_R(1) - sin_i * sin_i);
    } else {
        real sin_o, cos_o;
        ht_theta(wo, &sin_o, &cos_o);
        ht_mp_sample(u1, u2, sin_o, cos_o, ht_kajiya_spec_v(m), &sin_i, &cos_i);
    }
    real3 w = ht_dir_from(wo, sin_i, cos_i, HT_TWO_PI * (u3 - HT_R(0.5)));
    real3 lobes[4];
    real3 value;
    real pdv;
    ht_kajiya_eval(m, wo, w, h, lobes, &value, &pdv);
    *wi = w;
    *pdf = pdv;
    if (!(pdv > HT_R(0))) {
        *weight = ht_splat(HT_R(0));
        return 0;
    }
    *weight = ht_sanitize3(value / pdv);
    return 1;
}

#endif
