/* Stage 6: finished paths of a pass -> film.  film[pixel] holds (sum r, sum g, sum b, samples).
 * Camera path i renders a distinct pixel, so the film needs no atomics and the sum for a pixel is
 * taken in sample order: the image is independent of scheduling.  One sample of a pixel is the
 * sum of its camera path's `splits` path states (--first-hit-splits; each continuation already
 * carries 1/N of the weight), added in continuation order.
 * With `even` (an even sample index of a render --target-error) the sample is also added to
 * film_even: the half film whose difference from the odd half estimates each pixel's error
 * (host/render/adaptive.h). */
#include "../types.h"
#include "../aovs.h"
#include "stage_args.h"

__kernel void accumulate(__global const HtPathState* paths, uint count, uint splits,
                         __global float4* film, uint even,
                         __global float4* film_even HT_ACCUMULATE_AOV_PARAMS) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const uint first = i * splits;
    const uint pixel = paths[first].pixel;
    float3 radiance = (float3)(0.0f);
    for (uint j = 0u; j < splits; ++j) {
        const HtPathState s = paths[first + j];
        radiance += (float3)(s.radiance[0], s.radiance[1], s.radiance[2]);
    }
    float4 f = film[pixel];
    f += (float4)(radiance, 1.0f);
    film[pixel] = f;
    if (even) film_even[pixel] += (float4)(radiance, 1.0f);
#if HT_FEATURE_AOVS
    for (uint j = 0u; j < splits; ++j)
        for (uint c = 0u; c < HT_AOV_OUT; ++c)
            film_aov[(size_t)pixel * HT_AOV_OUT + c] += aovs[(size_t)(first + j) * HT_AOV_STRIDE + c];
#endif
}

/* The pixels that see no geometry (host/render/pixel_footprint.h), skipped by a sample over every
 * pixel: each gets what accumulate would have added for its camera ray, which misses --
 * `background` = (the environment's radiance, 1), the sum of a camera path whose only radiance is
 * that of its miss (the other slots add zeros) -- in the same float operations, so the film holds
 * the same bits as if it had been traced. */
__kernel void accumulate_background(__global const uint* pixels, uint count, float4 background,
                                    __global float4* film, uint even, __global float4* film_even) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const uint pixel = pixels[i];
    float4 f = film[pixel];
    f += background;
    film[pixel] = f;
    if (even) film_even[pixel] += background;
}
