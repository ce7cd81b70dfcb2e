/* Light-guided continuations (--light-guiding F; docs/ESTIMATOR.md "Light-guided continuations").
 *
 * In a lit lock much of the hair-to-hair light arrives through a chain that ends at a fibre lying
 * between the path and a light: the path's next vertex sees the light through its forward (TT)
 * lobe, a few degrees wide, or its R/TRT cone.  A continuation drawn from the BCSDF alone rarely
 * leaves along such a line, and when it does the next vertex's light estimate is large: rare,
 * bright samples.  Here a share F of a fibre vertex's continuations is drawn instead from a
 * von Mises-Fisher lobe around the direction to a light (one of the lights that reach the vertex,
 * picked uniformly), the rest from the BCSDF, and every continuation is weighted by the value over
 * the mixture's density (one-sample balance heuristic):
 *   pdf(w) = F * mean_l vMF(w; mu_l, kappa) + (1 - F) * pdf_bcsdf(w),   weight = value(w) / pdf(w).
 * Unbiased for any F in [0, 1): the BCSDF part keeps every direction the fibre scatters into
 * reachable.  The vertex's next-event estimate competes by MIS with that same density where the
 * light can be found by a continuation (an environment map).  That costs one full BCSDF
 * evaluation per continuation (the lobe-only weight of kernels/fiber/bcsdf.h cannot give the
 * mixture's pdf).  Where no light can be met by a continuation (no MIS partner) and the model's
 * lobes are sampled exactly (chiang, ht_bcsdf_has_lobe_densities), each lobe p is instead weighed
 * against the guide on its own, as if the vertex had two strategies per lobe, the guide and lobe p
 * (share (1 - F) c_p, c_p the BCSDF's choice of p):
 *   BCSDF draw of lobe p:  A_p d_p / (F guide + (1 - F) c_p d_p)       (d_p: lobe p's density)
 *   guide draw:            sum_p A_p d_p / (F guide + (1 - F) c_p d_p)
 * Unbiased (for each lobe the two strategies' balance weights sum to 1 wherever either can draw),
 * and a BCSDF draw evaluates one lobe instead of all: on pbrt's lock about 0.9x the shade stage's
 * time per sample for 0.3 % more error (docs/PERFORMANCE.md section 8 "Per-lobe weights for guided
 * continuations").
 * Triangles (Lambertian surfaces) are not guided.  Undefined HT_LIGHT_GUIDE: compiled out. */
#ifndef HT_INTEGRATOR_LIGHT_GUIDE_H
#define HT_INTEGRATOR_LIGHT_GUIDE_H

#include "../types.h"
#include "../lights.h"
#include "shading_point.h"
#include "../geometry/basis.h"

/* The guide lobe's concentration: about 1/sqrt(kappa) = 18 degrees of spread, the order of a
 * forward lobe's width after a bounce or two of roughness; measured flat between 5 and 30 on pbrt's
 * lock (docs/PERFORMANCE.md section 8 "Light-guided continuations"). */
#define HT_GUIDE_KAPPA HT_R(10)
/* Continuations guided: those of a path's first HT_GUIDE_VERTICES vertices.  A guided weight is
 * 1 / (F r + 1 - F) times the BCSDF-sampled one (r = the guide's density over the BCSDF's): 1 on
 * average, up to 1 / (1 - F), and a path of hundreds of bounces in a bright lock multiplies
 * hundreds of them, a product whose spread grows without bound (the dense-lock furnace,
 * tests/render/furnace_test.cpp, had single pixels at 6.5 with every vertex guided).  The light
 * that the guide finds arrives within a few bounces of it anyway. */
#define HT_GUIDE_VERTICES 4u
/* Lights beyond this many are not guided towards (each costs a direction and a pdf term per
 * continuation); the same bound as the importance pick's. */
#define HT_GUIDE_MAX_LIGHTS 16u

/* von Mises-Fisher density on the sphere around unit mu: kappa / (2 pi (1 - e^{-2 kappa})) e^{kappa (mu.w - 1)}. */
HT_FN real ht_vmf_pdf(real3 mu, real3 w) {
    const real k = HT_GUIDE_KAPPA;
    return k / (HT_TWO_PI * (HT_R(1) - exp(HT_R(-2) * k))) * exp(k * (ht_min(dot(mu, w), HT_R(1)) - HT_R(1)));
}

/* A direction from that density: cos of the angle to mu by inversion, azimuth uniform. */
HT_FN real3 ht_vmf_sample(real3 mu, real u1, real u2) {
    const real k = HT_GUIDE_KAPPA;
    const real c = ht_clamp(HT_R(1) + ht_log(u1 + (HT_R(1) - u1) * exp(HT_R(-2) * k)) / k, HT_R(-1), HT_R(1));
    const real s = sqrt(ht_max(HT_R(0), HT_R(1) - c * c));
    real sin_a, cos_a;
    ht_sincos(HT_TWO_PI * u2, &sin_a, &cos_a);
    real3 t, bt;
    ht_onb(mu, &t, &bt);
    return t * (s * cos_a) + bt * (s * sin_a) + mu * c;
}

/* The lights the guide aims at, the first HT_GUIDE_MAX_LIGHTS that reach p (kernels/lights.h
 * ht_light_toward): returns how many; the direction to the k-th of them in *mu (k < that count;
 * k = light_count asks for none), and, unless pdf is 0, the guide's density at w, the mean of
 * their vMF lobes (0 when none reaches p), in *pdf. */
HT_FN uint ht_guide_lights(HT_CONST_GLOBAL HtLight* lights, uint light_count, real3 p, uint k, real3* mu, real3 w,
                           real* pdf) {
    uint n = 0u;
    real sum = HT_R(0);
    const uint m = light_count < HT_GUIDE_MAX_LIGHTS ? light_count : HT_GUIDE_MAX_LIGHTS;
    for (uint i = 0u; i < m; ++i) {
        HtLight l = lights[i];
        HtLightSample s;
        if (!ht_light_toward(&l, p, &s)) continue;
        if (n == k) *mu = s.wi;
        if (pdf) sum += ht_vmf_pdf(s.wi, w);
        ++n;
    }
    if (pdf) *pdf = n ? sum / (real)n : HT_R(0);
    return n;
}

/* The density with which ht_point_sample_guided draws w at sp (a vertex of `bounce`), given the
 * BCSDF's pdf_bsdf there: the MIS partner of a next-event estimate that a continuation could also find. */
HT_FN real ht_guided_pdf(const HtShadingPoint* sp, HT_CONST_GLOBAL HtLight* lights, uint light_count, real share,
                         uint bounce, real3 w, real pdf_bsdf) {
    if (sp->is_surface || bounce >= HT_GUIDE_VERTICES) return pdf_bsdf;
    real3 unused;
    real guide;
    const uint n = ht_guide_lights(lights, light_count, sp->p, light_count, &unused, w, &guide);
    return n ? share * guide + (HT_R(1) - share) * pdf_bsdf : pdf_bsdf;
}

/* The per-lobe weight of the header comment at wl (fibre frame), guide = the guide's density there: lobe
 * `drawn`'s term for a BCSDF draw of that lobe, the sum over the lobes for a guided draw (drawn < 0). */
HT_FN real3 ht_guided_lobes_weight(const HtShadingPoint* sp, real share, real guide, real3 wl, int drawn) {
    real3 sum = make_real3(0, 0, 0), colour;
    real density;
    for (int p = drawn < 0 ? 0 : drawn; p <= (drawn < 0 ? 3 : drawn); ++p) {
        const real pick = ht_bcsdf_lobe_o(&sp->mat, &sp->wo_prep, sp->wo_l, wl, p, &colour, &density);
        const real d = share * guide + (HT_R(1) - share) * pick * density;
        if (pick > HT_R(0) && d > HT_R(0)) sum += colour * (density / d);
    }
    return ht_sanitize3(sum);
}

/* ht_point_sample with a share of the continuation drawn towards the lights (header comment).
 * u0 decides between the guide (u0 < share; u0 / share then picks the light) and the BCSDF
 * ((u0 - share) / (1 - share) is the BCSDF's own u0), so the sampler's dimensions are the same as
 * ht_point_sample's.  mixture 1: *pdf is the mixture's density and the weight value / *pdf (what
 * MIS needs); 0: the per-lobe weights where the model has them (*pdf then 0), else as 1; and
 * ht_point_sample's meaning for a vertex nothing guides (a surface, or no light reaches it). */
HT_FN int ht_point_sample_guided(const HtShadingPoint* sp, HT_CONST_GLOBAL HtLight* lights, uint light_count,
                                 real share, uint seed, uint pixel, uint sample, uint bounce, int mixture,
                                 real3* wi, real3* weight, real* pdf) {
    real3 mu = make_real3(0, 0, 1);
    const uint n = sp->is_surface || bounce >= HT_GUIDE_VERTICES
                       ? 0u
                       : ht_guide_lights(lights, light_count, sp->p, light_count, &mu, mu, 0);
    if (n == 0u) return ht_point_sample(sp, seed, pixel, sample, bounce, mixture, wi, weight, pdf);
    real u0, u1, u2, u3;
    ht_sample2(seed, pixel, sample, bounce, HT_DIM_BSDF_0, HT_DIM_BSDF_0 + 3u, &u0, &u3);
    ht_sample2(seed, pixel, sample, bounce, HT_DIM_BSDF_0 + 1u, HT_DIM_BSDF_0 + 2u, &u1, &u2);
    real3 value;
    real pdf_bsdf = HT_R(0);
    *weight = make_real3(0, 0, 0);
    *pdf = HT_R(0);
    /* per-lobe weights (header comment): the lobe a BCSDF draw took, -1 for a guided draw */
    const int per_lobe = !mixture && ht_bcsdf_has_lobe_densities(&sp->mat);
    int drawn = -1;
    real3 wl;
    if (u0 < share) {
        uint k = (uint)(u0 / share * (real)n);
        k = k < n ? k : n - 1u;
        ht_guide_lights(lights, light_count, sp->p, k, &mu, mu, 0);
        *wi = ht_vmf_sample(mu, u1, u2);
        if (per_lobe)
            wl = ht_to_fiber_local(*wi, sp->fx, sp->fy, sp->fz);
        else
            ht_point_eval(sp, *wi, &value, &pdf_bsdf);
    } else {
        real3 w;
        const real ub = ht_min((u0 - share) / (HT_R(1) - share), HT_R(0.99999994));
        if (per_lobe) {
            drawn = ht_bcsdf_draw_lobe_o(&sp->mat, &sp->wo_prep, sp->wo_l, ub, u1, u2, u3, &wl);
            if (drawn < 0) return 0;
            *wi = sp->fx * wl.x + sp->fy * wl.y + sp->fz * wl.z;
        } else {
            if (!ht_point_sample_fibre(sp, ub, u1, u2, u3, 1, wi, &w, &pdf_bsdf)) return 0;
            value = w * pdf_bsdf;
        }
    }
    real guide;
    ht_guide_lights(lights, light_count, sp->p, light_count, &mu, *wi, &guide);
    if (per_lobe) {
        *weight = ht_guided_lobes_weight(sp, share, guide, wl, drawn);
        return weight->x + weight->y + weight->z > HT_R(0);
    }
    const real p = share * guide + (HT_R(1) - share) * pdf_bsdf;
    if (!(p > HT_R(0))) return 0;
    *pdf = p;
    *weight = ht_sanitize3(value / p);
    return 1;
}

#endif
