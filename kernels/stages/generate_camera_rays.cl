/* Stage 1: camera -> extension queue.
 * A pass renders `samples` consecutive samples (first_sample ..) of each of its pixels: camera
 * path i renders pixel (pixel_offset + i / samples) for sample first_sample + i % samples, so the
 * samples of a pixel are neighbouring work-items and find its candidate list and its fibres in
 * cache.  Its ray goes to rays[i].  With --first-hit-splits N it owns the N path states from i N
 * on -- itself (continuation 0, ray_path[i] = i N) and the continuations its first vertex will
 * start (kernels/stages/shade.cl) -- all starting with throughput 1 and radiance 0, so that
 * accumulate can add them up whether they were started or not.
 * With `listed` (render --target-error) the pixel is pixel_list[pixel_offset + i / samples]
 * instead: the pixels still short of the target.  The random numbers depend on the pixel and the
 * sample, never on the slot, so a pixel renders the same sample whichever others share its pass. */
#include "../types.h"
#include "../rng.h"
#include "../camera.h"

__kernel void generate_camera_rays(HtCamera camera, uint pixel_offset, uint count, uint seed,
                                   uint first_sample, uint samples, uint splits, __global const uint* pixel_list,
                                   uint listed, __global HtRay* rays, __global uint* ray_path,
                                   __global HtPathState* paths) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const uint index = pixel_offset + i / samples, sample = first_sample + i % samples;
    uint pixel = listed ? pixel_list[index] : index;
    uint px = pixel % camera.width, py = pixel / camera.width;
    float jx, jy;
    ht_sample2(seed, pixel, sample, 0u, HT_DIM_PIXEL_X, HT_DIM_PIXEL_Y, &jx, &jy);
    rays[i] = ht_camera_ray(&camera, px, py, jx, jy);
    ray_path[i] = i * splits;
    HtPathState s;
    s.throughput[0] = s.throughput[1] = s.throughput[2] = 1.0f;
    s.radiance[0] = s.radiance[1] = s.radiance[2] = 0.0f;
    s.pixel = pixel;
    s.flags = HT_PATH_FROM_CAMERA;
    s.last_pdf = 0.0f;
    s.sample = sample;
    s.node = 0u;
    for (uint j = 0u; j < splits; ++j) {
        s.split = j;
        paths[i * splits + j] = s;
    }
}
