/* Writing the per-path records of render --aovs (layout: kernels/aovs.h).  Only compiled with
 * HT_FEATURE_AOVS: without it no kernel has the buffers or spends a cycle on them.  Nothing here
 * needs a fibre model, so the stages around shade that include it stay free of the models
 * (their build is shared across scenes: host/render/renderer.cpp); the lobe split that shade
 * computes is in aov_lobes.h. */
#ifndef HT_AOV_RECORD_H
#define HT_AOV_RECORD_H

#include "../aovs.h"
#include "../types.h"

#if HT_FEATURE_AOVS

HT_FN void ht_aov_add3(__global float* rec, uint at, float3 c) {
    rec[at] += c.x; rec[at + 1u] += c.y; rec[at + 2u] += c.z;
}

/* Radiance c reaching the camera through path record rec after `scatterings` scatterings, with
 * first-vertex lobe fractions f: into direct or indirect, and split over the lobes. */
HT_FN void ht_aov_add_light(__global float* rec, float3 c, uint scatterings, float4 f) {
    ht_aov_add3(rec, scatterings <= 1u ? HT_AOV_DIRECT : HT_AOV_INDIRECT, c);
    ht_aov_add3(rec, HT_AOV_LOBES + 0u, c * f.x);
    ht_aov_add3(rec, HT_AOV_LOBES + 3u, c * f.y);
    ht_aov_add3(rec, HT_AOV_LOBES + 6u, c * f.z);
    ht_aov_add3(rec, HT_AOV_LOBES + 9u, c * f.w);
}

HT_FN float4 ht_aov_fractions(__global const float* rec) {
    return (float4)(rec[HT_AOV_FRACTIONS], rec[HT_AOV_FRACTIONS + 1u], rec[HT_AOV_FRACTIONS + 2u],
                    rec[HT_AOV_FRACTIONS + 3u]);
}

/* An unoccluded next-event contribution c of shadow slot j: its share in its path's record. */
HT_FN void ht_aov_resolve(__global float* aovs, __global const float* shadow_aov, uint j, uint path, float3 c) {
    __global const float* sa = shadow_aov + (size_t)j * HT_SHADOW_AOV_STRIDE;
    ht_aov_add_light(aovs + (size_t)path * HT_AOV_STRIDE, c, sa[4] > 0.5f ? 1u : 2u,
                     (float4)(sa[0], sa[1], sa[2], sa[3]));
}

/* The camera ray's record: coverage, depth and tangent of what it met; the records of its other
 * first-hit continuations (the `splits` - 1 after it, --first-hit-splits) start empty, since
 * accumulate adds them all up whether they went on or not. */
HT_FN void ht_aov_begin(__global float* rec, const HtHit* hit, uint splits) {
    for (uint i = 0u; i < splits * HT_AOV_STRIDE; ++i) rec[i] = 0.0f;
    if (hit->segment == HT_NO_HIT) return;
    rec[HT_AOV_ALPHA] = 1.0f;
    rec[HT_AOV_DEPTH] = hit->t;
    rec[HT_AOV_TANGENT] = hit->tx;
    rec[HT_AOV_TANGENT + 1u] = hit->ty;
    rec[HT_AOV_TANGENT + 2u] = hit->tz;
}

#endif /* HT_FEATURE_AOVS */
#endif /* HT_AOV_RECORD_H */
