/* Ray vs triangle (Möller-Trumbore), shared by the kernels (float) and the host tests (double).
 *
 * Triangles live in the same BVH as the hair capsules (see bvh_traverse.h): a leaf record
 * HtSegment with HT_SEG_TRIANGLE set names three consecutive HtPoint vertices starting at
 * `point` (the points' r field is unused, 0), so the traversal needs no extra buffer.
 *
 * Watertight enough for a renderer of this kind: plain Möller-Trumbore rounds the barycentric of
 * a point on a shared edge to a tiny negative value in both neighbours about half the time
 * (measured: 4 % of rays through a quad's diagonal fell through in double), so the edge tests
 * accept HT_TRI_EDGE_EPS of overlap: a ray through a shared edge hits one of the two triangles
 * (which one does not matter, both give the same t up to rounding).  Both faces are
 * reported (no culling: a floor is hit from above and below, a closed head from inside), and the
 * determinant test is relative to |e1 x e2| |d| so tiny (but valid) triangles are not rejected
 * as parallel.  A ray exactly in the triangle's plane misses.
 *
 * Self-intersection: none is handled here; the shading stage offsets spawned rays along the
 * geometric normal (shade.cl), which is what makes the strict t > tmin test safe.
 */
#ifndef HT_GEOMETRY_TRIANGLE_H
#define HT_GEOMETRY_TRIANGLE_H

#include "../types.h"

/* |det| <= HT_TRI_PARALLEL_EPS * |e1 x e2| |d| counts as parallel (angle below ~1e-7 rad). */
#define HT_TRI_PARALLEL_EPS HT_R(1e-7)
/* Barycentric slack at the edges: ~8 float ulps of 1, a 1e-6 relative sliver of overlap. */
#define HT_TRI_EDGE_EPS HT_R(1e-6)

/* Closest intersection of o + t d, t in (tmin, tmax), with triangle (p0, p1, p2).  Returns t, or
 * tmax for a miss, like ht_capsule_intersect; *b1, *b2 get the barycentrics of p1 and p2 for a
 * hit (untouched otherwise). */
HT_FN real ht_triangle_intersect(real3 o, real3 d, real3 p0, real3 p1, real3 p2, real tmin,
                                 real tmax, real* b1, real* b2) {
    const real3 e1 = p1 - p0;
    const real3 e2 = p2 - p0;
    const real3 pv = cross(d, e2);
    const real det = dot(e1, pv);
    const real3 ng = cross(e1, e2);
    /* |det| = |d . (e1 x e2)|: compare against |ng| |d| without square roots. */
    const real scale2 = dot(ng, ng) * dot(d, d);
    if (det * det <= HT_TRI_PARALLEL_EPS * HT_TRI_PARALLEL_EPS * scale2) return tmax;
    const real inv = HT_R(1) / det;
    const real3 tv = o - p0;
    const real u = dot(tv, pv) * inv;
    if (u < -HT_TRI_EDGE_EPS || u > HT_R(1) + HT_TRI_EDGE_EPS) return tmax;
    const real3 qv = cross(tv, e1);
    const real v = dot(d, qv) * inv;
    if (v < -HT_TRI_EDGE_EPS || u + v > HT_R(1) + HT_TRI_EDGE_EPS) return tmax;
    const real t = dot(e2, qv) * inv;
    if (!(t > tmin && t < tmax)) return tmax;
    *b1 = u;
    *b2 = v;
    return t;
}

/* Unit geometric normal (p1 - p0) x (p2 - p0): counter-clockwise front face, as glTF. */
HT_FN real3 ht_triangle_normal(real3 p0, real3 p1, real3 p2) {
    const real3 n = cross(p1 - p0, p2 - p0);
    const real l2 = dot(n, n);
    return l2 > HT_R(0) ? n * (HT_R(1) / sqrt(l2)) : make_real3(HT_R(0), HT_R(1), HT_R(0));
}

#endif /* HT_GEOMETRY_TRIANGLE_H */
