/* Local frame of a fibre at a hit, the convention the fibre models use (docs/MODEL.md §1, pbrt):
 *
 *   x = t                                unit tangent, root -> tip
 *   z = normalize(wo - (wo . t) t)       wo projected into the normal plane (towards the viewer)
 *   y = cross(z, x)
 *
 * so in local coordinates sin(theta) = w.x and phi = atan2(w.z, w.y); the outgoing direction
 * has phi_o = +pi/2.  h = signed offset of the hit across the fibre in units of the radius,
 * dot(p_hit - p_axis, y) / r in [-1, 1] (p_axis = closest point on the axis).
 *
 * wo parallel to t has no projection: any unit vector perpendicular to t is used for z (the
 * azimuth is then undefined anyway and every model's phi-dependence degenerates).
 */
#ifndef HT_GEOMETRY_FIBER_FRAME_H
#define HT_GEOMETRY_FIBER_FRAME_H

#include "../compat.h"

/* A unit vector perpendicular to unit t: cross with the coordinate axis least aligned with t. */
HT_FN real3 ht_any_perpendicular(real3 t) {
    const real ax = fabs(t.x), ay = fabs(t.y), az = fabs(t.z);
    const real3 e = ax <= ay && ax <= az ? make_real3(HT_R(1), HT_R(0), HT_R(0))
                                         : (ay <= az ? make_real3(HT_R(0), HT_R(1), HT_R(0))
                                                     : make_real3(HT_R(0), HT_R(0), HT_R(1)));
    return normalize(cross(t, e));
}

HT_FN void ht_fiber_frame(real3 t, real3 wo, real3* x, real3* y, real3* z) {
    const real3 p = wo - t * dot(wo, t);
    const real p2 = dot(p, p);
    /* |p|^2 relative to |wo|^2: below 1e-12 the projection is rounding noise. */
    const real3 zz = p2 > HT_R(1e-12) * dot(wo, wo) ? p * (HT_R(1) / sqrt(p2)) : ht_any_perpendicular(t);
    *x = t;
    *z = zz;
    *y = cross(zz, t);
}

HT_FN real3 ht_to_fiber_local(real3 v, real3 x, real3 y, real3 z) {
    return make_real3(dot(v, x), dot(v, y), dot(v, z));
}

HT_FN real3 ht_from_fiber_local(real3 v, real3 x, real3 y, real3 z) {
    return x * v.x + y * v.y + z * v.z;
}

/* h from the hit's offset from the axis (p_hit - p_axis), the frame's y and the radius. */
HT_FN real ht_fiber_h(real3 offset, real3 y, real r) {
    return ht_clamp(dot(offset, y) / r, HT_R(-1), HT_R(1));
}

#endif /* HT_GEOMETRY_FIBER_FRAME_H */
