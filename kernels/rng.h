/* Counter-based random numbers: a pure function of (seed, pixel, sample, dimension).
 *
 * No state is carried between kernels or threads, so an image depends only on the seed and the
 * sample count -- not on the thread count, the device, the launch order, checkpoints or how the
 * samples are split across devices and machines.  Dimensions are numbered per bounce
 * (HT_DIMS_PER_BOUNCE each) so adding a bounce never changes the numbers of earlier ones. */
#ifndef HT_RNG_H
#define HT_RNG_H

#include "compat.h"

#define HT_DIMS_PER_BOUNCE 16u
/* dimension slots inside one bounce */
#define HT_DIM_PIXEL_X 0u
#define HT_DIM_PIXEL_Y 1u
#define HT_DIM_LIGHT_PICK 2u
#define HT_DIM_LIGHT_U 3u
#define HT_DIM_LIGHT_V 4u
#define HT_DIM_BSDF_0 5u /* 5..8: the four uniforms of the fibre sampler */
#define HT_DIM_RR 9u

/* "lowbias32" integer hash (Chris Wellons' hash prospector): full avalanche, 2 multiplies. */
HT_FN uint ht_hash32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

HT_FN uint ht_hash4(uint a, uint b, uint c, uint d) {
    uint h = ht_hash32(a ^ 0x9e3779b9u);
    h = ht_hash32(h ^ b);
    h = ht_hash32(h ^ (c * 0x85ebca6bu));
    return ht_hash32(h ^ (d * 0xc2b2ae35u));
}

/* Uniform in [0, 1): the top 24 bits, so the float result is exact and never rounds to 1. */
HT_FN real ht_uniform(uint seed, uint pixel, uint sample, uint dim) {
    return (real)(ht_hash4(seed, pixel, sample, dim) >> 8) * HT_R(5.9604644775390625e-8);
}

HT_FN uint ht_dim(uint bounce, uint slot) { return bounce * HT_DIMS_PER_BOUNCE + slot; }

#endif
