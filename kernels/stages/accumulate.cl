/* Stage 6: finished paths of a pass -> film.  film[pixel] holds (sum r, sum g, sum b, samples).
 * Path i renders a distinct pixel, so the film needs no atomics and the sum for a pixel is
 * taken in sample order: the image is independent of scheduling. */
#include "../types.h"

__kernel void accumulate(__global const HtPathState* paths, uint count, __global float4* film) {
    uint i = get_global_id(0);
    if (i >= count) return;
    HtPathState s = paths[i];
    float4 f = film[s.pixel];
    f += (float4)(s.radiance[0], s.radiance[1], s.radiance[2], 1.0f);
    film[s.pixel] = f;
}
