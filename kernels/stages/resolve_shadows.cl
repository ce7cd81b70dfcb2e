/* Stage 5: shadow results -> path radiance.
 * Shadow slot j belongs to path shadow_contrib[j].path; if its ray reached the light unoccluded
 * the contribution is added (empty slots carry tmax < 0 and were reported occluded).  A path has
 * at most one shadow slot per bounce, so no two work-items touch the same path. */
#include "../types.h"
#include "../integrator/aov_record.h"
#include "stage_args.h"

__kernel void resolve_shadows(__global const HtShadowContrib* shadow_contrib,
                              __global const uint* occluded, uint count,
                              __global HtPathState* paths HT_RESOLVE_AOV_PARAMS) {
    uint j = get_global_id(0);
    if (j >= count || occluded[j]) return;
    HtShadowContrib c = shadow_contrib[j];
    __global HtPathState* s = &paths[c.path];
    s->radiance[0] += c.contrib[0];
    s->radiance[1] += c.contrib[1];
    s->radiance[2] += c.contrib[2];
#if HT_FEATURE_AOVS
    ht_aov_resolve(aovs, shadow_aov, j, c.path, (float3)(c.contrib[0], c.contrib[1], c.contrib[2]));
#endif
}
