/* Lambertian (ideal diffuse) surface BSDF for triangle meshes, portable (kernels: float, host
 * tests: double).
 *
 * f = albedo / pi on the side of the shading normal ns the light arrives from (wo's side).
 * Sampling is cosine-weighted around ns (Malley: uniform disk, projected up), pdf = cos / pi, so
 * f cos / pdf = albedo exactly: the throughput never grows and a white (albedo 1) furnace stays
 * at 1.  Directions below the geometric normal ng are refused in both evaluation and sampling:
 * interpolated shading normals may lean past ng, and letting light through there would leak it
 * through the surface.
 */
#ifndef HT_SURFACE_LAMBERT_H
#define HT_SURFACE_LAMBERT_H

#include "../compat.h"
#include "../geometry/basis.h"

/* Both normals must already face wo (ht_lambert_face_forward).  Returns f * cos(ns, wi) per
 * unit albedo, i.e. cos / pi, and the sampling pdf of wi in *pdf (solid angle). */
HT_FN real ht_lambert_eval(real3 ns, real3 ng, real3 wi, real* pdf) {
    const real c = dot(ns, wi);
    if (c <= HT_R(0) || dot(ng, wi) <= HT_R(0)) {
        if (pdf) *pdf = HT_R(0);
        return HT_R(0);
    }
    if (pdf) *pdf = c * HT_INV_PI;
    return c * HT_INV_PI;
}

/* Cosine-weighted direction around ns from two uniforms.  Returns 0 (path absorbed) when the
 * sample falls below ng; otherwise *wi, its pdf, and the weight f cos / pdf = 1 per unit albedo. */
HT_FN int ht_lambert_sample(real3 ns, real3 ng, real u0, real u1, real3* wi, real* pdf) {
    const real r = sqrt(u0);
    const real phi = HT_TWO_PI * u1;
    const real x = r * cos(phi), y = r * sin(phi);
    const real z = ht_safe_sqrt(HT_R(1) - u0);
    real3 t, b;
    ht_onb(ns, &t, &b);
    const real3 w = t * x + b * y + ns * z;
    if (z <= HT_R(0) || dot(ng, w) <= HT_R(0)) return 0;
    *wi = w;
    *pdf = z * HT_INV_PI;
    return 1;
}

/* Turns ng towards wo (the viewer's side: both faces of a triangle are surfaces) and ns to ng's
 * side; an unusable ns (zero) becomes ng. */
HT_FN void ht_lambert_face_forward(real3 wo, real3* ng, real3* ns) {
    if (dot(*ng, wo) < HT_R(0)) *ng = -*ng;
    const real l2 = dot(*ns, *ns);
    if (!(l2 > HT_R(1e-12))) {
        *ns = *ng;
        return;
    }
    *ns = *ns * (HT_R(1) / sqrt(l2));
    if (dot(*ns, *ng) < HT_R(0)) *ns = -*ns;
}

#endif /* HT_SURFACE_LAMBERT_H */
