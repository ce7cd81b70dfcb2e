/* Stage: occlusion of a ray array, as intersect_shadow.cl answers it, with the directional lights'
 * shadow lists (host/render/shadow_lists.h): a ray along one of the grids' directions (bit for bit:
 * the shade stage copies the light's) tests the list of its origin's cell instead of traversing the
 * tree; outside the grid nothing blocks it; a cell whose list was too long
 * (HT_CANDIDATES_USE_TREE), and every other ray, take the tree. */
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
    uint g = grid_count;
    for (uint k = 0u; k < grid_count; ++k)
        if (r.dx == grids[k].dir[0] && r.dy == grids[k].dir[1] && r.dz == grids[k].dir[2]) g = k;
    uint cell = HT_NO_CELL, n = HT_CANDIDATES_USE_TREE;
    if (g < grid_count) {
        cell = ht_shadow_cell(&grids[g], make_real3(r.ox, r.oy, r.oz));
        n = cell == HT_NO_CELL ? 0u : candidate_count[cell];
    }
    if (n == HT_CANDIDATES_USE_TREE)
        occluded[i] = ht_trace_any(HT_GEOMETRY_ARGS, r);
    else
        occluded[i] = n == 0u ? 0u
                              : ht_candidates_any(HT_SEGS_ARG, HT_POINTS_ARG, candidate_prim + candidate_start[cell],
                                                  candidate_key + candidate_start[cell], n, r);
}
