/* Stage: closest hits of the camera rays (bounce 0).  Like intersect_closest.cl, except that a
 * ray whose pixel has a candidate list (host/render/candidate_lists.h) tests that list instead of
 * traversing the tree, with the same answer (geometry/candidate_list.h); pixels whose list was
 * too long (count = HT_CANDIDATES_USE_TREE) traverse the tree.  Camera ray i belongs to path
 * ray_path[i], whose state names its pixel; the ray leaves there the node of its hit, where the
 * path's next ray starts (intersect_closest_paths): the traversal's, or for a list's hit the node
 * holding that leaf entry (leaf_node, host/bvh/start_nodes.h). */
#include "../geometry/candidate_list.h"

__kernel void intersect_camera(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global HtHit* hits, uint count,
                               __global const uint* ray_path, __global HtPathState* paths,
                               __global const uint* candidate_start, __global const uint* candidate_count,
                               __global const uint* candidate_prim, __global const float* candidate_depth,
                               float4 depth_row, __global const uint* leaf_node) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    const HtRay ray = rays[i];
    __global HtPathState* path = &paths[ray_path[i]];
    const uint n = candidate_count[path->pixel];
    real t;
    uint best;
    if (n == HT_CANDIDATES_USE_TREE) {
        uint node;
        best = ht_traverse_from(HT_GEOMETRY_ARGS, ray, 0, 0u, &t, &node);
        path->node = node;
    } else {
        const uint b = candidate_start[path->pixel];
        best = ht_candidates_closest(HT_SEGS_ARG, HT_POINTS_ARG, candidate_prim + b, candidate_depth + b, n, ray,
                                     depth_row.xyz, &t);
        path->node = best != HT_NO_HIT ? leaf_node[best] : 0u;
    }
    HtHit hit;
    ht_closest_hit_record(HT_SEGS_ARG, HT_POINTS_ARG, ray, best, t, &hit);
    hits[i] = hit;
}
