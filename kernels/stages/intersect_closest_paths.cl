/* Stage: closest hits of a bounce's path rays.  Ray i belongs to path ray_path[i], whose traversal
 * starts at the node of its last hit (HtPathState.node, 0 for a camera ray) and which keeps this
 * hit's node for its next rays: the same hits as from the root (kernels/geometry/bvh_traverse.h
 * ht_traverse_from).  With HT_FEATURE_PATH_GRID the rays walk the uniform grid of capsule lists
 * instead (kernels/geometry/path_grid.h): the same hits again, and no node to keep.  The global size
 * is rounded up to the local size (64) by the host, hence the bound check. */
#include "../geometry/bvh_traverse.h"
#if HT_FEATURE_PATH_GRID
#include "../geometry/path_grid.h"
#include "stage_args.h"

__kernel void intersect_closest_paths(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global HtHit* hits, uint count,
                                      __global const uint* ray_path, __global HtPathState* paths, HT_PATH_GRID_PARAMS) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    HtHit hit;
    ht_grid_trace_closest(HT_SEGS_ARG, HT_POINTS_ARG, grid_cells, grid_entries, grid, rays[i], &hit);
    hits[i] = hit;
}
#else
__kernel void intersect_closest_paths(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global HtHit* hits, uint count,
                                      __global const uint* ray_path, __global HtPathState* paths) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    __global HtPathState* path = &paths[ray_path[i]];
    HtHit hit;
    uint node;
    ht_trace_closest_from(HT_GEOMETRY_ARGS, rays[i], path->node, &hit, &node);
    hits[i] = hit;
    path->node = node;
}
#endif
