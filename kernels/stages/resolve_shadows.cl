/* Stage 5: shadow results -> path radiance.
 * Shadow ray j belongs to path shadow_contrib[j].path; if it reached the light unoccluded its
 * contribution is added.  A path queues at most one shadow ray per bounce, so no two work-items
 * touch the same path. */
#include "../types.h"

__kernel void resolve_shadows(__global const HtShadowContrib* shadow_contrib,
                              __global const uint* occluded, uint count,
                              __global HtPathState* paths) {
    uint j = get_global_id(0);
    if (j >= count || occluded[j]) return;
    HtShadowContrib c = shadow_contrib[j];
    __global HtPathState* s = &paths[c.path];
    s->radiance[0] += c.contrib[0];
    s->radiance[1] += c.contrib[1];
    s->radiance[2] += c.contrib[2];
}
