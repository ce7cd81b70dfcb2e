/* Stage: occlusion (any hit in (tmin, tmax)) of a ray array against the hair BVH.
 * occluded[i] = 1 if rays[i] is blocked, else 0.  Self-contained like intersect_closest.cl. */
#include "../geometry/bvh_traverse.h"

__kernel void intersect_shadow(HT_GEOMETRY_PARAMS, __global const HtRay* rays, __global uint* occluded,
                               uint count) {
    const uint i = (uint)get_global_id(0);
    if (i >= count) return;
    HtRay r = rays[i];
    /* an empty slot (tmax < tmin) counts as occluded: nothing to add */
    occluded[i] = r.tmax > r.tmin ? ht_trace_any(HT_GEOMETRY_ARGS, r) : 1u;
}
