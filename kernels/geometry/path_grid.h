/* Closest hits of path rays from a uniform grid of capsule lists (kernels/types.h HtPathGrid; the
 * host's builder and the reasons are in host/render/path_grid.h).  A ray walks the cells it crosses
 * from its origin on (a 3-D DDA, Amanatides & Woo), tests each cell's list eight capsules at a time
 * with the BVH leaves' own test (bvh_traverse.h ht_intersect_entries), and stops in the first cell
 * whose far side lies beyond its closest hit.  Every capsule that meets the ray before that point
 * is listed in a cell the walk visited (the builder pads each capsule's cells by more than the
 * walk's rounding), and the order of ht_hit_precedes decides, so the answer is the tree's, bit
 * for bit. */
#ifndef HT_GEOMETRY_PATH_GRID_H
#define HT_GEOMETRY_PATH_GRID_H

#include "bvh_traverse.h"

/* The ray's closest hit (HT_NO_HIT for none) and its distance in *t_out. */
HT_FN uint ht_grid_closest(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                           HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray, real* t_out) {
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
        for (;;) {
            const uint cell = ((uint)c[2] * grid.dims[1] + (uint)c[1]) * grid.dims[0] + (uint)c[0];
            const uint end = cell_start[cell + 1u];
            for (uint g = cell_start[cell]; g < end; g += 8u)
                ht_intersect_entries(HT_SEGS_ARG, HT_POINTS_ARG, entries, g, end - g < 8u ? end - g : 8u, o, d, tmin,
                                     &tbest, &best);
            /* the axis whose cell wall comes first; stop where the closest hit lies before it
             * (a tie at the wall may still lose to a higher id beyond it, so strictly before) */
            const int a = next[0] <= next[1] ? (next[0] <= next[2] ? 0 : 2) : (next[1] <= next[2] ? 1 : 2);
            if (tbest < next[a]) break;
            c[a] += step[a];
            if ((uint)c[a] >= grid.dims[a]) break;
            next[a] += delta[a];
        }
    }
    *t_out = tbest;
    return best;
}

/* The closest hit with the fibre quantities the shading stages need (ht_closest_hit_record). */
HT_FN void ht_grid_trace_closest(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_CONST_GLOBAL uint* cell_start,
                                 HT_CONST_GLOBAL uint* entries, HtPathGrid grid, HtRay ray, HtHit* hit) {
    real t;
    const uint best = ht_grid_closest(HT_SEGS_ARG, HT_POINTS_ARG, cell_start, entries, grid, ray, &t);
    ht_closest_hit_record(HT_SEGS_ARG, HT_POINTS_ARG, ray, best, t, hit);
}

#endif /* HT_GEOMETRY_PATH_GRID_H */
