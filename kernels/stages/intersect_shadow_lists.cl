/* Stage: occlusion of a ray array, as intersect_shadow.cl answers it, with the lights' shadow lists
 * (host/render/shadow_lists.h): a ray along a directional light's grid direction (bit for bit: the
 * shade stage copies the light's), or one that runs to a point or spot light's position, tests the
 * list of its origin's cell instead of traversing the tree; outside the grid nothing blocks it; a
 * cell whose list was too long (HT_CANDIDATES_USE_TREE), and every other ray, take the tree.
 * Work-item k answers rays k * HT_SHADOW_LIST_RAYS_PER_ITEM onwards (geometry/candidate_list.h says
 * why), in three passes over them: cells found and their list bounds asked for, bounds read and
 * each list's first group asked for, rays answered.  The prefetches are hints: the answers are
 * those of one ray per work-item. */
#include "../geometry/candidate_list.h"

__kernel void intersect_shadow_lists(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global uint* occluded, uint count,
                                     uint grid_count, __global const HtShadowGrid* grids,
                                     __global const uint* candidate_start, __global const uint* candidate_count,
                                     __global const uint* candidate_prim, __global const float* candidate_key) {
    const uint first = (uint)get_global_id(0) * HT_SHADOW_LIST_RAYS_PER_ITEM;
    if (first >= count) return;
    const uint rays_here = count - first < HT_SHADOW_LIST_RAYS_PER_ITEM ? count - first : HT_SHADOW_LIST_RAYS_PER_ITEM;
    /* each ray's grid (grid_count: none serves it; the tree) and cell (HT_NO_CELL: nothing blocks it) */
    uint grid_of[HT_SHADOW_LIST_RAYS_PER_ITEM], cell_of[HT_SHADOW_LIST_RAYS_PER_ITEM];
    real limit_of[HT_SHADOW_LIST_RAYS_PER_ITEM];
    for (uint j = 0u; j < rays_here; ++j) {
        grid_of[j] = ht_shadow_grid_of(grids, grid_count, rays[first + j], &cell_of[j], &limit_of[j]);
        if (grid_of[j] != grid_count && cell_of[j] != HT_NO_CELL) {
            HT_PREFETCH(&candidate_count[cell_of[j]]);
            HT_PREFETCH(&candidate_start[cell_of[j]]);
        }
    }
    /* the group each list is walked from: a directional light's list from its end, a point light's
     * from its start (ht_shadow_list_any) */
    for (uint j = 0u; j < rays_here; ++j) {
        if (grid_of[j] == grid_count || cell_of[j] == HT_NO_CELL) continue;
        const uint n = candidate_count[cell_of[j]];
        if (n == 0u || n == HT_CANDIDATES_USE_TREE) continue;
        const uint start = candidate_start[cell_of[j]], in_group = n < 8u ? n : 8u;
        const uint group = grids[grid_of[j]].kind == HT_SHADOW_GRID_ALONG ? start + n - in_group : start;
        HT_PREFETCH(&candidate_prim[group]);
        HT_PREFETCH(&candidate_prim[group + in_group - 1u]);
        HT_PREFETCH(&candidate_key[group]);
        HT_PREFETCH(&candidate_key[group + in_group - 1u]);
    }
    for (uint j = 0u; j < rays_here; ++j) {
        const uint i = first + j;
        const HtRay r = rays[i];
        if (!(r.tmax > r.tmin)) {
            occluded[i] = 1u;
            continue;
        }
        const uint g = grid_of[j], cell = cell_of[j];
        const uint n = g == grid_count ? HT_CANDIDATES_USE_TREE : cell == HT_NO_CELL ? 0u : candidate_count[cell];
        if (n == HT_CANDIDATES_USE_TREE)
            occluded[i] = ht_trace_any(HT_GEOMETRY_ARGS, r);
        else
            occluded[i] = n == 0u ? 0u
                                  : ht_shadow_list_any(HT_SEGS_ARG, HT_POINTS_ARG, grids + g, candidate_prim + candidate_start[cell],
                                                       candidate_key + candidate_start[cell], n, r, limit_of[j]);
    }
}
