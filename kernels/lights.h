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

#endif
