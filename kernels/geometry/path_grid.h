/* Closest hits of path rays, and the occlusion of shadow rays, from a uniform grid of capsule lists
 * (kernels/types.h HtPathGrid; the host's builder and the reasons are in host/render/path_grid.h).
 * A ray walks the cells it crosses from its origin on (a 3-D DDA, Amanatides & Woo), gathers the
 * capsules its cells list and tests them eight at a time with the BVH leaves' own test
 * (bvh_traverse.h ht_intersect_ids), and stops after the first cell whose far side lies beyond its
 * closest hit (a shadow ray: at its first hit).  Every capsule that meets the ray before that point
 * is listed in a cell the walk visited (the builder pads each capsule's cells by more than the
 * walk's rounding), and the order of ht_hit_precedes decides, so the answer is the tree's, bit for
 * bit.  Gathering across cells fills the groups: a cell lists 2-4 capsules where the ray passes on
 * the scenes measured, and a group of eight costs the same however few it holds; capsules tested
 * beyond the stopping cell, or twice (listed in two cells), can only add real hits, and the order
 * picks the same one among them (docs/PERFORMANCE.md section 1 "Path rays from a uniform grid"). */
#ifndef HT_GEOMETRY_PATH_GRID_H
#define HT_GEOMETRY_PATH_GRID_H

#include "bvh_traverse.h"

/* The index of cell (x, y, z) in cell_start: x + dims[0] * (y + dims[1] * z), so a step along x moves
 * by 1, along y by dims[0] and along z by dims[0] * dims[1].  (Bricks of 4 x 4 x 4 cells, to bring a
 * ray's next cell into the same cache lines more often, measured slower: docs/PERFORMANCE.md section 1
 * "Path rays from a uniform grid".) */
HT_FN uint ht_path_grid_cell(HtPathGrid grid, uint x, uint y, uint z) { return (z * grid.dims[1] + y) * grid.dims[0] + x; }

/* The walk of ht_grid_closest and ht_grid_occluded below: the closest hit (HT_NO_HIT for none) and
 * its distance in *t_out; with `any` (a constant at each call, so each caller's walk is compiled
 * without the other's test) it returns at the first group that holds a hit in (tmin, tmax), a hit
 * or HT_NO_HIT: the occlusion the tree's any-hit traversal finds, since every capsule that meets
 * the ray before tmax is listed in a cell the walk reaches. */
HT_FN uint ht_grid_walk(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                        HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray, const int any, real* t_out) {
    real3 o, d;
    real tbest = ht_ray_start(ray, &o, &d);
    const real tmin = ray.tmin;
    uint best = HT_NO_HIT;
    const real org[3] = {o.x, o.y, o.z}, dir[3] = {d.x, d.y, d.z};
    /* the part of the ray inside the grid's box */
    real inv[3], t0 = tmin, t1 = tbest;
    for (int a = 0; a < 3; ++a) {
        inv[a] = ht_safe_inv(dir[a]);
        const real ta = ((real)grid.lo[a] - org[a]) * inv[a];
        const real tb = ((real)grid.lo[a] + (real)grid.dims[a] * (real)grid.cell - org[a]) * inv[a];
        t0 = ht_max(t0, ht_min(ta, tb));
        t1 = ht_min(t1, ht_max(ta, tb));
    }
    if (t0 <= t1) {
        int c[3], step[3];
        real next[3], delta[3];
        for (int a = 0; a < 3; ++a) {
            const real p = org[a] + dir[a] * t0;
            const int k = (int)floor((p - (real)grid.lo[a]) * (real)grid.inv_cell);
            c[a] = k < 0 ? 0 : k >= (int)grid.dims[a] ? (int)grid.dims[a] - 1 : k;
            step[a] = inv[a] > HT_R(0) ? 1 : -1; /* inv's sign: a zero direction steps up, never reached */
            delta[a] = fabs(inv[a]) * (real)grid.cell;
            /* ht_safe_inv keeps a zero direction finite and huge: that axis never steps */
            next[a] = ((real)grid.lo[a] + (real)(c[a] + (step[a] > 0 ? 1 : 0)) * (real)grid.cell - org[a]) * inv[a];
        }
        uint cell = ht_path_grid_cell(grid, (uint)c[0], (uint)c[1], (uint)c[2]);
        const int row = (int)grid.dims[0], slice = (int)(grid.dims[0] * grid.dims[1]); /* steps in y and z */
        uint from = cell_start[cell], end = cell_start[cell + 1u];
        /* the entries of the cells walked so far that are not tested yet, tested eight at a time */
        uint pending[8], np = 0u;
        for (;;) {
            /* the axis whose cell wall comes first, and the cell beyond it */
            const int a = next[0] <= next[1] ? (next[0] <= next[2] ? 0 : 2) : (next[1] <= next[2] ? 1 : 2);
            const int beyond = c[a] + step[a];
            const int inside = (uint)beyond < grid.dims[a];
            /* that cell's list bounds read before this cell's entries: on random rays the walk waits
             * mostly on these loads, and this way the two overlap */
            const int stride = a == 0 ? 1 : a == 1 ? row : slice;
            const uint next_cell = inside ? (uint)((int)cell + step[a] * stride) : cell;
            const uint next_from = cell_start[next_cell], next_end = cell_start[next_cell + 1u];
            /* and that cell's first entries asked for as soon as their place is known (where every
             * later cell is empty the address is one past the array's end: a prefetch never faults) */
            HT_PREFETCH(&entries[next_from]);
            for (uint e = from; e < end; ++e) {
                const uint id = entries[e];
                /* its leaf record is read when its group is tested, after up to seven more entries
                 * and a cell or two of the walk: asked for now, a record that misses the caches
                 * arrives meanwhile (docs/PERFORMANCE.md section 1 "The grid's leaf records and
                 * next entries prefetched") */
                HT_PREFETCH(&HT_SEG(id));
                pending[np++] = id;
                if (np == 8u) {
                    const int found = ht_intersect_ids(HT_SEGS_ARG, HT_POINTS_ARG, pending, 8u, o, d, tmin, &tbest, &best);
                    np = 0u;
                    if (any && found) {
                        *t_out = tbest;
                        return best;
                    }
                }
            }
            /* stop where the closest hit lies before the wall (a tie at the wall may still lose to a
             * higher id beyond it, so strictly before); entries still pending are tested below, and
             * can only bring the hit nearer */
            if (tbest < next[a] || !inside) break;
            c[a] = beyond;
            next[a] += delta[a];
            cell = next_cell;
            from = next_from;
            end = next_end;
        }
        if (np) ht_intersect_ids(HT_SEGS_ARG, HT_POINTS_ARG, pending, np, o, d, tmin, &tbest, &best);
    }
    *t_out = tbest;
    return best;
}

/* The ray's closest hit (HT_NO_HIT for none) and its distance in *t_out. */
HT_FN uint ht_grid_closest(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                           HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray, real* t_out) {
    return ht_grid_walk(HT_SEGS_ARG, HT_POINTS_ARG, cell_start, entries, grid, ray, 0, t_out);
}

/* Whether anything blocks the ray in (tmin, tmax): 1 or 0, as ht_trace_any answers. */
HT_FN uint ht_grid_occluded(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                            HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray) {
    real t;
    return ht_grid_walk(HT_SEGS_ARG, HT_POINTS_ARG, cell_start, entries, grid, ray, 1, &t) != HT_NO_HIT;
}

/* The closest hit with the fibre quantities the shading stages need (ht_closest_hit_record). */
HT_FN void ht_grid_trace_closest(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                                 HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray, HtHit* hit) {
    real t;
    const uint best = ht_grid_closest(HT_SEGS_ARG, HT_POINTS_ARG, cell_start, entries, grid, ray, &t);
    ht_closest_hit_record(HT_SEGS_ARG, HT_POINTS_ARG, ray, best, t, hit);
}

#endif /* HT_GEOMETRY_PATH_GRID_H */
