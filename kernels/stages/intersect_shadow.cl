/* Stage: occlusion (any hit in (tmin, tmax)) of a ray array.  occluded[i] = 1 if rays[i] is
 * blocked, else 0; an empty slot (tmax < tmin) counts as occluded: nothing to add.  With
 * HT_FEATURE_PATH_GRID the rays walk the path rays' uniform grid (kernels/geometry/path_grid.h),
 * which the render has made for its path rays anyway: the tree's answers, and in renders the stage
 * took 0.8x the tree's time on the anchor's ball, 0.9x on its strand, 0.7x on the default scene and
 * the same on pbrt's lock and straight.hair (docs/PERFORMANCE.md section 1 "Shadow rays through the
 * path grid"); without it the hair BVH.  Self-contained like intersect_closest.cl. */
#include "../geometry/bvh_traverse.h"
#if HT_FEATURE_PATH_GRID
#include "../geometry/path_grid.h"
#include "stage_args.h"

__kernel void intersect_shadow(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global uint* occluded, uint count,
                               HT_PATH_GRID_PARAMS) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    const HtRay r = rays[i];
    occluded[i] = r.tmax > r.tmin ? ht_grid_occluded(HT_SEGS_ARG, HT_POINTS_ARG, grid_cells, grid_entries, grid, r) : 1u;
}
#endif

/* By the tree: the stage without the grid, and with it, where HT_SHADOW_TREE_TOO asks
 * (stages/intersect.cl, `bench`'s program, which times both), as intersect_shadow_tree. */
#if !HT_FEATURE_PATH_GRID || defined(HT_SHADOW_TREE_TOO)
#if HT_FEATURE_PATH_GRID
#define HT_SHADOW_TREE_KERNEL intersect_shadow_tree
#else
#define HT_SHADOW_TREE_KERNEL intersect_shadow
#endif
__kernel void HT_SHADOW_TREE_KERNEL(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global uint* occluded, uint count) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    const HtRay r = rays[i];
    occluded[i] = r.tmax > r.tmin ? ht_trace_any(HT_GEOMETRY_ARGS, r) : 1u;
}
#undef HT_SHADOW_TREE_KERNEL
#endif
