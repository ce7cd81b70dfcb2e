/* 8-wide BVH traversal over HtBvhNode (children's bounds as SoA, kernels/types.h), shared by the
 * stage kernels (float) and the host tests / microbenchmarks (double).
 *
 * Node 0 is the root; each node holds its (up to) HT_BVH_WIDTH = 8 children's boxes.  Child slot k:
 * count[k] > 0 is a leaf = segments [child[k], child[k] + count[k]) of the leaf segment array;
 * count[k] == 0 is an inner node reference.  A slot with child == 0 and count == 0 is empty (node 0
 * is the root, never a child): that is how a scene of 0 or 1 segments is stored.  A reference
 * with HT_NODE_ORIENTED names a node whose children's boxes are oriented (kernels/types.h): the
 * ray is mapped by each child's affine map and cut with the unit cube (ht_node_oriented_slabs).
 *
 * Why it looks like this (measured on PoCL 3.1 CPU, docs/POCL.md §1, host/bvh/NOTES.md):
 *   - one float16 slab step per axis covers the eight children's lower and upper planes (PoCL
 *     makes it AVX-512 here); a path ray's time is mostly the descent to its origin's leaf, so
 *     fewer, wider levels (host/bvh/NOTES.md "8-wide nodes");
 *   - compare-select min/max, not fmin/fmax (13-24 % slower);
 *   - no always_inline;
 *   - no inf in comparisons: tmax is clamped to HT_T_FAR and reciprocal directions are bounded,
 *     so -cl-fast-relaxed-math (finite-math) is safe;
 *   - private stack of (node, entry distance), nearest inner child visited next and the others
 *     pushed farthest first, culled on pop;
 *   - few data-dependent branches per node step: the node test yields bit masks of its hit leaf
 *     and inner slots, taken by bit loops (as a leaf's hit lanes), and the eight-lane capsule
 *     test computes every lane instead of branching (capsule.h).  The traversal's time goes to
 *     mispredicted branches, not to memory (host/bvh/NOTES.md "Fewer data-dependent branches").
 * Leaves are intersected as soon as their box is hit, before descending, so a close leaf
 * shrinks t_best before the inner children are ordered.
 */
#ifndef HT_GEOMETRY_BVH_TRAVERSE_H
#define HT_GEOMETRY_BVH_TRAVERSE_H

#include "../types.h"
#include "capsule.h"
#include "triangle.h"
#include "fiber_frame.h"
#include "pages.h"

/* Stack entries: an 8-wide node pushes at most 7, and the builder keeps the 8-wide depth at most
 * a third of the binary depth cap; one more holds the root below a start node's subtree
 * (host/bvh/build.cpp asserts 7 * (kMaxBvhDepth / 3 + 1) + 1 fits). */
#define HT_STACK_SIZE 152
#define HT_T_FAR HT_R(1e30)
/* |d| components below this are replaced so 1/d stays finite (|1/d| <= 1e20; box extents
 * ~1e3 keep products far below float max). */
#define HT_DIR_EPS HT_R(1e-20)

HT_FN real ht_safe_inv(real x) {
    return HT_R(1) / ht_select(fabs(x) < HT_DIR_EPS, ht_select(x < HT_R(0), -HT_DIR_EPS, HT_DIR_EPS), x);
}

/* Index of the lowest set bit of a nonzero mask: the bit loops below visit set slots in slot order,
 * one iteration per set slot instead of a data-dependent branch per slot. */
HT_FN uint ht_lowest_bit(uint mask) {
#ifdef HT_OPENCL
    return 31u - clz(mask & (0u - mask));
#else
    return (uint)__builtin_ctz(mask);
#endif
}

#if defined(HT_OPENCL) && HT_BVH_WIDTH != 8
#error "the OpenCL node test is written for 8 children (float16 planes, ht_mask8)"
#endif

#ifdef HT_OPENCL
/* Bit k set where lane k of the comparison result m is true. */
HT_FN uint ht_mask8(int8 m) {
    const int8 bits = m & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
    const int4 bits4 = bits.lo | bits.hi;
    const int2 bits2 = bits4.lo | bits4.hi;
    return (uint)(bits2.x | bits2.y);
}
#endif

HT_FN real ht_hit_radius(HtPoint a, HtPoint b) { return HT_R(0.5) * ((real)a.r + (real)b.r); }

/* Whether the root t of segment s (points a, b) lies inside one of its direct neighbours in the
 * strand, i.e. on an interior surface (capsule.h, ht_inside_neighbour).  The neighbours' points
 * are read only here, for roots that would otherwise be taken. */
HT_FN int ht_strand_interior(HT_POINTS_PARAM, HtSegment s, HtPoint a, HtPoint b, real3 o, real3 d, real t) {
    const real3 pa = ht_point_pos(a), pb = ht_point_pos(b);
    const real3 p = o + d * t;
    const real pmax = ht_max(ht_max(fabs(p.x), fabs(p.y)), fabs(p.z));
    const real tol = ht_max(HT_SURFACE_TOL_REL * ht_hit_radius(a, b), HT_SURFACE_TOL_ULPS * HT_REAL_EPS * pmax);
    if (!(ht_seg_flags(s) & HT_SEG_LAST)) {
        const HtPoint c = HT_POINT(s.point + 2u);
        if (ht_inside_neighbour((o - pb) + d * t, ht_point_pos(c) - pb, ht_hit_radius(b, c), tol, 0)) return 1;
    }
    if (!(ht_seg_flags(s) & HT_SEG_FIRST)) {
        const HtPoint z = HT_POINT(s.point - 1u);
        if (ht_inside_neighbour((o - pa) + d * t, ht_point_pos(z) - pa, ht_hit_radius(z, a), tol, 1)) return 1;
    }
    return 0;
}

/* The closest root in (tmin, tmax) of hair segment s that lies on its strand's surface (returns
 * tmax for none): a root on an interior surface is dropped for the capsule's next one (at most
 * six roots). */
HT_FN real ht_strand_segment_intersect(HT_POINTS_PARAM, HtSegment s, real3 o, real3 d, real tmin, real tmax) {
    const HtPoint a = HT_POINT(s.point);
    const HtPoint b = HT_POINT(s.point + 1u);
    const real3 pa = ht_point_pos(a), pb = ht_point_pos(b);
    const real r = ht_hit_radius(a, b);
    const uint first = ht_seg_flags(s) & HT_SEG_FIRST;
    /* one call site: the kernels inline it, and a second copy of the capsule test cost time */
    real t = tmin;
    do t = ht_capsule_intersect(o, d, pa, pb, r, first, t, tmax);
    while (t < tmax && ht_strand_interior(HT_POINTS_ARG, s, a, b, o, d, t));
    return t;
}

/* The order of closest-hit candidates (host/bvh/NOTES.md "Semantics"): the nearer first and, at a
 * bit-equal t, the higher global id (Embree's primID, which grows with HtSegment.point: the ids
 * are compared as their first points, kernels/types.h).  A total order, so the
 * answer is the same whichever order the tree presents the candidates in: two segments meet at a
 * bit-equal t on the circle where a strand's joint sphere meets the next segment's cylinder, or
 * where fibres coincide, and with "first found wins" the 8-wide layout moved 27 pixels of a render
 * (issue #15).  The higher id is the segment that begins at the joint, the one Embree's round
 * linear curves (a segment's cone and end sphere minus its neighbours' cones) report there in most
 * cases: on the strand anchor's camera rays primIDs agree with Embree at 99.975 % with it, 99.933 %
 * with the lower id, 99.960 % with the first found (NOTES.md).  Whether leaf entry k at t precedes
 * the best so far (best = HT_NO_HIT: nothing at tbest = the ray's tmax, which stays excluded); the
 * ids are read only at a tie. */
HT_FN int ht_hit_precedes(HT_SEGS_PARAM, real t, uint k, real tbest, uint best) {
    return t < tbest || (t == tbest && best != HT_NO_HIT && HT_SEG(k).point > HT_SEG(best).point);
}

/* The exclusive far end for the intersection tests that still lets a root at exactly tbest through
 * (it may win its tie): the next value above tbest.  Roots lie above tmin >= 0, so tbest <= 0 has
 * none to admit. */
HT_FN real ht_tie_bound(real tbest) {
#ifdef HT_OPENCL
    return tbest > 0.0f ? as_float(as_uint(tbest) + 1u) : tbest;
#else
    return tbest > HT_R(0) ? std::nextafter(tbest, HT_R(HT_REAL_MAX)) : tbest;
#endif
}

/* Leaf entry k (a capsule or, with meshes, a triangle) against the ray: updates *tbest / *best and
 * returns 1 if it precedes the closest hit so far. */
HT_FN int ht_leaf_entry(HT_SEGS_PARAM, HT_POINTS_PARAM, uint k, real3 o, real3 d, real tmin, real* tbest, uint* best) {
    const HtSegment s = HT_SEG(k);
    const real bound = ht_tie_bound(*tbest);
    real t;
#if HT_FEATURE_MESHES
    if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
        real b1, b2;
        t = ht_triangle_intersect(o, d, ht_point_pos(HT_POINT(s.point)), ht_point_pos(HT_POINT(s.point + 1u)),
                                  ht_point_pos(HT_POINT(s.point + 2u)), tmin, bound, &b1, &b2);
    } else
#endif
    t = ht_strand_segment_intersect(HT_POINTS_ARG, s, o, d, tmin, bound);
    if (!(t < bound && ht_hit_precedes(HT_SEGS_ARG, t, k, *tbest, *best))) return 0;
    *tbest = t;
    *best = k;
    return 1;
}

/* n (1 <= n <= 8) entries of the leaf segment array against the ray: g .. g + n - 1, or with a list
 * the entries list[g .. g + n - 1]; updates *tbest / *best and returns 1 if one of them precedes
 * the closest hit so far.  The tree's leaves pass no list (a null pointer, known when the call is
 * inlined: an index array in its place made the tree's traversal 5-7 % slower).
 *
 * OpenCL takes the eight at once, one capsule per float8 lane (ht_capsule_lane8, capsule.h), so a
 * leaf of up to max_leaf = 8 is one branch-free test: the group's loads are issued together and
 * its arithmetic is shared, which is what lets the builder fill leaves (host/bvh/bvh.h
 * BvhOptions::leaf_lanes; host/bvh/NOTES.md "Leaves tested four at a time" and "Leaves tested
 * eight at a time").  A lane's answer is the scalar test's (same operations), and every lane's
 * hit up to the group's starting *tbest is offered to ht_hit_precedes, so a group finds what the
 * scalar loop finds: the first candidate in the order of (t, global id).  A group holding a
 * triangle, and the host build, take the scalar loop.  The tree's leaves, a pixel's candidate
 * list (candidate_list.h) and the path grid's gathered ids (path_grid.h) all come here, so each
 * finds the same t for the same capsule.  `ids` (private, up to eight) replaces list and g when
 * given: the grid gathers the entries of several cells into one group. */
HT_FN int ht_intersect_group(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* list, const uint* ids, uint g,
                             uint n, real3 o, real3 d, real tmin, real* tbest, uint* best) {
    int found = 0;
/* entry j, and j's lane (lanes past n repeat the first entry and are not read back) */
#define HT_ENTRY(j) (ids ? ids[j] : list ? list[g + (j)] : g + (j))
#define HT_LANE(j) HT_SEG(HT_ENTRY(n > (j) ? (j) : 0u))
#ifdef HT_OPENCL
    const HtSegment s0 = HT_LANE(0u), s1 = HT_LANE(1u), s2 = HT_LANE(2u), s3 = HT_LANE(3u);
    const HtSegment s4 = HT_LANE(4u), s5 = HT_LANE(5u), s6 = HT_LANE(6u), s7 = HT_LANE(7u);
#if HT_FEATURE_MESHES
    if (!((s0.strand_flags | s1.strand_flags | s2.strand_flags | s3.strand_flags | s4.strand_flags | s5.strand_flags |
           s6.strand_flags | s7.strand_flags) & HT_SEG_TRIANGLE))
#endif
    {
        /* Each point as one float4 load (x, y, z, r), transposed into the lanes by shuffles:
         * assembling the float8s from 16 scalar HtPoint fields per coordinate instead (one insert
         * each) made the eight-lane leaf test 0.86x of the four-lane one (host/bvh/NOTES.md
         * "Leaves tested eight at a time"). */
#define HT_POINT4(i) vload4(0, (HT_CONST_GLOBAL float*)&HT_POINT(i))
        const float4 a0 = HT_POINT4(s0.point), b0 = HT_POINT4(s0.point + 1u);
        const float4 a1 = HT_POINT4(s1.point), b1 = HT_POINT4(s1.point + 1u);
        const float4 a2 = HT_POINT4(s2.point), b2 = HT_POINT4(s2.point + 1u);
        const float4 a3 = HT_POINT4(s3.point), b3 = HT_POINT4(s3.point + 1u);
        const float4 a4 = HT_POINT4(s4.point), b4 = HT_POINT4(s4.point + 1u);
        const float4 a5 = HT_POINT4(s5.point), b5 = HT_POINT4(s5.point + 1u);
        const float4 a6 = HT_POINT4(s6.point), b6 = HT_POINT4(s6.point + 1u);
        const float4 a7 = HT_POINT4(s7.point), b7 = HT_POINT4(s7.point + 1u);
#undef HT_POINT4
/* component F of the eight float4s P0..P7 */
#define HT_LANES8(P, F) (float8)(P##0 .F, P##1 .F, P##2 .F, P##3 .F, P##4 .F, P##5 .F, P##6 .F, P##7 .F)
        /* the flags are the words' low bits */
        const uint8 flags = (uint8)(s0.strand_flags, s1.strand_flags, s2.strand_flags, s3.strand_flags, s4.strand_flags,
                                    s5.strand_flags, s6.strand_flags, s7.strand_flags);
        const float bound = ht_tie_bound(*tbest);
        const float8 t = ht_capsule_lane8(o, d, HT_LANES8(a, x), HT_LANES8(a, y), HT_LANES8(a, z), HT_LANES8(b, x),
                                          HT_LANES8(b, y), HT_LANES8(b, z), 0.5f * (HT_LANES8(a, w) + HT_LANES8(b, w)),
                                          (flags & (uint8)(HT_SEG_FIRST)) != (uint8)(0u), tmin, bound);
#undef HT_LANES8
        float tl[8];
        vstore8(t, 0, tl);
        /* Lanes with a root up to *tbest as a mask, visited in lane order; an earlier lane's hit
         * may shorten *tbest, hence the test inside the loop too. */
        uint lanes = ht_mask8(t < (float8)(bound)) & ((1u << n) - 1u); /* padding lanes dropped */
        for (; lanes != 0u; lanes &= lanes - 1u) {
            const uint j = ht_lowest_bit(lanes);
            const uint k = HT_ENTRY(j);
            if (!ht_hit_precedes(HT_SEGS_ARG, tl[j], k, *tbest, *best)) continue;
            const HtSegment sj = HT_SEG(k);
            /* A root on an interior surface of its strand: that capsule's later roots, one at a
             * time, as the scalar loop takes them. */
            if (ht_strand_interior(HT_POINTS_ARG, sj, HT_POINT(sj.point), HT_POINT(sj.point + 1u), o, d, tl[j])) {
                found |= ht_leaf_entry(HT_SEGS_ARG, HT_POINTS_ARG, k, o, d, tl[j], tbest, best);
                continue;
            }
            *tbest = tl[j];
            *best = k;
            found = 1;
        }
        return found;
    }
#endif
    for (uint j = 0; j < n; ++j) found |= ht_leaf_entry(HT_SEGS_ARG, HT_POINTS_ARG, HT_ENTRY(j), o, d, tmin, tbest, best);
#undef HT_LANE
#undef HT_ENTRY
    return found;
}

/* Entries g .. g + n - 1 of the leaf array, or of `list` when given (1 <= n <= 8). */
HT_FN int ht_intersect_entries(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* list, uint g, uint n, real3 o,
                               real3 d, real tmin, real* tbest, uint* best) {
    return ht_intersect_group(HT_SEGS_ARG, HT_POINTS_ARG, list, 0, g, n, o, d, tmin, tbest, best);
}

/* The leaf records ids[0 .. n - 1] (1 <= n <= 8). */
HT_FN int ht_intersect_ids(HT_SEGS_PARAM, HT_POINTS_PARAM, const uint* ids, uint n, real3 o, real3 d, real tmin,
                           real* tbest, uint* best) {
    return ht_intersect_group(HT_SEGS_ARG, HT_POINTS_ARG, 0, ids, 0u, n, o, d, tmin, tbest, best);
}

/* Intersects the leaf [first, first + count) against the ray, eight at a time; updates *tbest /
 * *best.  Returns 1 if something was hit (any-hit callers stop then).  Called, not inlined into
 * the traversal loop: path rays' closest hits took 0.86-0.97x the time and shadow rays 0.92-0.99x
 * (host/bvh/NOTES.md "The leaf test called, not inlined"). */
HT_FN HT_NOINLINE int ht_intersect_leaf(HT_SEGS_PARAM, HT_POINTS_PARAM, uint first, uint count, real3 o, real3 d, real tmin, real* tbest,
                            uint* best) {
    int found = 0;
    const uint end = first + count;
    for (uint g = first; g < end; g += 8u) {
        const uint n = end - g < 8u ? end - g : 8u;
        found |= ht_intersect_entries(HT_SEGS_ARG, HT_POINTS_ARG, 0, g, n, o, d, tmin, tbest, best);
    }
    return found;
}

/* The ray's constants for the slab test: 1/d and o/d per axis. */
typedef struct {
    real ix, iy, iz, ox, oy, oz;
} HtSlabRay;

HT_FN HtSlabRay ht_slab_ray(real3 o, real3 d) {
    HtSlabRay r;
    r.ix = ht_safe_inv(d.x);
    r.iy = ht_safe_inv(d.y);
    r.iz = ht_safe_inv(d.z);
    r.ox = o.x * r.ix;
    r.oy = o.y * r.iy;
    r.oz = o.z * r.iz;
    return r;
}

#ifdef HT_OPENCL
/* Eight children's slab distances per axis (the two planes in either order) -> entry distances
 * (stored to near[0..7]) and the mask of the hit boxes, with compare-selects (fmin/fmax were
 * 13-24 % slower, see the top of this file). */
HT_FN uint ht_slabs8(float8 ax, float8 bx, float8 ay, float8 by, float8 az, float8 bz, float tmin, float tfar,
                     float* near) {
    const float8 nx = ax < bx ? ax : bx, fx = ax < bx ? bx : ax;
    const float8 ny = ay < by ? ay : by, fy = ay < by ? by : ay;
    const float8 nz = az < bz ? az : bz, fz = az < bz ? bz : az;
    const float8 t0 = (float8)(tmin), t1 = (float8)(tfar);
    const float8 nxy = nx < ny ? ny : nx, nzt = nz < t0 ? t0 : nz;
    const float8 fxy = fx < fy ? fx : fy, fzt = fz < t1 ? fz : t1;
    const float8 tn = nxy < nzt ? nzt : nxy;
    const float8 tf = fxy < fzt ? fxy : fzt;
    vstore8(tn, 0, near);
    return ht_mask8(tn <= tf);
}
#endif

/* Node n's children against the ray segment [tmin, tfar]: entry distances near[k] and the mask of
 * the children whose box overlaps the segment (empty slots included: ht_node_test drops them). */
HT_FN uint ht_node_slabs(HT_CONST_GLOBAL HtBvhNode* n, const HtSlabRay* r, real tmin, real tfar, real* near) {
#ifdef HT_OPENCL
    /* The only OpenCL-specific code: three float16 steps, lanes 0-7 lower planes, 8-15 upper. */
    const float16 tx = vload16(0, n->x) * r->ix - r->ox;
    const float16 ty = vload16(0, n->y) * r->iy - r->oy;
    const float16 tz = vload16(0, n->z) * r->iz - r->oz;
    return ht_slabs8(tx.lo, tx.hi, ty.lo, ty.hi, tz.lo, tz.hi, tmin, tfar, near);
#else
    uint mask = 0u;
    for (int k = 0; k < HT_BVH_WIDTH; ++k) {
        const int u = k + HT_BVH_WIDTH;
        const real ax = (real)n->x[k] * r->ix - r->ox, bx = (real)n->x[u] * r->ix - r->ox;
        const real ay = (real)n->y[k] * r->iy - r->oy, by = (real)n->y[u] * r->iy - r->oy;
        const real az = (real)n->z[k] * r->iz - r->oz, bz = (real)n->z[u] * r->iz - r->oz;
        const real tn = ht_max(ht_max(ht_min(ax, bx), ht_min(ay, by)), ht_max(ht_min(az, bz), tmin));
        const real tf = ht_min(ht_min(ht_max(ax, bx), ht_max(ay, by)), ht_min(ht_max(az, bz), tfar));
        near[k] = tn;
        mask |= tn <= tf ? 1u << k : 0u;
    }
    return mask;
#endif
}

/* Coefficient c (row c / 4, column c % 4: x, y, z, offset) of child k's map in an oriented node
 * n with its second record f: rows 0-1 in n's x, y, z, rows 1-2 in f's, the children side by side. */
HT_FN real ht_oriented_coef(HT_CONST_GLOBAL HtBvhNode* n, HT_CONST_GLOBAL HtBvhNode* f, int c, int k) {
    HT_CONST_GLOBAL float* a = c < 2 ? n->x : c < 4 ? n->y : c < 6 ? n->z : c < 8 ? f->x : c < 10 ? f->y : f->z;
    return (real)a[HT_BVH_WIDTH * (c & 1) + k];
}

/* The same for an oriented node (kernels/types.h): child k's affine map takes its box to the
 * unit cube, p' = A_k p + b_k, so the slab planes are 0 and 1 of the mapped ray; the map is
 * affine, so the distances are the world ray's t.  n holds rows 0 and the first half of 1, f the
 * rest, each coefficient as the children side by side. */
HT_FN uint ht_node_oriented_slabs(HT_CONST_GLOBAL HtBvhNode* n, HT_CONST_GLOBAL HtBvhNode* f, real3 o, real3 d,
                                  real tmin, real tfar, real* near) {
#ifdef HT_OPENCL
    const float16 a0 = vload16(0, n->x), b0 = vload16(0, n->y);
    const float16 a1 = vload16(0, n->z), b1 = vload16(0, f->x);
    const float16 a2 = vload16(0, f->y), b2 = vload16(0, f->z);
    const float8 dx = a0.lo * d.x + a0.hi * d.y + b0.lo * d.z;
    const float8 dy = a1.lo * d.x + a1.hi * d.y + b1.lo * d.z;
    const float8 dz = a2.lo * d.x + a2.hi * d.y + b2.lo * d.z;
    const float8 ox = a0.lo * o.x + a0.hi * o.y + b0.lo * o.z + b0.hi;
    const float8 oy = a1.lo * o.x + a1.hi * o.y + b1.lo * o.z + b1.hi;
    const float8 oz = a2.lo * o.x + a2.hi * o.y + b2.lo * o.z + b2.hi;
    const float8 eps = (float8)(HT_DIR_EPS);
    const float8 ix = 1.0f / (fabs(dx) < eps ? (dx < 0.0f ? -eps : eps) : dx);
    const float8 iy = 1.0f / (fabs(dy) < eps ? (dy < 0.0f ? -eps : eps) : dy);
    const float8 iz = 1.0f / (fabs(dz) < eps ? (dz < 0.0f ? -eps : eps) : dz);
    const float8 lx = -ox * ix, ly = -oy * iy, lz = -oz * iz;
    return ht_slabs8(lx, lx + ix, ly, ly + iy, lz, lz + iz, tmin, tfar, near);
#else
    uint mask = 0u;
    for (int k = 0; k < HT_BVH_WIDTH; ++k) {
        real tn = tmin, tf = tfar;
        for (int j = 0; j < 3; ++j) {
            real a[4];
            for (int c = 0; c < 4; ++c) a[c] = ht_oriented_coef(n, f, 4 * j + c, k);
            const real inv = ht_safe_inv(a[0] * d.x + a[1] * d.y + a[2] * d.z);
            const real lo = -(a[0] * o.x + a[1] * o.y + a[2] * o.z + a[3]) * inv, hi = lo + inv;
            tn = ht_max(tn, ht_min(lo, hi));
            tf = ht_min(tf, ht_max(lo, hi));
        }
        near[k] = tn;
        mask |= tn <= tf ? 1u << k : 0u;
    }
    return mask;
#endif
}

/* Node n = the node of reference `ref` (index | HT_NODE_ORIENTED) against the ray: near[k] as
 * above; returns the mask of its hit inner children and sets *leaves to that of its hit leaves
 * (empty slots never hit). */
HT_FN uint ht_node_test(HT_NODES_PARAM, uint ref, HT_CONST_GLOBAL HtBvhNode* n, real3 o, real3 d,
                        const HtSlabRay* r, real tmin, real tfar, real* near, uint* leaves) {
    const uint hit = ref & HT_NODE_ORIENTED
                         ? ht_node_oriented_slabs(n, HT_NODE_PTR((ref & ~HT_NODE_ORIENTED) + 1u), o, d, tmin, tfar, near)
                         : ht_node_slabs(n, r, tmin, tfar, near);
#ifdef HT_OPENCL
    const uint8 child = vload8(0, n->child), count = vload8(0, n->count);
    const uint leaf = ht_mask8(count != (uint8)(0u));
    const uint used = leaf | ht_mask8(child != (uint8)(0u));
#else
    uint leaf = 0u, used = 0u;
    for (int k = 0; k < HT_BVH_WIDTH; ++k) {
        leaf |= n->count[k] != 0u ? 1u << k : 0u;
        used |= (n->child[k] | n->count[k]) != 0u ? 1u << k : 0u;
    }
#endif
    *leaves = hit & leaf;
    return hit & used & ~leaf;
}

/* The node record of reference ref. */
HT_FN HT_CONST_GLOBAL HtBvhNode* ht_node_of(HT_NODES_PARAM, uint ref) { return HT_NODE_PTR(ref & ~HT_NODE_ORIENTED); }

/* A ray's origin, direction and the far end of its search: tmax, but x < C ? x : C keeps a +inf
 * tmax out of every later comparison. */
HT_FN real ht_ray_start(HtRay ray, real3* o, real3* d) {
    *o = make_real3(ray.ox, ray.oy, ray.oz);
    *d = make_real3(ray.dx, ray.dy, ray.dz);
    return (real)ray.tmax < HT_T_FAR ? (real)ray.tmax : HT_T_FAR;
}

/* Core traversal.  any_hit: stop at the first intersection in (tmin, tmax).  Returns the leaf
 * segment index of the hit (HT_NO_HIT for none) and its distance in *t_out; for closest hits, the
 * first in the order of ht_hit_precedes, whatever the tree's layout, so also whatever node the
 * traversal starts from.
 *
 * start: a node reference (as a child slot holds it) to traverse first, 0 for none.  A path's next
 * ray leaves the fibre its last ray hit, and the hair around that point is under the node whose
 * leaf held that hit (*node_out, 0 for a miss).  Traversed first, its leaves nearest first, it
 * gives the closest hit in about half the path rays of a dense lock before the descent from the
 * root, which then culls what lies beyond it and skips that subtree (host/bvh/NOTES.md "Traversal
 * started at the last hit's node").  Any node of the tree is a valid start: its subtree is
 * traversed once either way, and the answer does not depend on the order. */
HT_FN uint ht_traverse_from(HT_GEOMETRY_PARAMS, HtRay ray, int any_hit, uint start, real* t_out, uint* node_out) {
    real3 o, d;
    real tbest = ht_ray_start(ray, &o, &d);
    const real tmin = ray.tmin;
    uint best = HT_NO_HIT;

    const HtSlabRay slab = ht_slab_ray(o, d);

    uint stack_node[HT_STACK_SIZE];
    real stack_t[HT_STACK_SIZE];
    int sp = 0;
    uint cur = start;
    uint best_node = 0u;
    if (start != 0u) { /* the root after the start node's subtree; never culled (entered at tmin) */
        stack_node[0] = 0u;
        stack_t[0] = tmin;
        sp = 1;
    }

    for (;;) {
        real near[HT_BVH_WIDTH];
        uint leaves, tested = 0u; /* the leaf slot tested last */
        HT_CONST_GLOBAL HtBvhNode* n = ht_node_of(HT_NODES_ARG, cur);
        uint inner = ht_node_test(HT_NODES_ARG, cur, n, o, d, &slab, tmin, tbest, near, &leaves);

        /* Leaves now: they may shorten the ray before the inner children are ordered.  A bit loop
         * over the hit leaf slots in slot order: a branch per hit leaf, not two per slot.  The start
         * node's leaves are entered with no closest hit yet, so there the nearest goes first and
         * the loop ends at the first entered beyond the closest hit (elsewhere that culls under
         * 1.5 % of the leaf tests and does not pay, host/bvh/NOTES.md). */
        int stop = 0;
        for (; leaves != 0u; leaves &= ~(1u << tested)) {
            uint k = ht_lowest_bit(leaves);
            if (cur == start) { /* the start node: nearest leaf first, none beyond the closest hit */
                for (uint rest = leaves & (leaves - 1u); rest != 0u; rest &= rest - 1u) {
                    const uint j = ht_lowest_bit(rest);
                    k = near[j] < near[k] ? j : k;
                }
                if (near[k] > tbest) break;
            }
            tested = k;
            if (ht_intersect_leaf(HT_SEGS_ARG, HT_POINTS_ARG, n->child[k], n->count[k], o, d, tmin, &tbest, &best)) {
                best_node = cur;
                if (any_hit) {
                    stop = 1;
                    break;
                }
            }
        }
        if (stop) break;

        /* Hit inner children entered up to the closest hit, sorted by entry distance (insertion).
         * "<=" here, on pop and in the slab test's far end: a child entered at exactly tbest may
         * hold a tie that a higher id wins (ht_hit_precedes). */
        uint sc[HT_BVH_WIDTH];
        real st[HT_BVH_WIDTH];
        int m = 0;
        for (; inner != 0u; inner &= inner - 1u) {
            const uint k = ht_lowest_bit(inner);
            /* the start node's subtree was traversed first (a start of 0, the root, is no child) */
            if (!(near[k] <= tbest) | (n->child[k] == start)) continue;
            int j = m++;
            for (; j > 0 && st[j - 1] > near[k]; --j) {
                st[j] = st[j - 1];
                sc[j] = sc[j - 1];
            }
            st[j] = near[k];
            sc[j] = n->child[k];
        }
        if (m > 0) {
            cur = sc[0];
            for (int j = m - 1; j > 0; --j) {
                stack_node[sp] = sc[j];
                stack_t[sp] = st[j];
                ++sp;
            }
            continue;
        }
        /* Pop, skipping entries that start beyond the current closest hit. */
        int popped = 0;
        while (sp > 0) {
            --sp;
            if (stack_t[sp] <= tbest) {
                cur = stack_node[sp];
                popped = 1;
                break;
            }
        }
        if (!popped) break;
    }
    *t_out = tbest;
    *node_out = best_node;
    return best;
}

/* The same from the root. */
HT_FN uint ht_traverse(HT_GEOMETRY_PARAMS, HtRay ray, int any_hit, real* t_out) {
    uint node;
    return ht_traverse_from(HT_GEOMETRY_ARGS, ray, any_hit, 0u, t_out, &node);
}

/* The closest hit `best` at t (HT_NO_HIT: none) with the fibre quantities the shading stages need
 * (see HtHit). */
HT_FN void ht_closest_hit_record(HT_SEGS_PARAM, HT_POINTS_PARAM, HtRay ray, uint best, real t, HtHit* hit) {
    hit->segment = best;
    if (best == HT_NO_HIT) {
        hit->t = (float)HT_REAL_MAX;
        hit->u = 0.0f;
        hit->h = 0.0f;
        hit->tx = 0.0f;
        hit->ty = 0.0f;
        hit->tz = 0.0f;
        hit->radius = 0.0f;
        return;
    }
    const HtSegment s = HT_SEG(best);
    const real3 o = make_real3(ray.ox, ray.oy, ray.oz);
    const real3 d = make_real3(ray.dx, ray.dy, ray.dz);
#if HT_FEATURE_MESHES
    if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
        const real3 p0 = ht_point_pos(HT_POINT(s.point));
        const real3 p1 = ht_point_pos(HT_POINT(s.point + 1u));
        const real3 p2 = ht_point_pos(HT_POINT(s.point + 2u));
        /* The same arithmetic as in the traversal, so the same t and barycentrics come out. */
        real b1 = HT_R(0), b2 = HT_R(0);
        (void)ht_triangle_intersect(o, d, p0, p1, p2, ray.tmin, HT_T_FAR, &b1, &b2);
        const real3 n = ht_triangle_normal(p0, p1, p2);
        hit->t = (float)t;
        hit->u = (float)b1;
        hit->h = (float)b2;
        hit->tx = (float)n.x;
        hit->ty = (float)n.y;
        hit->tz = (float)n.z;
        hit->radius = 0.0f;
        return;
    }
#endif
    const HtPoint a = HT_POINT(s.point);
    const HtPoint b = HT_POINT(s.point + 1u);
    real3 tangent;
    real u;
    const real3 off = ht_capsule_hit_offset(o, d, ht_point_pos(a), ht_point_pos(b), t, &tangent, &u);
    const real r = ht_hit_radius(a, b);
    real3 fx, fy, fz;
    ht_fiber_frame(tangent, -d, &fx, &fy, &fz);
    hit->t = (float)t;
    hit->u = (float)u;
    hit->h = (float)ht_fiber_h(off, fy, r);
    hit->tx = (float)tangent.x;
    hit->ty = (float)tangent.y;
    hit->tz = (float)tangent.z;
    hit->radius = (float)r;
}

/* The closest hit, the traversal started at node `start` (ht_traverse_from); *node = the node
 * whose leaf held it (0 for a miss), where the next rays from the hit start theirs. */
HT_FN void ht_trace_closest_from(HT_GEOMETRY_PARAMS, HtRay ray, uint start, HtHit* hit, uint* node) {
    real t;
    const uint best = ht_traverse_from(HT_GEOMETRY_ARGS, ray, 0, start, &t, node);
    ht_closest_hit_record(HT_SEGS_ARG, HT_POINTS_ARG, ray, best, t, hit);
}

HT_FN void ht_trace_closest(HT_GEOMETRY_PARAMS, HtRay ray, HtHit* hit) {
    uint node;
    ht_trace_closest_from(HT_GEOMETRY_ARGS, ray, 0u, hit, &node);
}

/* Shadow rays: 1 if anything lies in (tmin, tmax).  From the root: started at the node of the
 * hit they leave, they took 5 % longer (host/bvh/NOTES.md "Traversal started at the last hit's node"). */
HT_FN uint ht_trace_any(HT_GEOMETRY_PARAMS, HtRay ray) {
    real t;
    return ht_traverse(HT_GEOMETRY_ARGS, ray, 1, &t) != HT_NO_HIT ? 1u : 0u;
}

#endif /* HT_GEOMETRY_BVH_TRAVERSE_H */
