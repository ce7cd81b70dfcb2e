/* Random numbers: a pure function of (seed, pixel, sample, bounce, slot).
 *
 * No state is carried between kernels or threads, so an image depends only on the seed and the
 * sample count -- not on the thread count, the device, the launch order, checkpoints or how the
 * samples are split across devices and machines.  Two samplers, chosen at kernel build time
 * (HT_SAMPLER_SOBOL, `render --sampler`; part of the build options and so of the render's identity):
 *   sobol (1)        Owen-scrambled Sobol' points (sobol.h), one jointly stratified group per use;
 *   independent (0)  counter-based hashing, every dimension independent (A/B reference).
 *
 * Dimension layout of one bounce (the slot numbers; the independent sampler uses dimension
 * bounce * HT_DIMS_PER_BOUNCE + slot, so adding a bounce never changes the numbers of earlier
 * ones).  For sobol, the slots that are used together form one group -- the components of one
 * padded Sobol' set -- so their first 2^m samples are stratified jointly:
 *
 *   group       slots (Sobol' component)              used for
 *   CAMERA      PIXEL_X (0), PIXEL_Y (1)              sub-pixel jitter (bounce 0 only)
 *   LIGHT       LIGHT_U (0), LIGHT_V (1), LIGHT_PICK (2)  next-event light point and which light
 *   BSDF_THETA  BSDF_1 (0), BSDF_2 (1)                fibre: longitudinal angle (u1, u2);
 *                                                     surfaces: the cosine-weighted direction
 *   BSDF_PHI    BSDF_0 (0), BSDF_3 (1)                fibre: lobe pick u0 (its remainder is reused
 *                                                     with u3 for the azimuth, kernels/fiber/zinke.h)
 *   ROULETTE    RR (0), LIGHT_RR (1)                  Russian roulette of the path; of its
 *                                                     next-event estimate (--light-threshold)
 *   LIGHT_VERTEX LV_PICK (0), LV_RR (1)               --light-vertices: which light vertex a
 *                                                     vertex connects to; that connection's
 *                                                     light-threshold roulette
 *   LIGHT_RAY   LR_U (0), LR_V (1)                    --light-vertices: a light ray's start on
 *                                                     its disc (pixel HT_LIGHT_RAY_PIXEL, bounce 0,
 *                                                     sample index sample * count + ray)
 * The last two groups came after the others; their Sobol' group numbers lie above every bounce's
 * (HT_GROUP_EXTRA_BASE), so adding them left the numbers of the first five as they were.
 *
 * Every pair above is components 0/1 of its group: the first two Sobol' dimensions, a (0,2)-sequence
 * (tests/unit/sobol_test.cpp checks the nets).
 *
 * First-hit splits (--first-hit-splits N, kernels/stages/shade.cl): the camera path's own draws --
 * the jitter and the first vertex's next-event estimate -- take sample index `sample`; each of its
 * N continuations takes index sample * N + split (ht_continuation_sample) for everything from the
 * first vertex's BCSDF sample on.  So every continuation has numbers of its own, still a pure
 * function of (seed, pixel, sample, split, dimension); for the Sobol' sampler the N continuations
 * of a camera sample are N consecutive indices of each group -- an aligned block of N points when
 * N is a power of two, which the shuffle keeps together -- so their first directions are
 * stratified among themselves.  N = 1 gives every draw index `sample`, as without splits. */
#ifndef HT_RNG_H
#define HT_RNG_H

#include "hash.h"
#include "sobol.h"

#ifndef HT_SAMPLER_SOBOL
#define HT_SAMPLER_SOBOL 0
#endif

#define HT_DIMS_PER_BOUNCE 16u
/* dimension slots inside one bounce */
#define HT_DIM_PIXEL_X 0u
#define HT_DIM_PIXEL_Y 1u
#define HT_DIM_LIGHT_PICK 2u
#define HT_DIM_LIGHT_U 3u
#define HT_DIM_LIGHT_V 4u
#define HT_DIM_BSDF_0 5u /* 5..8: the four uniforms of the fibre sampler */
#define HT_DIM_RR 9u
#define HT_DIM_LIGHT_RR 10u
#define HT_DIM_LV_PICK 11u
#define HT_DIM_LV_RR 12u
#define HT_DIM_LR_U 13u
#define HT_DIM_LR_V 14u
/* the pixel number of light rays' draws (no camera pixel has it: images are < 2^32 pixels) */
#define HT_LIGHT_RAY_PIXEL 0xFFFFFFFFu

/* Sobol' groups inside one bounce */
#define HT_GROUPS_PER_BOUNCE 5u
#define HT_GROUP_CAMERA 0u
#define HT_GROUP_LIGHT 1u
#define HT_GROUP_BSDF_THETA 2u
#define HT_GROUP_BSDF_PHI 3u
#define HT_GROUP_ROULETTE 4u
#define HT_GROUP_LIGHT_VERTEX 5u
#define HT_GROUP_LIGHT_RAY 6u
/* Sobol' group number of the groups past the first HT_GROUPS_PER_BOUNCE: above any bounce's */
#define HT_GROUP_EXTRA_BASE 0x40000000u

/* Independent sampler: uniform in [0, 1), the top 24 bits, exact in float and never 1. */
HT_FN real ht_uniform(uint seed, uint pixel, uint sample, uint dim) {
    return (real)(ht_hash4(seed, pixel, sample, dim) >> 8) * HT_R(5.9604644775390625e-8);
}

HT_FN uint ht_dim(uint bounce, uint slot) { return bounce * HT_DIMS_PER_BOUNCE + slot; }

/* The sample index of continuation `split` (0..splits-1) of camera sample `sample` (the layout above). */
HT_FN uint ht_continuation_sample(uint sample, uint splits, uint split) { return sample * splits + split; }

/* The Sobol' group of a slot (the layout table above); comp receives its component. */
HT_FN uint ht_slot_group(uint slot, uint* comp) {
    switch (slot) {
    case HT_DIM_PIXEL_X: *comp = 0u; return HT_GROUP_CAMERA;
    case HT_DIM_PIXEL_Y: *comp = 1u; return HT_GROUP_CAMERA;
    case HT_DIM_LIGHT_U: *comp = 0u; return HT_GROUP_LIGHT;
    case HT_DIM_LIGHT_V: *comp = 1u; return HT_GROUP_LIGHT;
    case HT_DIM_LIGHT_PICK: *comp = 2u; return HT_GROUP_LIGHT;
    case HT_DIM_BSDF_0 + 1u: *comp = 0u; return HT_GROUP_BSDF_THETA;
    case HT_DIM_BSDF_0 + 2u: *comp = 1u; return HT_GROUP_BSDF_THETA;
    case HT_DIM_BSDF_0: *comp = 0u; return HT_GROUP_BSDF_PHI;
    case HT_DIM_BSDF_0 + 3u: *comp = 1u; return HT_GROUP_BSDF_PHI;
    case HT_DIM_LIGHT_RR: *comp = 1u; return HT_GROUP_ROULETTE;
    case HT_DIM_LV_PICK: *comp = 0u; return HT_GROUP_LIGHT_VERTEX;
    case HT_DIM_LV_RR: *comp = 1u; return HT_GROUP_LIGHT_VERTEX;
    case HT_DIM_LR_U: *comp = 0u; return HT_GROUP_LIGHT_RAY;
    case HT_DIM_LR_V: *comp = 1u; return HT_GROUP_LIGHT_RAY;
    default: *comp = 0u; return HT_GROUP_ROULETTE;
    }
}

/* The Sobol' group number of group `group` of `bounce`. */
HT_FN uint ht_group_number(uint bounce, uint group) {
    return group < HT_GROUPS_PER_BOUNCE ? bounce * HT_GROUPS_PER_BOUNCE + group
                                        : HT_GROUP_EXTRA_BASE + (group - HT_GROUPS_PER_BOUNCE) * 0x10000u + bounce;
}

/* Owen-scrambled Sobol' sampler: the slot's component of its group's padded set. */
HT_FN real ht_sobol_sample(uint seed, uint pixel, uint sample, uint bounce, uint slot) {
    uint comp;
    uint group = ht_slot_group(slot, &comp);
    return ht_sobol_uniform(seed, pixel, ht_group_number(bounce, group), sample, comp);
}

/* The sampler the kernels were built with. */
HT_FN real ht_sample(uint seed, uint pixel, uint sample, uint bounce, uint slot) {
#if HT_SAMPLER_SOBOL
    return ht_sobol_sample(seed, pixel, sample, bounce, slot);
#else
    return ht_uniform(seed, pixel, sample, ht_dim(bounce, slot));
#endif
}

/* The pair of slots that are components 0 and 1 of slot_a's group (the pairs of the layout
 * above): one group seed and one shuffle for both; the numbers of two ht_sobol_sample calls
 * (tests/unit/sobol_test.cpp). */
HT_FN void ht_sobol_sample2(uint seed, uint pixel, uint sample, uint bounce, uint slot_a, real* a, real* b) {
    uint comp;
    const uint group = ht_slot_group(slot_a, &comp);
    ht_sobol_uniform2(seed, pixel, ht_group_number(bounce, group), sample, a, b);
}

/* Slots a and b of one bounce drawn together; for sobol they must be components 0 and 1 of one
 * group (a pair of the layout above). */
HT_FN void ht_sample2(uint seed, uint pixel, uint sample, uint bounce, uint slot_a, uint slot_b, real* a, real* b) {
#if HT_SAMPLER_SOBOL
    ht_sobol_sample2(seed, pixel, sample, bounce, slot_a, a, b);
    (void)slot_b;
#else
    *a = ht_uniform(seed, pixel, sample, ht_dim(bounce, slot_a));
    *b = ht_uniform(seed, pixel, sample, ht_dim(bounce, slot_b));
#endif
}

#endif
