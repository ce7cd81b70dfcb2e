/* --first-hit-splits auto: the pilot's two stages (host/render/split_choice.h chooses N from what
 * they gather).  A pilot sample is an ordinary sample with N = HT_PILOT_SPLITS continuations
 * (kernels/types.h); besides the film it needs how much of each sample's variance the
 * continuations carry.
 *
 * pilot_record_first_vertex runs after the first bounce's shadow rays are resolved: each path
 * slot's radiance is then all its camera sample's first vertex gave it (the camera ray's
 * environment, the first-hit next-event estimates credited to that slot), so what a slot gains
 * later is its continuation's alone.
 *
 * pilot_accumulate, in place of accumulate: work-item i takes pilot pixel list_offset + i and its
 * `samples` camera paths of the pass (i samples .., as accumulate does), each, with slot
 * radiances R_j and first-vertex parts F_j (continuation j in slot j < N), gives the sample
 * Y = sum_j R_j, its first vertex's part F = sum_j F_j and the continuations' values
 * c_j = R_j - F_j (each 1/N of a continuation's estimate C_j).  The pilot renders every pixel
 * with two seeds (`seed_half` 0 and 1: two independent scramblings of the same sampler); per
 * pilot pixel, with |v|^2 summed over the channels, it sums
 *   moments[4 list + 0]            += (Y, |Y|^2)
 *   moments[4 list + 1 + seed_half] += (F, 0)
 *   moments[4 list + 1].w          += |F|^2
 *   moments[4 list + 2].w          += N^2 / (N - 1) sum_j |c_j - mean c|^2
 *   moments[4 list + 3].w          += 1:
 * the sample's moments, the first vertex's per half (whose means differ by the error of either)
 * and its second moment, and an unbiased estimate of E[Var(C | first vertex)]: the variance the
 * splits divide by N.  Sums are taken in sample order, one work-item per pixel, with the same float
 * additions however many samples a pass holds. */
#include "../types.h"

__kernel void pilot_record_first_vertex(__global const HtPathState* paths, uint count,
                                        __global float4* first_vertex) {
    uint i = get_global_id(0);
    if (i >= count) return;
    const HtPathState s = paths[i];
    first_vertex[i] = (float4)(s.radiance[0], s.radiance[1], s.radiance[2], 0.0f);
}

__kernel void pilot_accumulate(__global const HtPathState* paths, __global const float4* first_vertex,
                               uint count, uint samples, uint slots, uint list_offset, uint seed_half,
                               __global float4* moments) {
    uint i = get_global_id(0);
    if (i >= count) return;
    __global float4* m = moments + 4u * (size_t)(list_offset + i);
    float4 m0 = m[0], m1 = m[1], m2 = m[2], m3 = m[3];
    for (uint k = 0u; k < samples; ++k) {
        const uint first = (i * samples + k) * slots;
        /* one read per slot; the continuations are the first HT_PILOT_SPLITS slots, any after them
         * (more first-hit light samples than continuations) hold light samples only */
        float3 y = (float3)(0.0f), f = (float3)(0.0f), c_mean = (float3)(0.0f);
        float3 c[HT_PILOT_SPLITS];
        for (uint j = 0u; j < slots; ++j) {
            const HtPathState s = paths[first + j];
            const float3 r = (float3)(s.radiance[0], s.radiance[1], s.radiance[2]);
            const float3 fj = first_vertex[first + j].xyz;
            y += r;
            f += fj;
            if (j < HT_PILOT_SPLITS) {
                c[j] = r - fj;
                c_mean += c[j];
            }
        }
        c_mean /= (float)HT_PILOT_SPLITS;
        float spread = 0.0f;
        for (uint j = 0u; j < HT_PILOT_SPLITS; ++j) spread += dot(c[j] - c_mean, c[j] - c_mean);
        const float n = (float)HT_PILOT_SPLITS;
        m0 += (float4)(y, dot(y, y));
        if (seed_half == 0u)
            m1.xyz += f;
        else
            m2.xyz += f;
        m1.w += dot(f, f);
        m2.w += n * n / (n - 1.0f) * spread;
        m3.w += 1.0f;
    }
    m[0] = m0, m[1] = m1, m[2] = m2, m[3] = m3;
}
