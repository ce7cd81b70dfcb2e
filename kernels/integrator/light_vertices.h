/* Light-vertex next-event estimation (--light-vertices N; docs/ESTIMATOR.md "Light vertices").
 *
 * Deep in a lit lock a vertex's own next-event estimate mostly finds hair between it and the
 * light; the light that reaches it arrives through a fibre nearer the light that scatters it on.
 * Unidirectional paths find that fibre only when a continuation happens to hit it, and then its
 * light estimate is large: the rare, bright hair-to-hair samples.  Here each camera sample also
 * owns N light rays from the scene's lights (ht_light_ray); their first fibre hits are light
 * vertices, lit by construction.  A fibre vertex x connects to one of them, y, picked uniformly:
 * x's BCSDF towards y, y's towards the light, a shadow ray between the two -- a second strategy
 * for the paths x -> y -> light, which a continuation from x followed by y's next-event estimate
 * samples too.
 *
 * Fibres are lines at this scale, as where rays leave them (shading_point.h ht_fibre_spawn): a
 * vertex is a point (s, h) of a fibre, s along its axis and h across its width, on the measure
 * radius ds dh.  A ray of direction w sees the fibre's width 2 radius and its length foreshortened
 * by cos_w = sqrt(1 - (t . w)^2), so the densities on that measure (over the radius) are
 *   light vertex:   p_light(y) = share_l cos_l / (pi R_disc^2)       directional light
 *                   p_light(y) = share_l pdf_cone cos_l / d_l^2       point or spot light
 *   continuation:   p_cont(y)  = pdf_x(w) cos_w / r^2
 * (cos_l: the foreshortening towards the light, d_l: y's distance from it, share_l: its share of
 * the rays; r: from where the ray left x to y's axis).  y's offset h is the light ray's, uniform
 * on [-1, 1] like a continuation's, and y's BCSDF is evaluated as if the ray from x had hit it
 * there (the near field of hair-to-hair light, field auto).  The two strategies share each path
 * by the balance heuristic, the continuation's side counting N_A samples (the first vertex's
 * --first-hit-splits, else 1); with E the light reaching y unshadowed:
 *   connection:           value_x value_y E cos_w / (r^2 (N_A p_cont + p_light))
 *   continuation's NEE:   its estimate x N_A p_cont / (N_A p_cont + p_light)
 * Their weights sum to 1 on every path both can make, so the sum is unbiased; r and the densities
 * are taken from y's axis in both, so they agree to a fraction of a fibre radius over the
 * distance between the fibres.  Near y (r -> 0) the connection's term tends to
 * value_x value_y E / (N_A pdf_x): bounded, the continuation takes over.
 *
 * Why it does not pay in hair (docs/PERFORMANCE.md section 8 "Light-vertex next-event
 * estimation"): a connection outweighs the continuation only where p_light > p_cont, beyond
 * r = sqrt(pdf_x pi R_disc^2 / cos_l) -- some 70 units on pbrt's lock, which is 13 deep -- and
 * hair-to-hair light comes from fibres a few spacings away, behind which a far lit fibre is
 * mostly hidden. */
#ifndef HT_INTEGRATOR_LIGHT_VERTICES_H
#define HT_INTEGRATOR_LIGHT_VERTICES_H

#include "../types.h"
#include "../rng.h"
#include "../fiber/math.h"
#include "../geometry/basis.h"
#include "../geometry/facing.h"

/* The light of light ray j (0 .. count - 1 within its set): the lights take turns, so light l
 * starts the share n_l / count of them, n_l = the j with j mod light_count = l. */
HT_FN uint ht_light_vertex_light(uint j, uint light_count) { return j % light_count; }
HT_FN real ht_light_vertex_share(const HtLightVertices* lv, uint l, uint light_count) {
    const uint n = lv->count / light_count + (l < lv->count % light_count ? 1u : 0u);
    return (real)n / (real)lv->count;
}

/* The cone of directions from a point light at p towards the scene's bounding sphere: its axis
 * and the cosine of its half-angle (-1, the whole sphere, from inside). */
HT_FN real ht_light_cone(const HtLightVertices* lv, real3 p, real3* axis) {
    const real3 d = make_real3(lv->disc[0], lv->disc[1], lv->disc[2]) - p;
    const real d2 = dot(d, d), r2 = lv->disc[3] * lv->disc[3];
    *axis = d2 > HT_R(0) ? d * rsqrt(d2) : make_real3(0, 0, 1);
    return d2 > r2 ? sqrt(HT_R(1) - r2 / d2) : HT_R(-1);
}

/* Light ray i of a pass (0 .. count x samples - 1): set i / count belongs to camera sample
 * first_sample + i / count, ray j = i mod count of it to light ht_light_vertex_light(j).  A
 * directional light's ray starts uniformly on the disc across it that covers the bounding sphere;
 * a point or spot light's leaves it uniformly inside the cone towards that sphere (a spot's
 * falloff is in the light its vertices receive).  A Sobol' index per ray, so the rays of one set
 * are stratified.  Sphere lights start none (tmax < 0: no hit): their light keeps to the paths'
 * own estimates. */
HT_FN HtRay ht_light_ray(const HtLightVertices* lv, const HtLight* light, uint seed, uint i) {
    const uint set = i / lv->count, j = i - set * lv->count;
    real u, v;
    ht_sample2(seed, HT_LIGHT_RAY_PIXEL, (lv->first_sample + set) * lv->count + j, 0u, HT_DIM_LR_U, HT_DIM_LR_V, &u,
               &v);
    real sin_a, cos_a;
    ht_sincos(HT_TWO_PI * v, &sin_a, &cos_a);
    real3 o, w, e1, e2;
    if (light->type == HT_LIGHT_DIRECTIONAL) {
        w = make_real3(light->direction[0], light->direction[1], light->direction[2]);
        ht_onb(w, &e1, &e2);
        const real radius = lv->disc[3], rho = radius * sqrt(u);
        o = make_real3(lv->disc[0], lv->disc[1], lv->disc[2]) - w * (radius * HT_R(1.01)) + e1 * (rho * cos_a) +
            e2 * (rho * sin_a);
    } else {
        o = make_real3(light->position[0], light->position[1], light->position[2]);
        real3 axis;
        const real cos_max = ht_light_cone(lv, o, &axis);
        const real c = HT_R(1) - u * (HT_R(1) - cos_max);
        const real s = ht_safe_sqrt(HT_R(1) - c * c);
        ht_onb(axis, &e1, &e2);
        w = e1 * (s * cos_a) + e2 * (s * sin_a) + axis * c;
    }
    HtRay r;
    r.ox = o.x; r.oy = o.y; r.oz = o.z;
    r.dx = w.x; r.dy = w.y; r.dz = w.z;
    r.tmin = 0.0f;
    r.tmax = light->type == HT_LIGHT_SPHERE ? -1.0f : 1e30f;
    return r;
}

/* p_light of the header for the vertices of `light` (share and all) at the fibre through y with
 * tangent t: a directional light's rays cross its disc uniformly, a point light's leave it
 * uniformly inside its cone (ht_light_ray); 0 for a sphere light, which starts none. */
HT_FN real ht_light_vertex_density(const HtLightVertices* lv, const HtLight* light, uint l, uint light_count,
                                   real3 y, real3 t) {
    if (light->type == HT_LIGHT_SPHERE) return HT_R(0);
    const real share = ht_light_vertex_share(lv, l, light_count);
    if (light->type == HT_LIGHT_DIRECTIONAL) {
        const real3 w = make_real3(light->direction[0], light->direction[1], light->direction[2]);
        return share * ht_fibre_facing(t, w) / (HT_PI * lv->disc[3] * lv->disc[3]);
    }
    const real3 p = make_real3(light->position[0], light->position[1], light->position[2]);
    real3 axis;
    const real cos_max = ht_light_cone(lv, p, &axis);
    const real3 d = y - p;
    const real d2 = dot(d, d);
    if (!(d2 > HT_R(0))) return HT_R(0);
    return share * ht_fibre_facing(t, d * rsqrt(d2)) / (HT_TWO_PI * (HT_R(1) - cos_max) * d2);
}

/* p_cont of the header, times the continuations n_a: a ray that left x at `from` with solid-angle
 * density pdf reaching the fibre of tangent t whose axis point is y. */
HT_FN real ht_continuation_density(real n_a, real pdf, real3 from, real3 y, real3 t) {
    const real3 d = y - from;
    const real r2 = dot(d, d);
    if (!(r2 > HT_R(0))) return HT_R(0);
    return n_a * pdf * ht_fibre_facing(t, d * rsqrt(r2)) / r2;
}

/* The continuation's balance weight on its next-event estimate of a light that starts light vertices. */
HT_FN real ht_light_vertex_mis_continuation(real p_cont, real p_light) {
    return p_cont + p_light > HT_R(0) ? p_cont / (p_cont + p_light) : HT_R(1);
}

#endif
