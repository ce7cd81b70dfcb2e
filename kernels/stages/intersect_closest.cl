/* Stage: closest hit of a ray array against the hair BVH.  Work-item i < count traces rays[i]
 * into hits[i]; the global size is rounded up to the local size (64) by the host, hence the
 * bound check.  Self-contained so the render loop can include it in its own program. */
#include "../geometry/bvh_traverse.h"

__kernel void intersect_closest(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global HtHit* hits,
                                uint count) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    HtHit hit;
    ht_trace_closest(HT_GEOMETRY_ARGS, rays[i], &hit);
    hits[i] = hit;
}

/* The same, ray i's traversal started at node starts[i] (0: the root): how `hairtrace bench` times
 * the render's rays as the render traced them (host/bvh/start_nodes.h); the same hits. */
__kernel void intersect_closest_from(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global HtHit* hits, uint count,
                                     __global const uint* starts) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    HtHit hit;
    uint node;
    ht_trace_closest_from(HT_GEOMETRY_ARGS, rays[i], starts[i], &hit, &node);
    hits[i] = hit;
}

/* The render loop's form: ray i belongs to path ray_path[i], whose traversal starts at the node of
 * its last hit (HtPathState.node, 0 for a camera ray) and which keeps this hit's node for its
 * next rays.  The same hits as intersect_closest (kernels/geometry/bvh_traverse.h ht_traverse_from). */
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
