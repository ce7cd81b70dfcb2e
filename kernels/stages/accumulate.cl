/* Stage 6: finished paths of a pass -> film.  film[pixel] holds (sum r, sum g, sum b, samples).
 * Work-item i adds the `samples` samples of its pixel that the pass rendered (camera paths
 * i samples .. i samples + samples - 1, kernels/stages/generate_camera_rays.cl), in sample order;
 * pixels are distinct, so the film needs no atomics, and each sample is one addition of the same
 * float values as when a pass renders one sample: the image is independent of scheduling and of
 * how many samples share a pass.  One sample of a pixel is the sum of its camera path's `splits`
 * path states (--first-hit-splits; each continuation already carries 1/N of the weight), added in
 * continuation order.
 * With `halves` (render --target-error) a sample with an even index is also added to film_even:
 * the half film whose difference from the odd half estimates each pixel's error
 * (host/render/adaptive.h). */
#include "../types.h"
#include "../aovs.h"
#include "stage_args.h"

__kernel void accumulate(__global const HtPathState* paths, uint count, uint samples, uint splits,
                         __global float4* film, uint halves,
                         __global float4* film_even HT_ACCUMULATE_AOV_PARAMS) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const uint pixel = paths[i * samples * splits].pixel;
    float4 f = film[pixel];
    for (uint k = 0u; k < samples; ++k) {
        const uint first = (i * samples + k) * splits;
        float3 radiance = (float3)(0.0f);
        for (uint j = 0u; j < splits; ++j) {
            const HtPathState s = paths[first + j];
            radiance += (float3)(s.radiance[0], s.radiance[1], s.radiance[2]);
        }
        f += (float4)(radiance, 1.0f);
        if (halves && paths[first].sample % 2u == 0u) film_even[pixel] += (float4)(radiance, 1.0f);
#if HT_FEATURE_AOVS
        for (uint j = 0u; j < splits; ++j)
            for (uint c = 0u; c < HT_AOV_OUT; ++c)
                film_aov[(size_t)pixel * HT_AOV_OUT + c] += aovs[(size_t)(first + j) * HT_AOV_STRIDE + c];
#endif
    }
    film[pixel] = f;
}

/* The pixels that see no geometry (host/render/pixel_footprint.h), skipped by a sample over every
 * pixel: each gets what accumulate would have added for its camera ray, which misses --
 * `background` = (the environment's radiance, 1), the sum of a camera path whose only radiance is
 * that of its miss (the other slots add zeros) -- once for each of samples first_sample .., in
 * the same float operations, so the film holds the same bits as if they had been traced. */
__kernel void accumulate_background(__global const uint* pixels, uint count, float4 background, uint first_sample,
                                    uint samples, __global float4* film, uint halves, __global float4* film_even) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const uint pixel = pixels[i];
    float4 f = film[pixel];
    for (uint k = 0u; k < samples; ++k) {
        f += background;
        if (halves && (first_sample + k) % 2u == 0u) film_even[pixel] += background;
    }
    film[pixel] = f;
}
