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

/* Whether a shadow ray toward a point light is blocked, from the list of its cell
 * (host/render/shadow_lists.h, HT_SHADOW_GRID_FROM_POINT): prim[0 .. n), nearest the light first,
 * depth[i] its primitive's nearest depth from the light (nondecreasing, rounded down).  The ray's
 * points before the light lie no deeper than `limit` (the stage's bound from its origin's depth), so
 * the walk ends at the first group that starts deeper, or at a group holding a hit: the tree's
 * any-hit answer, since an entry tested needlessly can only give a true hit. */
HT_FN uint ht_candidates_any_near_first(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* prim,
                                        HT_CONST_GLOBAL float* depth, uint n, HtRay ray, real limit) {
    real3 o, d;
    real tbest = ht_ray_start(ray, &o, &d);
    const real tmin = ray.tmin;
    uint best = HT_NO_HIT;
    for (uint g = 0u; g < n && (real)depth[g] <= limit; g += 8u)
        if (ht_intersect_entries(HT_SEGS_ARG, HT_POINTS_ARG, prim, g, n - g < 8u ? n - g : 8u, o, d, tmin, &tbest, &best))
            return 1u;
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

/* Whether shadow ray r runs to the point light of grid `grid` (HT_SHADOW_GRID_FROM_POINT): towards
 * it, its line passing within dir[3] of it (the shade stage spawns a fibre's ray up to about two
 * radii beside the point it aimed from).  The ray's part before the light then lies within dir[3]
 * of the line from the light through its origin, and the builder widened every primitive's image
 * by that much: the origin's cell lists every primitive the ray can meet. */
HT_FN int ht_ray_runs_to_point(HT_CONST_GLOBAL HtShadowGrid* grid, HtRay r) {
    const real3 to = make_real3((real)grid->dir[0] - (real)r.ox, (real)grid->dir[1] - (real)r.oy, (real)grid->dir[2] - (real)r.oz);
    const real3 d = make_real3(r.dx, r.dy, r.dz);
    const real3 c = cross(to, d);
    const real beside = (real)grid->dir[3];
    return dot(to, d) > HT_R(0) && dot(c, c) <= beside * beside * dot(d, d);
}

/* The cell of a point light's grid that a shadow ray from o takes (its index among all grids' cells),
 * or HT_NO_CELL when no primitive lies between o and the light (o outside the image, or no deeper
 * than the light: every primitive lies deeper than dir[3] in front of it); *limit: how deep the
 * ray's points before the light may lie (o's depth, allowing for the line's offset and rounding). */
HT_FN uint ht_point_shadow_cell(HT_CONST_GLOBAL HtShadowGrid* grid, real3 o, real* limit) {
    const real3 rel = o - make_real3(grid->dir[0], grid->dir[1], grid->dir[2]);
    const real z = dot(rel, make_real3(grid->u[0], grid->u[1], grid->u[2]));
    *limit = z * HT_R(1.0001) + (real)grid->dir[3];
    if (!(z > HT_R(0))) return HT_NO_CELL;
    /* as host/render/primitive_images.cpp maps a camera's NDC to pixels (y downwards) */
    const real cx = (dot(rel, make_real3(grid->v[0], grid->v[1], grid->v[2])) / z + HT_R(1)) * HT_R(0.5) * (real)grid->nx;
    const real cy = (HT_R(1) - dot(rel, make_real3(grid->w[0], grid->w[1], grid->w[2])) / z) * HT_R(0.5) * (real)grid->ny;
    if (!(cx >= HT_R(0) && cx < (real)grid->nx && cy >= HT_R(0) && cy < (real)grid->ny)) return HT_NO_CELL;
    return grid->cell_offset + (uint)cy * grid->nx + (uint)cx;
}

/* Which of the lights' grids serves shadow ray r (grid_count: none; the first that does), the cell
 * of it that the ray takes (HT_NO_CELL: nothing can block it) and, for a point light's, the depth
 * limit of ht_point_shadow_cell. */
HT_FN uint ht_shadow_grid_of(HT_CONST_GLOBAL HtShadowGrid* grids, uint grid_count, HtRay r, uint* cell, real* limit) {
    *cell = HT_NO_CELL;
    *limit = HT_R(0);
    for (uint k = 0u; k < grid_count; ++k) {
        HT_CONST_GLOBAL HtShadowGrid* g = grids + k;
        const real3 o = make_real3(r.ox, r.oy, r.oz);
        if (g->kind == HT_SHADOW_GRID_ALONG) {
            if (r.dx == g->dir[0] && r.dy == g->dir[1] && r.dz == g->dir[2]) {
                *cell = ht_shadow_cell(g, o);
                return k;
            }
        } else if (ht_ray_runs_to_point(g, r)) {
            *cell = ht_point_shadow_cell(g, o, limit);
            return k;
        }
    }
    return grid_count;
}

/* intersect_shadow_lists answers this many rays per work-item: it finds every ray's cell and asks
 * for its list bounds, then reads those and asks for each list's first group, then tests the rays,
 * so the loads of one ray overlap those of the others instead of each ray waiting on its own three
 * in turn (a render's shadow rays come from scattered points, for two or three lights in turn:
 * neighbouring rays rarely share a list).  Measured on the CPU device, 2, 4, 8 and 16
 * (docs/PERFORMANCE.md section 1 "Shadow lists: sixteen rays per work-item"). */
#define HT_SHADOW_LIST_RAYS_PER_ITEM 16u
/* The stage's work-items for n rays (the host's global size before rounding to the local size). */
HT_FN uint ht_shadow_list_items(uint n) {
    return n / HT_SHADOW_LIST_RAYS_PER_ITEM + (n % HT_SHADOW_LIST_RAYS_PER_ITEM != 0u ? 1u : 0u);
}

/* Whether shadow ray r is blocked, from the n entries of its cell's list in `grid` (n > 0 and not
 * HT_CANDIDATES_USE_TREE): the tree's answer. */
HT_FN uint ht_shadow_list_any(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL HtShadowGrid* grid, HT_CONST_GLOBAL uint* prim,
                              HT_CONST_GLOBAL float* key, uint n, HtRay r, real limit) {
    return grid->kind == HT_SHADOW_GRID_ALONG ? ht_candidates_any(HT_SEGS_ARG, HT_POINTS_ARG, prim, key, n, r)
                                              : ht_candidates_any_near_first(HT_SEGS_ARG, HT_POINTS_ARG, prim, key, n, r, limit);
}

#endif /* HT_GEOMETRY_CANDIDATE_LIST_H */
