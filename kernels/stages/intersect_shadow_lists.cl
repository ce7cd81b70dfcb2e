/* Stage: occlusion of a ray array, as intersect_shadow.cl answers it, with the lights' shadow lists
 * (host/render/shadow_lists.h): a ray along a directional light's grid direction (bit for bit: the
 * shade stage copies the light's), or one that runs to a point or spot light's position, tests the
 * list of its origin's cell instead of traversing the tree; outside the grid nothing blocks it; a
 * cell whose list was too long (HT_CANDIDATES_USE_TREE), and every other ray, take the tree. */
#include "../geometry/candidate_list.h"

__kernel void intersect_shadow_lists(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global uint* occluded, uint count,
                                     uint grid_count, __global const HtShadowGrid* grids,
                                     __global const uint* candidate_start, __global const uint* candidate_count,
                                     __global const uint* candidate_prim, __global const float* candidate_key) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    const HtRay r = rays[i];
    if (!(r.tmax > r.tmin)) {
        occluded[i] = 1u;
        return;
    }
    uint cell;
    real limit;
    const uint g = ht_shadow_grid_of(grids, grid_count, r, &cell, &limit);
    const uint n = g == grid_count ? HT_CANDIDATES_USE_TREE : cell == HT_NO_CELL ? 0u : candidate_count[cell];
    if (n == HT_CANDIDATES_USE_TREE)
        occluded[i] = ht_trace_any(HT_GEOMETRY_ARGS, r);
    else
        occluded[i] = n == 0u ? 0u
                              : ht_shadow_list_any(HT_SEGS_ARG, HT_POINTS_ARG, grids + g, candidate_prim + candidate_start[cell],
                                                   candidate_key + candidate_start[cell], n, r, limit);
}
