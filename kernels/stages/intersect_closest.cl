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
