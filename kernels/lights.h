/* Next-event estimation: sample a direction towards one light from a shading point.
 *
 * Returns the incident radiance already divided by the sampling pdf (delta lights: the pdf is a
 * delta and cancels), so the direct-light estimate is  value(wo, wi) * li_over_pdf.
 * Deltas (point, spot, directional) cannot be hit by BCSDF-sampled rays; the sphere light can, and
 * its solid-angle pdf is returned for multiple importance sampling. */
#ifndef HT_LIGHTS_H
#define HT_LIGHTS_H

#include "types.h"

/* light types a scene lacks are compiled out (HT_FEATURE_LIGHT_*, kernels/features.h) */
#include "features.h"
#include "geometry/facing.h"

typedef struct {
    real3 wi;          /* unit direction from the shading point towards the light */
    real distance;     /* to the light sample (HT_REAL_MAX for directional) */
    real3 li_over_pdf; /* rgb */
    real pdf;          /* solid-angle pdf, 0 for delta lights */
} HtLightSample;

HT_FN real ht_smoothstep(real e0, real e1, real x) {
    real t = ht_clamp((x - e0) / ht_max(e1 - e0, HT_R(1e-12)), HT_R(0), HT_R(1));
    return t * t * (HT_R(3) - HT_R(2) * t);
}

HT_FN int ht_sample_light(const HtLight* l, real3 p, real u, real v, HtLightSample* s) {
    real3 lp = make_real3(l->position[0], l->position[1], l->position[2]);
    real3 rad = make_real3(l->radiance[0], l->radiance[1], l->radiance[2]);
    s->pdf = HT_R(0);
#if HT_FEATURE_LIGHT_DIRECTIONAL
    if (l->type == HT_LIGHT_DIRECTIONAL) {
        s->wi = -make_real3(l->direction[0], l->direction[1], l->direction[2]);
        s->distance = HT_REAL_MAX;
        s->li_over_pdf = rad;
        return 1;
    }
#endif
    real3 d = lp - p;
    real d2 = dot(d, d);
    if (!(d2 > HT_R(1e-20))) return 0;
    real dist = sqrt(d2);
    s->wi = d / dist;
#if HT_FEATURE_LIGHT_SPHERE
    if (l->type == HT_LIGHT_SPHERE && l->position[3] > 0.0f) {
        /* uniform direction inside the cone the sphere subtends (pbrt's sphere sampling) */
        real radius = l->position[3];
        real sin2max = ht_min(radius * radius / d2, HT_R(1));
        real cosmax = ht_safe_sqrt(HT_R(1) - sin2max);
        if (!(cosmax < HT_R(1) - HT_R(1e-7))) {
            /* numerically a point light: radiance * solid angle */
            real omega = HT_PI * sin2max;
            s->distance = dist - radius;
            s->li_over_pdf = rad * omega;
            return 1;
        }
        real cos_t = HT_R(1) - u * (HT_R(1) - cosmax);
        real sin_t = ht_safe_sqrt(HT_R(1) - cos_t * cos_t);
        real phi = HT_TWO_PI * v;
        real3 w = s->wi;
        real3 a = fabs(w.x) > HT_R(0.9) ? make_real3(0, 1, 0) : make_real3(1, 0, 0);
        real3 t1 = normalize(cross(a, w));
        real3 t2 = cross(w, t1);
        s->wi = normalize(w * cos_t + t1 * (sin_t * cos(phi)) + t2 * (sin_t * sin(phi)));
        /* distance to the sphere along the sampled direction */
        real b = dist * cos_t;
        real disc = radius * radius - (d2 - b * b);
        s->distance = b - ht_safe_sqrt(disc);
        real cone = HT_TWO_PI * (HT_R(1) - cosmax);
        s->pdf = HT_R(1) / cone;
        s->li_over_pdf = rad * cone;
        return 1;
    }
#endif
    real atten = HT_R(1) / d2;
#if HT_FEATURE_LIGHT_SPOT
    if (l->type == HT_LIGHT_SPOT) {
        real3 axis = make_real3(l->direction[0], l->direction[1], l->direction[2]);
        real c = -dot(s->wi, axis);
        atten *= ht_smoothstep(l->cos_outer, l->cos_inner, c);
    }
#endif
    s->distance = dist;
    s->li_over_pdf = rad * atten;
    return atten > HT_R(0);
}

/* ---------------------------------------------------------------- picking a light by importance */

/* The light sample the pick reads: u = v = 0 is the direction to the light's centre for every
 * type (a sphere's cone axis), and li_over_pdf depends on p alone for every light type (a delta
 * light's radiance over distance squared, the sphere's radiance times its cone), never on the
 * sample's numbers.  Returns 0 where the light gives nothing at p (outside a spot's cone, at its
 * position). */
HT_FN int ht_light_toward(const HtLight* l, real3 p, HtLightSample* s) {
    return ht_sample_light(l, p, HT_R(0), HT_R(0), s);
}

/* What the light of sample s delivers unshadowed, summed over the channels; capped so that a sum
 * over HT_LIGHT_PICK_MAX lights stays finite. */
HT_FN real ht_delivered(const HtLightSample* s) {
    const real w = s->li_over_pdf.x + s->li_over_pdf.y + s->li_over_pdf.z;
    return w > HT_R(0) ? ht_min(w, HT_R(1e30)) : HT_R(0);
}

/* How squarely direction w (unit, towards a light) faces the receiver, floored at
 * HT_LIGHT_FACING_MIN (never 0, so no light that reaches p loses its chance): for a fibre with
 * tangent `axis` the cosine of w's inclination to the fibre's normal plane, sqrt(1 - (axis . w)^2)
 * -- the fibre's width as the light sees it, the cos(theta_i) of every fibre model
 * (kernels/fiber/); for a surface with normal `axis` (axis_is_normal) |axis . w|.  What a light
 * delivers along a fibre's axis scatters little: a spot above a hanging lock is bright at the hair
 * and lights it hardly at all. */
#define HT_LIGHT_FACING_MIN HT_R(0.1)
HT_FN real ht_facing(real3 w, real3 axis, int axis_is_normal) {
    const real facing = axis_is_normal ? fabs(dot(axis, w)) : ht_fibre_facing(axis, w);
    return ht_max(facing, HT_LIGHT_FACING_MIN);
}

/* The two factors of ht_pick_light's weight for light l at p, each on its own. */
HT_FN real ht_light_delivered(const HtLight* l, real3 p) {
    HtLightSample s;
    return ht_light_toward(l, p, &s) ? ht_delivered(&s) : HT_R(0);
}
HT_FN real ht_light_facing(const HtLight* l, real3 p, real3 axis, int axis_is_normal) {
    HtLightSample s;
    return ht_light_toward(l, p, &s) ? ht_facing(s.wi, axis, axis_is_normal) : HT_R(1);
}

/* One of lights[0, count) for a next-event estimate at p (count <= HT_LIGHT_PICK_MAX), u in
 * [0, 1): light i with probability
 *     q_i = 1/2 w_i / sum_j w_j + 1/2 / n,   w = ht_light_delivered x ht_light_facing at p,
 * n the number of lights with w > 0 (q_i = 0 for the others: their estimate would be 0, a pick of
 * them a wasted sample).  w is chosen before the light's own sample numbers and never depends on
 * them, so the estimate L_i / q_i stays unbiased.  The uniform half is defensive: w knows nothing
 * of the hair between p and the light or of the fibre's lobes, and where the brightest light is
 * occluded, a pick by w alone starves the lights that do reach p (pure importance made the demo
 * scene's relative error worse while its RMSE improved; the even mix improved both most,
 * docs/PERFORMANCE.md §8).  Returns the light and 1 / q in *inv_prob, or count (and 0) when no
 * light gives anything at p. */
HT_FN uint ht_pick_light(HT_CONST_GLOBAL HtLight* lights, uint count, real3 p, real3 axis, int axis_is_normal,
                         real u, real* inv_prob) {
    real w[HT_LIGHT_PICK_MAX];
    real sum = HT_R(0), reach = HT_R(0);
    for (uint i = 0u; i < count; ++i) {
        const HtLight l = lights[i];
        HtLightSample s;
        w[i] = ht_light_toward(&l, p, &s) ? ht_delivered(&s) * ht_facing(s.wi, axis, axis_is_normal) : HT_R(0);
        sum += w[i];
        reach += w[i] > HT_R(0) ? HT_R(1) : HT_R(0);
    }
    *inv_prob = HT_R(0);
    if (!(sum > HT_R(0))) return count;
    const real by_w = HT_R(0.5) / sum, even = HT_R(0.5) / reach;
    real below = HT_R(0), q = HT_R(0);
    uint pick = count;
    for (uint i = 0u; i < count; ++i) {
        if (!(w[i] > HT_R(0))) continue;
        /* the last light that reaches p, if rounding leaves u past every one */
        pick = i;
        q = w[i] * by_w + even;
        if (u < below + q) break;
        below += q;
    }
    *inv_prob = HT_R(1) / q;
    return pick;
}

#endif
