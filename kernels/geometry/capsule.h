/* Ray vs one hair segment ("round segment"): a finite cylinder between two strand points plus
 * spheres at the joints, following Embree's ROUND_LINEAR_CURVE semantics
 * (anchors/embree/README.md "What Embree's round linear curve is"):
 *
 *   - the end sphere (at point + 1) always belongs to the segment;
 *   - the begin sphere only on a strand's first segment (HT_SEG_FIRST); every other begin joint
 *     is the previous segment's end sphere, so each joint is tested exactly once;
 *   - a strand is the union of its capsules: where a capsule overlaps its direct neighbours
 *     (the end sphere inside the next segment, the cylinders' slivers inside each other at a
 *     bend) its surface is interior and no hit (ht_inside_neighbour below; the traversal's leaf
 *     test, kernels/geometry/bvh_traverse.h, drops such roots and takes the capsule's next one);
 *   - entry and exit surfaces are both reported (no back-face culling), so a ray starting inside
 *     a fibre (overlapping fibres) hits the exit side;
 *   - a ray parallel to the segment axis misses the whole segment, spheres included (Embree's
 *     cone test rejects parallel rays; we match it so hit/miss agrees ray by ray).
 *
 * Radius: one radius per segment, the mean of its two point radii (cylinder and both spheres).
 * Per-point radii differ by a few percent at most in real hair, and a constant-radius capsule is
 * convex, which keeps the root selection below simple and exact.  A joint between segments with
 * different means gets the ending segment's radius.
 *
 * Precision (float in the kernels): everything is solved relative to the segment midpoint m and
 * to q = the point of the ray closest to m, so the quadratics see coordinates of the size of the
 * segment, not of the scene or of the ray origin's distance (far cameras, t ~ 1e4 L).  The
 * discriminants use the cross-product (Lagrange identity) form r^2 A - |q x d . w|^2, which has
 * no cancellation for thin fibres (r = 1e-5 L).
 *
 * Self-intersection: a ray whose origin lies on a segment's surface (|dist(o, axis) - r| < band)
 * ignores that segment entirely.  Rays spawned from a hit point are either leaving the fibre
 * (the exit root sits at t ~ 0 +- rounding) or travelling through it (TT); a hair BCSDF already
 * accounts for transport through the whole cross-section, so hitting the far side of the same
 * fibre would double count.  band = max(1e-3 r, 64 float ulps of the origin's largest
 * coordinate): the spawn point p = o + t d carries a rounding error of a few ulps of |p| (and of
 * the primary t), which is what the band must absorb.  It is kept that narrow because rays that
 * really start inside a fibre (overlapping fibres, the anchor's incoherent/shadow sets) must
 * still see its exit, as Embree does; only origins within the band of a surface lose it.
 * Fibres thinner than ~64 ulps of their coordinates (r/|p| < 8e-6) are below float resolution:
 * there the band exceeds r and a ray starting on or inside such a fibre never hits it.
 */
#ifndef HT_GEOMETRY_CAPSULE_H
#define HT_GEOMETRY_CAPSULE_H

#include "../types.h"

#define HT_SURFACE_TOL_REL HT_R(1e-3)
#define HT_SURFACE_TOL_ULPS HT_R(64)
/* |d_perp|^2 <= HT_PARALLEL_EPS * |d|^2 counts as parallel (angle below ~1e-6 rad). */
#define HT_PARALLEL_EPS HT_R(1e-12)

HT_FN real3 ht_point_pos(HtPoint p) { return make_real3(p.x, p.y, p.z); }

/* Closest intersection of the ray o + t d, t in (tmin, tmax), with the segment p0-p1 of radius
 * r.  Returns the hit distance, or tmax when there is none (so the caller's "t < best" test is
 * the only branch it needs).  d need not be unit length; t is in units of |d|. */
HT_FN real ht_capsule_intersect(real3 o, real3 d, real3 p0, real3 p1, real r, uint first,
                                real tmin, real tmax) {
    const real3 a = p1 - p0;
    const real L2 = dot(a, a);
    const real3 m = (p0 + p1) * HT_R(0.5);
    const real3 oc = o - m;
    const real dd = dot(d, d);
    const real t0 = -dot(oc, d) / dd;
    const real3 q = oc + d * t0; /* ray point closest to the midpoint */
    const real r2 = r * r;

    /* Bounding sphere of the capsule around m, radius L/2 + r, tested without the square root:
     * |q|^2 > L^2/4 + r^2 + L r  <=>  e > 0 and e^2 > L^2 r^2.  Most leaf candidates end here. */
    const real e = dot(q, q) - HT_R(0.25) * L2 - r2;
    if (e > HT_R(0) && e * e > L2 * r2) return tmax;

    const real L = sqrt(L2);
    const real invL = ht_select(L > HT_R(0), HT_R(1) / L, HT_R(0));
    /* Degenerate segment (repeated point): any axis works, the cylinder has zero length. */
    const real3 w = ht_select(L > HT_R(0), a * invL, make_real3(HT_R(1), HT_R(0), HT_R(0)));
    const real hl = HT_R(0.5) * L;

    const real dw = dot(d, w);
    const real3 dp = d - w * dw;
    const real A = dot(dp, dp);
    if (A <= HT_PARALLEL_EPS * dd) return tmax;

    /* Origin on this segment's surface: see the header comment. */
    const real so = ht_clamp(dot(oc, w), -hl, hl);
    const real3 ro = oc - w * so;
    const real ro2 = dot(ro, ro);
    const real omax = ht_max(ht_max(fabs(o.x), fabs(o.y)), fabs(o.z));
    const real band = ht_max(HT_SURFACE_TOL_REL * r, HT_SURFACE_TOL_ULPS * HT_REAL_EPS * omax);
    const real rin = ht_max(r - band, HT_R(0)), rout = r + band;
    if (ro2 > rin * rin && ro2 < rout * rout) return tmax;

    real best = tmax;
    const real qw = dot(q, w);

    /* Cylinder: |q_perp + dt d_perp|^2 = r^2; accept roots whose axial coordinate is inside. */
    const real cw = dot(cross(q, d), w);
    const real disc = A * r2 - cw * cw;
    if (disc >= HT_R(0)) {
        const real sq = sqrt(disc);
        const real B = dot(q, dp);
        const real invA = HT_R(1) / A;
        const real dt1 = (-B - sq) * invA;
        const real dt2 = (-B + sq) * invA;
        const real t1 = t0 + dt1, t2 = t0 + dt2;
        const real s1 = qw + dt1 * dw, s2 = qw + dt2 * dw;
        if (t1 > tmin && t1 < best && fabs(s1) <= hl) best = t1;
        if (t2 > tmin && t2 < best && fabs(s2) <= hl) best = t2;
    }

    /* End sphere (always owned): only its part beyond the end cap (s >= hl) is outer surface. */
    {
        const real3 rel = q - w * hl;
        const real b = dot(rel, d);
        const real3 c = cross(rel, d);
        const real sd = dd * r2 - dot(c, c);
        if (sd >= HT_R(0)) {
            const real sq = sqrt(sd);
            const real dt1 = (-b - sq) / dd, dt2 = (-b + sq) / dd;
            const real t1 = t0 + dt1, t2 = t0 + dt2;
            if (t1 > tmin && t1 < best && qw + dt1 * dw >= hl) best = t1;
            if (t2 > tmin && t2 < best && qw + dt2 * dw >= hl) best = t2;
        }
    }
    /* Begin sphere: only on a strand's first segment. */
    if (first) {
        const real3 rel = q + w * hl;
        const real b = dot(rel, d);
        const real3 c = cross(rel, d);
        const real sd = dd * r2 - dot(c, c);
        if (sd >= HT_R(0)) {
            const real sq = sqrt(sd);
            const real dt1 = (-b - sq) / dd, dt2 = (-b + sq) / dd;
            const real t1 = t0 + dt1, t2 = t0 + dt2;
            if (t1 > tmin && t1 < best && qw + dt1 * dw <= -hl) best = t1;
            if (t2 > tmin && t2 < best && qw + dt2 * dw <= -hl) best = t2;
        }
    }
    return best;
}

/* Whether the point joint + x lies strictly inside, by more than tol, the part of a neighbour
 * capsule (from the joint to joint + e, radius rn) that the neighbour owns: its cylinder and far
 * end, and the joint's sphere only when owns_joint (the previous segment owns the joint it ends
 * at; the next one does not, so a thicker next segment does not swallow the joint sphere that
 * closes the bend's outside).  A root there is on an interior surface of the strand.  Strictly,
 * because the outer surface is where a capsule's own surface is exactly rn from the neighbour's
 * axis (a straight strand's joint, the outside of a bend); tol (the surface band of
 * ht_capsule_intersect's self-intersection rule) keeps rounding from removing it.  x is relative
 * to the joint, so far rays keep the fibre-scale digits. */
HT_FN int ht_inside_neighbour(real3 x, real3 e, real rn, real tol, int owns_joint) {
    const real ee = dot(e, e);
    const real xe = dot(x, e);
    if (!owns_joint && !(xe > HT_R(0))) return 0;
    const real tau = ee > HT_R(0) ? ht_clamp(xe / ee, HT_R(0), HT_R(1)) : HT_R(0);
    const real3 y = x - e * tau;
    const real rin = rn - tol;
    return rin > HT_R(0) && dot(y, y) < rin * rin;
}

/* Hit point relative to the segment, for a t returned by ht_capsule_intersect: the offset from
 * the closest axis point (p_hit - p_axis), the unit tangent and u along the segment in [0,1].
 * Computed from q (closest ray point to the midpoint) so far origins keep the offset exact to
 * float precision relative to r. */
HT_FN real3 ht_capsule_hit_offset(real3 o, real3 d, real3 p0, real3 p1, real t, real3* tangent,
                                  real* u) {
    const real3 a = p1 - p0;
    const real L = sqrt(dot(a, a));
    const real3 w = ht_select(L > HT_R(0), a * (HT_R(1) / ht_max(L, HT_R(1e-30))), make_real3(HT_R(1), HT_R(0), HT_R(0)));
    const real hl = HT_R(0.5) * L;
    const real3 m = (p0 + p1) * HT_R(0.5);
    const real3 oc = o - m;
    const real t0 = -dot(oc, d) / dot(d, d);
    const real3 q = oc + d * t0;
    const real3 p = q + d * (t - t0); /* hit point relative to m */
    const real s = ht_clamp(dot(p, w), -hl, hl);
    *tangent = w;
    *u = ht_select(L > HT_R(0), ht_clamp((s + hl) / ht_max(L, HT_R(1e-30)), HT_R(0), HT_R(1)), HT_R(0));
    return p - w * s;
}

#endif /* HT_GEOMETRY_CAPSULE_H */
