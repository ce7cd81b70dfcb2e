/* Stage 6: finished paths of a pass -> film.  film[pixel] holds (sum r, sum g, sum b, samples).
 * Path i renders a distinct pixel, so the film needs no atomics and the sum for a pixel is
 * taken in sample order: the image is independent of scheduling. */
#include "../types.h"
#include "../aovs.h"
#include "stage_args.h"

__kernel void accumulate(__global const HtPathState* paths, uint count, __global float4* film HT_ACCUMULATE_AOV_PARAMS) {
    uint i = get_global_id(0);
    if (i >= count) return;
    HtPathState s = paths[i];
    float4 f = film[s.pixel];
    f += (float4)(s.radiance[0], s.radiance[1], s.radiance[2], 1.0f);
    film[s.pixel] = f;
#if HT_FEATURE_AOVS
    for (uint c = 0u; c < HT_AOV_OUT; ++c) film_aov[(size_t)s.pixel * HT_AOV_OUT + c] += aovs[(size_t)i * HT_AOV_STRIDE + c];
#endif
}
