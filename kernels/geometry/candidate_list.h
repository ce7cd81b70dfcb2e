/* Closest hit of a camera ray among its pixel's candidates (host/render/candidate_lists.h
 * pixel_candidates): the primitives whose projected bounds cover the pixel, nearest depth first.
 * No primitive outside the list can meet a ray through the pixel, and the candidates go through
 * the tree's own leaf test (ht_intersect_entries) in the same total order of (t, global id), so
 * the answer is the tree's, bit for bit.  A dense lock puts a few dozen primitives under a pixel,
 * and a ray that meets the front ones stops after a group or two: much less than the descent
 * through the tree (docs/PERFORMANCE.md "Camera rays from per-pixel lists"). */
#ifndef HT_GEOMETRY_CANDIDATE_LIST_H
#define HT_GEOMETRY_CANDIDATE_LIST_H

#include "bvh_traverse.h"

/* A pixel's or cell's list count that means "traverse the tree" (host/render/candidate_lists.h
 * kCandidatesUseTree) */
#define HT_CANDIDATES_USE_TREE 0xFFFFFFFFu

/* The list prim[0 .. n), depths depth[0 ..) (nondecreasing, each at most its primitive's nearest
 * depth), against the ray; depth_row . d is the ray's depth per unit of t.  Returns the closest
 * hit's leaf index (HT_NO_HIT for none) and its distance in *t_out, as ht_traverse does. */
HT_FN uint ht_candidates_closest(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* prim,
                                 HT_CONST_GLOBAL float* depth, uint n, HtRay ray, real3 depth_row, real* t_out) {
    real3 o, d;
    real tbest = ht_ray_start(ray, &o, &d);
    const real tmin = ray.tmin;
    uint best = HT_NO_HIT;
    /* A point at depth z lies at t = z / (depth_row . d) on the ray; the bound is lowered by a
     * relative 1e-3, far beyond the rounding of that division and of the capsule test's roots,
     * so a candidate is never passed over while it could still win.  A ray that does not advance
     * in depth (not a camera ray through the image) gets no bound and tests the whole list. */
    const real per_t = dot(depth_row, d);
    const real scale = per_t > HT_R(0) ? HT_R(0.999) / per_t : HT_R(0);
    for (uint g = 0u; g < n; g += 8u) {
        if ((real)depth[g] * scale > tbest) break;
        ht_intersect_entries(HT_SEGS_ARG, HT_POINTS_ARG, prim, g, n - g < 8u ? n - g : 8u, o, d, tmin, &tbest, &best);
    }
    *t_out = tbest;
    return best;
}

/* Whether a shadow ray along a directional light's `dir` is blocked, from the list of its cell
 * (host/render/shadow_lists.h): prim[0 .. n) with key[i] how far along dir primitive i reaches
 * (nondecreasing, rounded up).  A primitive reaching no further than the ray's origin cannot
 * block it, and testing one anyway changes no answer (a hit it gave would be a true hit, which
 * the tree finds too): so the list is walked from its end, the primitives reaching furthest
 * towards the light first, in groups of eight through the tree's leaf test, until a group's
 * furthest entry reaches no further than the origin (with an allowance of a relative 1e-4 for
 * the float arithmetic) or a group holds a hit -- the tree's any-hit answer.  Walking down in
 * sequence reads the list's cache lines in order; a binary search for the first entry past the
 * origin, then a walk up, waited on a miss at each of its steps (docs/PERFORMANCE.md section 8). */
HT_FN uint ht_candidates_any(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* prim, HT_CONST_GLOBAL float* key,
                             uint n, HtRay ray) {
    real3 o, d;
    real tbest = ht_ray_start(ray, &o, &d);
    const real tmin = ray.tmin;
    uint best = HT_NO_HIT;
    const real w = dot(o, d);
    const real reach = w - HT_R(1e-4) * (HT_R(1) + fabs(w));
    for (uint end = n; end > 0u && (real)key[end - 1u] > reach; end = end > 8u ? end - 8u : 0u) {
        const uint g = end > 8u ? end - 8u : 0u;
        if (ht_intersect_entries(HT_SEGS_ARG, HT_POINTS_ARG, prim, g, end - g, o, d, tmin, &tbest, &best))
            return 1u;
    }
    return 0u;
}

/* The cell of grid `grid` that a point o lies in (its index among all grids' cells), or
 * HT_NO_CELL when o lies outside the grid, where no primitive's shadow reaches. */
#define HT_NO_CELL 0xFFFFFFFFu
HT_FN uint ht_shadow_cell(HT_CONST_GLOBAL HtShadowGrid* grid, real3 o) {
    const real cu = (dot(o, make_real3(grid->u[0], grid->u[1], grid->u[2])) - (real)grid->u[3]) * (real)grid->inv_cell;
    const real cv = (dot(o, make_real3(grid->v[0], grid->v[1], grid->v[2])) - (real)grid->v[3]) * (real)grid->inv_cell;
    if (!(cu >= HT_R(0) && cu < (real)grid->nx && cv >= HT_R(0) && cv < (real)grid->ny)) return HT_NO_CELL;
    return grid->cell_offset + (uint)cv * grid->nx + (uint)cu;
}

#endif /* HT_GEOMETRY_CANDIDATE_LIST_H */
