/* Binary BVH traversal over HtBvhNode ("SoA in node" layout, docs/POCL.md §1), shared by the
 * stage kernels (float) and the host tests / microbenchmarks (double).
 *
 * Node 0 is the root; each node holds both children's boxes.  Child slot i: count_i > 0 is a
 * leaf = segments [child_i, child_i + count_i) of the leaf segment array; count_i == 0 is an inner
 * node index.  A slot with child == 0 and count == 0 is empty (node 0 is the root, never a child):
 * that is how a scene of 0 or 1 segments is stored.
 *
 * Why it looks like this (measured on PoCL 3.1 CPU, docs/POCL.md §1):
 *   - one 8-wide slab test for both children (float8 in OpenCL; lanes 6,7 carry the child/count
 *     bits and are ignored);
 *   - compare-select min/max, not fmin/fmax (13-24 % slower);
 *   - no always_inline;
 *   - no inf in comparisons: tmax is clamped to HT_T_FAR and reciprocal directions are bounded,
 *     so -cl-fast-relaxed-math (finite-math) is safe;
 *   - private stack of (node, entry distance), near child first, culled on pop.
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

/* Stack entries; the builder caps the tree depth below this (host/bvh/bvh.h kMaxDepth). */
#define HT_STACK_SIZE 64
#define HT_T_FAR HT_R(1e30)
/* |d| components below this are replaced so 1/d stays finite (|1/d| <= 1e20; box extents
 * ~1e3 keep products far below float max). */
#define HT_DIR_EPS HT_R(1e-20)

HT_FN real ht_safe_inv(real x) {
    return HT_R(1) / ht_select(fabs(x) < HT_DIR_EPS, ht_select(x < HT_R(0), -HT_DIR_EPS, HT_DIR_EPS), x);
}

HT_FN real ht_hit_radius(HtPoint a, HtPoint b) { return HT_R(0.5) * ((real)a.r + (real)b.r); }

/* Intersects the leaf [first, first + count) against the ray; updates *tbest / *best.
 * Returns 1 if something was hit (any-hit callers stop then). */
HT_FN int ht_intersect_leaf(HT_SEGS_PARAM, HT_POINTS_PARAM, uint first, uint count, real3 o, real3 d, real tmin, real* tbest,
                            uint* best) {
    int found = 0;
    for (uint k = first; k < first + count; ++k) {
        const HtSegment s = HT_SEG(k);
#if HT_FEATURE_MESHES
        if (s.flags & HT_SEG_TRIANGLE) {
            real b1, b2;
            const real t = ht_triangle_intersect(o, d, ht_point_pos(HT_POINT(s.point)),
                                                 ht_point_pos(HT_POINT(s.point + 1u)),
                                                 ht_point_pos(HT_POINT(s.point + 2u)), tmin, *tbest,
                                                 &b1, &b2);
            if (t < *tbest) {
                *tbest = t;
                *best = k;
                found = 1;
            }
            continue;
        }
#endif
        const HtPoint a = HT_POINT(s.point);
        const HtPoint b = HT_POINT(s.point + 1u);
        const real t = ht_capsule_intersect(o, d, ht_point_pos(a), ht_point_pos(b),
                                            ht_hit_radius(a, b), s.flags & HT_SEG_FIRST, tmin,
                                            *tbest);
        if (t < *tbest) {
            *tbest = t;
            *best = k;
            found = 1;
        }
    }
    return found;
}

/* The ray's constants for the slab test of a node's two child boxes (HtBvhNode stores them
 * interleaved: lo/hi = x0 x1 y0 y1 z0 z1 + child fields), 1/d and o/d per axis, twice. */
typedef struct {
#ifdef HT_OPENCL
    /* The only OpenCL-specific code: the 8-wide slab test PoCL compiles to one vector op. */
    float8 inv, oi;
#else
    real inv[6], oi[6];
#endif
} HtSlabRay;

HT_FN HtSlabRay ht_slab_ray(real3 o, real3 d) {
    const real ix = ht_safe_inv(d.x), iy = ht_safe_inv(d.y), iz = ht_safe_inv(d.z);
    HtSlabRay r;
#ifdef HT_OPENCL
    r.inv = (float8)(ix, ix, iy, iy, iz, iz, 0.0f, 0.0f);
    r.oi = (float8)(o.x * ix, o.x * ix, o.y * iy, o.y * iy, o.z * iz, o.z * iz, 0.0f, 0.0f);
#else
    const real inv[6] = {ix, ix, iy, iy, iz, iz};
    const real oi[6] = {o.x * ix, o.x * ix, o.y * iy, o.y * iy, o.z * iz, o.z * iz};
    for (int k = 0; k < 6; ++k) r.inv[k] = inv[k], r.oi[k] = oi[k];
#endif
    return r;
}

/* Node n's two children against the ray segment [tmin, tfar]: entry distances near0/1, whether
 * each child is hit (h0/1: boxes overlap the segment and the child exists) and the children's
 * fields (c = first index, n = leaf count, 0 for an inner node). */
HT_FN void ht_node_slabs(HT_CONST_GLOBAL HtBvhNode* n, const HtSlabRay* r, real tmin, real tfar, real* near0,
                         real* near1, int* h0, int* h1, uint* c0, uint* c1, uint* n0, uint* n1) {
#ifdef HT_OPENCL
    const float8 lo = vload8(0, n->lo);
    const float8 hi = vload8(0, n->hi);
    const float8 ta = lo * r->inv - r->oi;
    const float8 tb = hi * r->inv - r->oi;
    const float8 tn = ta < tb ? ta : tb;
    const float8 tf = ta < tb ? tb : ta;
    *near0 = ht_max(ht_max(tn.s0, tn.s2), ht_max(tn.s4, tmin));
    *near1 = ht_max(ht_max(tn.s1, tn.s3), ht_max(tn.s5, tmin));
    const real far0 = ht_min(ht_min(tf.s0, tf.s2), ht_min(tf.s4, tfar));
    const real far1 = ht_min(ht_min(tf.s1, tf.s3), ht_min(tf.s5, tfar));
    *c0 = as_uint(lo.s6), *c1 = as_uint(lo.s7);
    *n0 = as_uint(hi.s6), *n1 = as_uint(hi.s7);
#else
    real tn[6], tf[6];
    for (int k = 0; k < 6; ++k) {
        const real ta = (real)n->lo[k] * r->inv[k] - r->oi[k];
        const real tb = (real)n->hi[k] * r->inv[k] - r->oi[k];
        tn[k] = ta < tb ? ta : tb;
        tf[k] = ta < tb ? tb : ta;
    }
    *near0 = ht_max(ht_max(tn[0], tn[2]), ht_max(tn[4], tmin));
    *near1 = ht_max(ht_max(tn[1], tn[3]), ht_max(tn[5], tmin));
    const real far0 = ht_min(ht_min(tf[0], tf[2]), ht_min(tf[4], tfar));
    const real far1 = ht_min(ht_min(tf[1], tf[3]), ht_min(tf[5], tfar));
    *c0 = ht_as_uint(n->lo[6]), *c1 = ht_as_uint(n->lo[7]);
    *n0 = ht_as_uint(n->hi[6]), *n1 = ht_as_uint(n->hi[7]);
#endif
    *h0 = *near0 <= far0 && (*c0 | *n0) != 0u;
    *h1 = *near1 <= far1 && (*c1 | *n1) != 0u;
}

/* Core traversal.  any_hit: stop at the first intersection in (tmin, tmax).  Returns the leaf
 * segment index of the hit (HT_NO_HIT for none) and its distance in *t_out. */
HT_FN uint ht_traverse(HT_GEOMETRY_PARAMS, HtRay ray, int any_hit, real* t_out) {
    const real3 o = make_real3(ray.ox, ray.oy, ray.oz);
    const real3 d = make_real3(ray.dx, ray.dy, ray.dz);
    const real tmin = ray.tmin;
    /* x < C ? x : C keeps a +inf tmax out of every later comparison. */
    real tbest = (real)ray.tmax < HT_T_FAR ? (real)ray.tmax : HT_T_FAR;
    uint best = HT_NO_HIT;

    const HtSlabRay slab = ht_slab_ray(o, d);

    uint stack_node[HT_STACK_SIZE];
    real stack_t[HT_STACK_SIZE];
    int sp = 0;
    uint cur = 0;

    for (;;) {
        HT_CONST_GLOBAL HtBvhNode* n = HT_NODE_PTR(cur);
        real near0, near1;
        uint c0, c1, n0, n1;
        int h0, h1;
        ht_node_slabs(n, &slab, tmin, tbest, &near0, &near1, &h0, &h1, &c0, &c1, &n0, &n1);

        /* Leaves now, the nearer one first. */
        if (h0 && n0 != 0u && h1 && n1 != 0u && near1 < near0) {
            if (ht_intersect_leaf(HT_SEGS_ARG, HT_POINTS_ARG, c1, n1, o, d, tmin, &tbest, &best) && any_hit) break;
            h1 = 0;
        }
        if (h0 && n0 != 0u) {
            if (ht_intersect_leaf(HT_SEGS_ARG, HT_POINTS_ARG, c0, n0, o, d, tmin, &tbest, &best) && any_hit) break;
            h0 = 0;
        }
        if (h1 && n1 != 0u) {
            if (ht_intersect_leaf(HT_SEGS_ARG, HT_POINTS_ARG, c1, n1, o, d, tmin, &tbest, &best) && any_hit) break;
            h1 = 0;
        }
        /* A leaf may have shortened the ray. */
        h0 = h0 && near0 <= tbest;
        h1 = h1 && near1 <= tbest;

        if (h0 && h1) {
            const int first1 = near1 < near0;
            cur = first1 ? c1 : c0;
            stack_node[sp] = first1 ? c0 : c1;
            stack_t[sp] = first1 ? near0 : near1;
            ++sp;
            continue;
        }
        if (h0) {
            cur = c0;
            continue;
        }
        if (h1) {
            cur = c1;
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
    return best;
}

/* Closest hit with the fibre quantities the shading stages need (see HtHit). */
HT_FN void ht_trace_closest(HT_GEOMETRY_PARAMS, HtRay ray, HtHit* hit) {
    real t;
    const uint best = ht_traverse(HT_GEOMETRY_ARGS, ray, 0, &t);
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
    if (s.flags & HT_SEG_TRIANGLE) {
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

/* Shadow rays: 1 if anything lies in (tmin, tmax). */
HT_FN uint ht_trace_any(HT_GEOMETRY_PARAMS, HtRay ray) {
    real t;
    return ht_traverse(HT_GEOMETRY_ARGS, ray, 1, &t) != HT_NO_HIT ? 1u : 0u;
}

#endif /* HT_GEOMETRY_BVH_TRAVERSE_H */
