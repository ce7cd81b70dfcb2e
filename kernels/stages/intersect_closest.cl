/* Closest hits of a ray array against the hair BVH, from the root or from given nodes: `hairtrace
 * bench`'s program (intersect.cl) and --light-vertices' light rays (trace.cl).  Work-item i <
 * count traces rays[i] into hits[i]; the global size is rounded up to the local size (64) by the
 * host, hence the bound check.  The render loop's own form is intersect_closest_paths.cl. */
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
