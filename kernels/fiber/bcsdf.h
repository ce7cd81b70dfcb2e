/* Hair fibre scattering: the one entry point the renderer calls.
 *
 * Frame (docs/MODEL.md §1): +x = tangent root->tip, sin theta = w.x, phi = atan2(w.z, w.y); wo and wi
 * are unit vectors pointing away from the fibre; h in [-1, 1] is the signed offset of the hit across
 * the fibre in units of the radius (h = sin gamma_o in pbrt's sense).
 *
 * `value` is the scattering function with every cosine folded in:
 *     L_o(wo) = integral over the sphere of value(wo, wi, h) L_i(wi) dwi
 * (solid-angle measure, no extra cosine).  For chiang this is pbrt-v4's f(wo, wi) |cos theta_i|, so a
 * white fibre (sigma_a = 0) has integral value dwi = 1 for every wo and h.  `pdf` is the solid-angle
 * density with which ht_bcsdf_sample generates wi.  Both are finite and >= 0 for every input
 * (including non-unit / degenerate directions and h outside [-1, 1], which are clamped).
 *
 * Lobes (ht_bcsdf_eval_lobes): [0] R, [1] TT, [2] TRT (marschner/zinke: including the glint),
 * [3] residual (chiang: TRRT+; kajiya: the diffuse term, [0] its specular term).  Lobes compiled out
 * for the scene (lobes.h) are 0 and have no share in the pdf. */
#ifndef HT_FIBER_BCSDF_H
#define HT_FIBER_BCSDF_H

#include "../types.h"

/* models no material uses are compiled out (HT_FEATURE_MODEL_*, kernels/features.h) */
#include "../features.h"
/* shared building blocks; each model header below includes what it needs of them too.  They are
 * included here unconditionally because the host's kernel assembler (host/cl/kernel_source.cpp)
 * includes a file once, at its first textual #include, even inside an #if that is false. */
#include "math.h"
#include "lobes.h"
#include "fresnel.h"
#include "longitudinal.h"
#include "azimuthal.h"
#if HT_FEATURE_MODEL_KAJIYA
#include "kajiya.h"
#endif
#if HT_FEATURE_MODEL_CHIANG
#include "chiang.h"
#endif
#if HT_FEATURE_MODEL_MARSCHNER || HT_FEATURE_MODEL_ZINKE
#include "marschner.h" /* zinke reuses its attenuation, caustic and angle helpers */
#endif
#if HT_FEATURE_MODEL_ZINKE
#include "zinke.h"
#endif

/* Finite, non-zero direction (x - x == 0 exactly for finite x; NaN otherwise). */
HT_FIBER_FN int ht_valid_dir(real3 w) {
    real s = w.x * w.x + w.y * w.y + w.z * w.z;
    return (s - s == HT_R(0)) && s > HT_R(1e-30) && (w.x - w.x == HT_R(0)) && (w.y - w.y == HT_R(0)) && (w.z - w.z == HT_R(0));
}
HT_FIBER_FN real ht_sanitize_u(real u) { return (u == u) ? ht_clamp(u, HT_R(0), HT_R(0.99999994)) : HT_R(0); }

/* h as every model reads it: NaN -> 0, clamped to [-1, 1]. */
HT_FIBER_FN real ht_sanitize_h(real h) { return (h == h) ? ht_clamp(h, HT_R(-1), HT_R(1)) : HT_R(0); }

/* What eval and sample derive from wo and h alone, made once by ht_bcsdf_prepare for a shading
 * point that evaluates and samples the model several times (kernels/stages/shade.cl: one
 * evaluation per light estimate, one per sample).  Kajiya keeps nothing. */
typedef struct {
#if HT_FEATURE_MODEL_MARSCHNER || HT_FEATURE_MODEL_ZINKE
    HtMzWo mz;
#endif
#if HT_FEATURE_MODEL_CHIANG
    HtChiangSetup chiang;
#endif
    int unused; /* a struct needs a member when every model that keeps something is compiled out */
} HtBcsdfWo;

HT_FIBER_FN void ht_bcsdf_prepare(const HtMaterial* m, real3 wo, real h, HtBcsdfWo* o) {
    h = ht_sanitize_h(h);
#ifdef HT_HOST
    *o = HtBcsdfWo(); /* g++ cannot see that eval reads only the part prepared for the same model */
#endif
    o->unused = 0;
    switch (m->model) {
#if HT_FEATURE_MODEL_MARSCHNER
    case HT_MODEL_MARSCHNER: ht_marschner_wo(m, wo, &o->mz); break;
#endif
#if HT_FEATURE_MODEL_ZINKE
    case HT_MODEL_ZINKE: ht_zinke_wo(m, wo, h, &o->mz); break;
#endif
#if HT_FEATURE_MODEL_CHIANG
    case HT_MODEL_CHIANG: ht_chiang_setup(m, wo, h, &o->chiang); break;
#endif
    default: /* never read; defined, so that no compiler need prove it */
#if HT_FEATURE_MODEL_MARSCHNER || HT_FEATURE_MODEL_ZINKE
        ht_mz_wo_clear(&o->mz);
#endif
#if HT_FEATURE_MODEL_CHIANG
        ht_chiang_setup_clear(&o->chiang);
#endif
        break;
    }
}

/* Whether the model returns a delta/near-delta that next-event estimation cannot hit. */
HT_FIBER_FN int ht_bcsdf_is_delta(const HtMaterial* m) { return 0; }

/* o: ht_bcsdf_prepare of m, wo and h.  pdf may be 0 (no pointer): the pdf is then not computed
 * (marschner's and zinke's cost as much as a lobe each); a next-event estimate of a light that
 * BCSDF sampling cannot find needs none (kernels/stages/shade.cl ht_next_event). */
HT_FIBER_FN void ht_bcsdf_eval_lobes_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real3 wi, real h, real3* lobes,
                                 real3* value, real* pdf) {
    h = ht_sanitize_h(h);
    if (!ht_valid_dir(wo) || !ht_valid_dir(wi)) {
        for (int p = 0; p < 4; ++p) lobes[p] = ht_splat(HT_R(0));
        *value = ht_splat(HT_R(0));
        if (pdf) *pdf = HT_R(0);
        return;
    }
    switch (m->model) {
#if HT_FEATURE_MODEL_KAJIYA
    case HT_MODEL_KAJIYA: ht_kajiya_eval(m, wo, wi, h, lobes, value, pdf); break;
#endif
#if HT_FEATURE_MODEL_MARSCHNER
    case HT_MODEL_MARSCHNER: ht_marschner_eval_o(m, &o->mz, wo, wi, lobes, value, pdf); break;
#endif
#if HT_FEATURE_MODEL_ZINKE
    case HT_MODEL_ZINKE: ht_zinke_eval_o(m, &o->mz, wo, wi, h, lobes, value, pdf); break;
#endif
#if HT_FEATURE_MODEL_CHIANG
    case HT_MODEL_CHIANG: ht_chiang_eval_setup(m, &o->chiang, wo, wi, lobes, value, pdf); break;
#endif
    default:
        for (int p = 0; p < 4; ++p) lobes[p] = ht_splat(HT_R(0));
        *value = ht_splat(HT_R(0));
        if (pdf) *pdf = HT_R(0);
    }
}

HT_FIBER_FN void ht_bcsdf_eval_lobes(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value,
                               real* pdf) {
    HtBcsdfWo o;
    ht_bcsdf_prepare(m, wo, h, &o);
    ht_bcsdf_eval_lobes_o(m, &o, wo, wi, h, lobes, value, pdf);
}

HT_FIBER_FN void ht_bcsdf_eval_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real3 wi, real h, real3* value,
                           real* pdf) {
    real3 lobes[4];
    ht_bcsdf_eval_lobes_o(m, o, wo, wi, h, lobes, value, pdf);
}
// m: material in private memory; wo, wi: unit vectors in the fibre frame; h in [-1,1]
HT_FIBER_FN void ht_bcsdf_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* value, real* pdf) {
    HtBcsdfWo o;
    ht_bcsdf_prepare(m, wo, h, &o);
    ht_bcsdf_eval_o(m, &o, wo, wi, h, value, pdf);
}

/* o: ht_bcsdf_prepare of m, wo and h.  mixture 1: weight = value / pdf with pdf the whole
 * sampler's density at *wi (what MIS needs).  mixture 0, for a caller that has no MIS partner
 * (no light a sampled ray can meet): the same directions, and zinke and chiang weigh the drawn
 * lobe alone (ht_zinke_sample_lobe_o, ht_chiang_sample_lobe_setup: unbiased, cheaper) with *pdf
 * 0; kajiya and marschner as with 1. */
HT_FIBER_FN int ht_bcsdf_sample_mode_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real h, real u0, real u1,
                                       real u2, real u3, int mixture, real3* wi, real3* weight, real* pdf) {
    h = ht_sanitize_h(h);
    u0 = ht_sanitize_u(u0);
    u1 = ht_sanitize_u(u1);
    u2 = ht_sanitize_u(u2);
    u3 = ht_sanitize_u(u3);
    int ok = 0;
    if (ht_valid_dir(wo)) switch (m->model) {
#if HT_FEATURE_MODEL_KAJIYA
    case HT_MODEL_KAJIYA: ok = ht_kajiya_sample(m, wo, h, u0, u1, u2, u3, wi, weight, pdf); break;
#endif
#if HT_FEATURE_MODEL_MARSCHNER
    case HT_MODEL_MARSCHNER: ok = ht_marschner_sample_o(m, &o->mz, wo, u0, u1, u2, u3, wi, weight, pdf); break;
#endif
#if HT_FEATURE_MODEL_ZINKE
    case HT_MODEL_ZINKE:
        if (mixture) {
            ok = ht_zinke_sample_o(m, &o->mz, wo, h, u0, u1, u2, u3, wi, weight, pdf);
        } else {
            ok = ht_zinke_sample_lobe_o(m, &o->mz, wo, h, u0, u1, u2, u3, wi, weight);
            *pdf = HT_R(0);
        }
        break;
#endif
#if HT_FEATURE_MODEL_CHIANG
    case HT_MODEL_CHIANG:
        if (mixture) {
            ok = ht_chiang_sample_setup(m, &o->chiang, wo, u0, u1, u2, u3, wi, weight, pdf);
        } else {
            ok = ht_chiang_sample_lobe_setup(m, &o->chiang, wo, u0, u1, u2, u3, wi, weight);
            *pdf = HT_R(0);
        }
        break;
#endif
    default: break;
    }
    if (ok && !ht_valid_dir(*wi)) ok = 0;
    if (!ok) {
        *wi = make_real3(HT_R(1), HT_R(0), HT_R(0));
        *weight = ht_splat(HT_R(0));
        *pdf = HT_R(0);
    }
    return ok;
}
HT_FIBER_FN int ht_bcsdf_sample_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real h, real u0, real u1, real u2,
                            real u3, real3* wi, real3* weight, real* pdf) {
    return ht_bcsdf_sample_mode_o(m, o, wo, h, u0, u1, u2, u3, 1, wi, weight, pdf);
}

/* The lobes one at a time, for an estimator that weighs each lobe against another density on its
 * own (kernels/integrator/light_guide.h: a lobe drawn by the BCSDF then needs only that lobe's
 * density, not the whole model's).  Models whose lobes are sampled exactly, so that lobe p's value
 * at wi is colour_p times the density with which it draws wi: chiang.  For the others
 * ht_bcsdf_has_lobe_densities is 0 and the other two are not to be called. */
HT_FIBER_FN int ht_bcsdf_has_lobe_densities(const HtMaterial* m) {
#if HT_FEATURE_MODEL_CHIANG
    return m->model == HT_MODEL_CHIANG;
#else
    return 0;
#endif
}
/* Lobe p's share of the sampler's choice (its return), colour (*colour) and density at wi (*density). */
HT_FIBER_FN real ht_bcsdf_lobe_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real3 wi, int p, real3* colour,
                                 real* density) {
    *colour = ht_splat(HT_R(0));
    *density = HT_R(0);
#if HT_FEATURE_MODEL_CHIANG
    if (m->model == HT_MODEL_CHIANG && o->chiang.ap_pdf[p] > HT_R(0) && ht_valid_dir(wi)) {
        *colour = o->chiang.ap[p];
        *density = ht_sanitize(ht_chiang_lobe_density(m, &o->chiang, wo, wi, p));
        return o->chiang.ap_pdf[p];
    }
#endif
    return HT_R(0);
}
/* A direction drawn from the sampler's lobe choice (u0) and that lobe (u1..u3): returns the lobe,
 * or -1 when none could be drawn. */
HT_FIBER_FN int ht_bcsdf_draw_lobe_o(const HtMaterial* m, const HtBcsdfWo* o, real3 wo, real u0, real u1, real u2,
                                     real u3, real3* wi) {
    *wi = make_real3(HT_R(1), HT_R(0), HT_R(0));
#if HT_FEATURE_MODEL_CHIANG
    if (m->model == HT_MODEL_CHIANG && ht_valid_dir(wo)) {
        const int p = ht_chiang_draw(m, &o->chiang, wo, ht_sanitize_u(u0), ht_sanitize_u(u1), ht_sanitize_u(u2),
                                     ht_sanitize_u(u3), wi);
        return ht_valid_dir(*wi) ? p : -1;
    }
#endif
    return -1;
}

// mixture: as ht_bcsdf_sample_mode_o's
HT_FIBER_FN int ht_bcsdf_sample_mode(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3,
                                     int mixture, real3* wi, real3* weight, real* pdf) {
    HtBcsdfWo o;
    ht_bcsdf_prepare(m, wo, h, &o);
    return ht_bcsdf_sample_mode_o(m, &o, wo, h, u0, u1, u2, u3, mixture, wi, weight, pdf);
}
// u: 4 uniforms in [0,1). Returns 0 if no direction could be sampled. weight = value/pdf.
HT_FIBER_FN int ht_bcsdf_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3, real3* wi,
                          real3* weight, real* pdf) {
    return ht_bcsdf_sample_mode(m, wo, h, u0, u1, u2, u3, 1, wi, weight, pdf);
}

#endif
