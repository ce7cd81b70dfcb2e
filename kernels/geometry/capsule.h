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

/* The capsule test, written once for a lane type V: real (one capsule) and, in OpenCL, float8 (a
 * leaf's up to eight capsules, one per lane: the leaf test of kernels/geometry/bvh_traverse.h).  Each lane runs the
 * same operations in the same order, so a capsule's answer does not depend on the lane it is in.
 * M is the comparison result type (int for real, int8 for float8: lanes true = nonzero / -1),
 * SPLAT(x) widens a real to V, ANY(m) / ALL(m) reduce a mask to a branch condition.  SKIP (a
 * constant) says whether the test branches past work that no lane needs: the scalar instance does
 * (it returns at the first early out), the float8 instance does not, but for the begin sphere
 * (only a strand's first segment has one, so that branch is rarely taken and well predicted).
 * Which of a leaf's capsules pass the bounding sphere, the surface band or a root's discriminant is
 * data-dependent, so those branches were mispredicted; computing every lane is cheaper
 * (host/bvh/NOTES.md "Fewer data-dependent branches").  Every lane's result is selected by its own
 * mask (masked lanes may hold inf or NaN, compared false and replaced by tmax at the end), so
 * neither the early outs nor their absence can change an answer.
 * Arguments: p0 = (ax, ay, az), p1 = (bx, by, bz), radius r, first = the lane owns its begin
 * sphere (HT_SEG_FIRST), all per lane; returns the hit distance per lane, tmax for none. */
#define HT_CAPSULE_LANES(NAME, V, M, SPLAT, ANY, ALL, DOT, DIF, SKIP)                                   \
    HT_FN V NAME(real3 o, real3 d, V ax, V ay, V az, V bx, V by, V bz, V r, M first, real tmin,         \
                 real tmax) {                                                                           \
        const V ex = bx - ax, ey = by - ay, ez = bz - az;                                               \
        const V L2 = DOT(ex, ey, ez, ex, ey, ez);                                                       \
        const V mx = (ax + bx) * HT_R(0.5), my = (ay + by) * HT_R(0.5), mz = (az + bz) * HT_R(0.5);     \
        const V ox = o.x - mx, oy = o.y - my, oz = o.z - mz;                                            \
        const real dd = dot(d, d);                                                                      \
        const V t0 = -DOT(ox, oy, oz, d.x, d.y, d.z) / dd;                                              \
        /* q: the ray point closest to the midpoint */                                                  \
        const V qx = ox + d.x * t0, qy = oy + d.y * t0, qz = oz + d.z * t0;                             \
        const V r2 = r * r;                                                                             \
        /* Bounding sphere of the capsule around m, radius L/2 + r, tested without the square root:     \
         * |q|^2 > L^2/4 + r^2 + L r  <=>  e > 0 and e^2 > L^2 r^2.  Most candidates miss it. */        \
        const V e = DOT(qx, qy, qz, qx, qy, qz) - HT_R(0.25) * L2 - r2;                                 \
        M miss = (e > HT_R(0)) & (e * e > L2 * r2);                                                     \
        if (SKIP && ALL(miss)) return SPLAT(tmax);                                                      \
        const V L = sqrt(L2);                                                                           \
        const M pos = L > HT_R(0);                                                                      \
        const V invL = pos ? HT_R(1) / L : SPLAT(HT_R(0));                                              \
        /* Degenerate segment (repeated point): any axis works, the cylinder has zero length. */        \
        const V wx = pos ? ex * invL : SPLAT(HT_R(1)), wy = pos ? ey * invL : SPLAT(HT_R(0));           \
        const V wz = pos ? ez * invL : SPLAT(HT_R(0));                                                  \
        const V hl = HT_R(0.5) * L;                                                                     \
        const V dw = DOT(d.x, d.y, d.z, wx, wy, wz);                                                    \
        const V px = d.x - wx * dw, py = d.y - wy * dw, pz = d.z - wz * dw;                             \
        const V A = DOT(px, py, pz, px, py, pz);                                                        \
        miss |= A <= HT_PARALLEL_EPS * dd;                                                              \
        if (SKIP && ALL(miss)) return SPLAT(tmax);                                                      \
        /* Origin on this segment's surface: see the header comment. */                                 \
        const V so0 = DOT(ox, oy, oz, wx, wy, wz);                                                      \
        const V so = so0 < -hl ? -hl : (so0 > hl ? hl : so0);                                           \
        const V rox = ox - wx * so, roy = oy - wy * so, roz = oz - wz * so;                             \
        const V ro2 = DOT(rox, roy, roz, rox, roy, roz);                                                \
        const real omax = ht_max(ht_max(fabs(o.x), fabs(o.y)), fabs(o.z));                              \
        const V band_r = HT_SURFACE_TOL_REL * r, band_o = SPLAT(HT_SURFACE_TOL_ULPS * HT_REAL_EPS * omax); \
        const V band = band_r > band_o ? band_r : band_o;                                               \
        const V rin = r - band > HT_R(0) ? r - band : SPLAT(HT_R(0)), rout = r + band;                  \
        miss |= (ro2 > rin * rin) & (ro2 < rout * rout);                                                \
        if (SKIP && ALL(miss)) return SPLAT(tmax);                                                      \
                                                                                                        \
        V best = SPLAT(tmax);                                                                           \
        const V qw = DOT(qx, qy, qz, wx, wy, wz);                                                       \
        /* Cylinder: |q_perp + dt d_perp|^2 = r^2; accept roots whose axial coordinate is inside.       \
         * The discriminant in the Lagrange form r^2 A - ((q x d) . w)^2. */                            \
        const V cw = DOT(DIF(qy, d.z, qz, d.y), DIF(qz, d.x, qx, d.z), DIF(qx, d.y, qy, d.x), wx, wy, wz); \
        const V disc = A * r2 - cw * cw;                                                                \
        const M cyl = disc >= HT_R(0);                                                                  \
        if (!SKIP || ANY(cyl)) {                                                                        \
            const V sq = sqrt(cyl ? disc : SPLAT(HT_R(0)));                                             \
            const V B = DOT(qx, qy, qz, px, py, pz);                                                    \
            const V invA = HT_R(1) / A;                                                                 \
            const V dt1 = (-B - sq) * invA, dt2 = (-B + sq) * invA;                                     \
            const V t1 = t0 + dt1, t2 = t0 + dt2;                                                       \
            const V s1 = qw + dt1 * dw, s2 = qw + dt2 * dw;                                             \
            best = (cyl & (t1 > tmin) & (t1 < best) & (fabs(s1) <= hl)) ? t1 : best;                    \
            best = (cyl & (t2 > tmin) & (t2 < best) & (fabs(s2) <= hl)) ? t2 : best;                    \
        }                                                                                               \
        /* End sphere (always owned): only its part beyond the end cap (s >= hl) is outer surface. */   \
        {                                                                                               \
            const V rx = qx - wx * hl, ry = qy - wy * hl, rz = qz - wz * hl;                            \
            const V b = DOT(rx, ry, rz, d.x, d.y, d.z);                                                 \
            const V cx = DIF(ry, d.z, rz, d.y), cy = DIF(rz, d.x, rx, d.z), cz = DIF(rx, d.y, ry, d.x); \
            const V sd = dd * r2 - DOT(cx, cy, cz, cx, cy, cz);                                         \
            const M in = sd >= HT_R(0);                                                                 \
            if (!SKIP || ANY(in)) {                                                                     \
                const V sq = sqrt(in ? sd : SPLAT(HT_R(0)));                                            \
                const V dt1 = (-b - sq) / dd, dt2 = (-b + sq) / dd;                                     \
                const V t1 = t0 + dt1, t2 = t0 + dt2;                                                   \
                best = (in & (t1 > tmin) & (t1 < best) & (qw + dt1 * dw >= hl)) ? t1 : best;            \
                best = (in & (t2 > tmin) & (t2 < best) & (qw + dt2 * dw >= hl)) ? t2 : best;            \
            }                                                                                           \
        }                                                                                               \
        /* Begin sphere: only on a strand's first segment. */                                           \
        if (ANY(first)) {                                                                               \
            const V rx = qx + wx * hl, ry = qy + wy * hl, rz = qz + wz * hl;                            \
            const V b = DOT(rx, ry, rz, d.x, d.y, d.z);                                                 \
            const V cx = DIF(ry, d.z, rz, d.y), cy = DIF(rz, d.x, rx, d.z), cz = DIF(rx, d.y, ry, d.x); \
            const V sd = dd * r2 - DOT(cx, cy, cz, cx, cy, cz);                                         \
            const M in = first & (sd >= HT_R(0));                                                       \
            if (ANY(in)) {                                                                              \
                const V sq = sqrt(in ? sd : SPLAT(HT_R(0)));                                            \
                const V dt1 = (-b - sq) / dd, dt2 = (-b + sq) / dd;                                     \
                const V t1 = t0 + dt1, t2 = t0 + dt2;                                                   \
                best = (in & (t1 > tmin) & (t1 < best) & (qw + dt1 * dw <= -hl)) ? t1 : best;           \
                best = (in & (t2 > tmin) & (t2 < best) & (qw + dt2 * dw <= -hl)) ? t2 : best;           \
            }                                                                                           \
        }                                                                                               \
        return miss ? SPLAT(tmax) : best;                                                               \
    }

/* DOT(a, b) = a.x b.x + a.y b.y + a.z b.z and DIF(a, b, c, d) = a b - c d.  In OpenCL as fused
 * multiply-adds, written out with fma() (PoCL defines no FP_FAST_FMAF although it makes these
 * vfmadd, and mad() stayed a product and a sum there): the compiled grid stage holds 37 more fused
 * instructions (82 -> 119), each one instruction for a product and a sum, and the ball's grid sets
 * came 0.03-0.08 nearer Embree (medians of fifteen rounds; host/bvh/NOTES.md "The grid walked by
 * eight rays at once; fused multiply-adds in the capsule test").  Every device this renderer
 * targets has the instruction (x86-64 CPUs since 2013, ARMv8, GPUs); on one without it fma() stays
 * exact but slow.
 * The same for one lane and for eight, so a capsule's t does not depend on which structure's test
 * finds it (tree leaves, path grid, lists).  Plain products and sums in C++ (the host's double
 * reference). */
#ifdef HT_OPENCL
#define HT_LANE_ARITH(SUF, V)                                                                          \
    HT_FN V ht_dot3##SUF(V ax, V ay, V az, V bx, V by, V bz) { return fma(ax, bx, fma(ay, by, az * bz)); } \
    HT_FN V ht_dif##SUF(V a, V b, V c, V d) { return fma(a, b, -(c * d)); }
HT_LANE_ARITH(1, float)
HT_LANE_ARITH(8, float8)
#else
HT_FN real ht_dot31(real ax, real ay, real az, real bx, real by, real bz) { return ax * bx + ay * by + az * bz; }
HT_FN real ht_dif1(real a, real b, real c, real d) { return a * b - c * d; }
#endif
#define HT_LANE1_SPLAT(x) (x)
#define HT_LANE1_TEST(m) (m)
HT_CAPSULE_LANES(ht_capsule_lane1, real, int, HT_LANE1_SPLAT, HT_LANE1_TEST, HT_LANE1_TEST, ht_dot31, ht_dif1, 1)
#ifdef HT_OPENCL
#define HT_LANE8_SPLAT(x) ((float8)(x))
HT_CAPSULE_LANES(ht_capsule_lane8, float8, int8, HT_LANE8_SPLAT, any, all, ht_dot38, ht_dif8, 0)
#endif

/* Closest intersection of the ray o + t d, t in (tmin, tmax), with the segment p0-p1 of radius
 * r.  Returns the hit distance, or tmax when there is none (so the caller's "t < best" test is
 * the only branch it needs).  d need not be unit length; t is in units of |d|. */
HT_FN real ht_capsule_intersect(real3 o, real3 d, real3 p0, real3 p1, real r, uint first,
                                real tmin, real tmax) {
    return ht_capsule_lane1(o, d, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, r, first != 0u, tmin, tmax);
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
