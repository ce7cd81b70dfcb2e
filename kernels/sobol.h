/* Owen-scrambled Sobol' points, a pure function of (seed, pixel, group, sample index, component).
 *
 * Burley 2020, "Practical Hash-based Owen Scrambling": the sample index is shuffled per pixel and
 * group by a nested uniform (Owen) scramble, the shuffled index picks a point of the first four
 * Sobol' dimensions, and each component is Owen-scrambled again with its own seed.  A "group" is
 * a set of up to four dimensions a sampler uses together (the camera's x/y, a light's u/v...):
 * every group gets its own shuffle, so groups are decorrelated while the components inside one
 * are stratified jointly -- the padding of pbrt-v4's PaddedSobolSampler.
 *
 * Why the first 2^m samples of a group form a (0,m,2)-net in components 0/1 for every m: the
 * Sobol' generator matrices are upper triangular, so the first m output digits depend only on the
 * m lowest index bits; the shuffle permutes those bits among themselves (a nested scramble of the
 * bit-reversed index changes bit k from bits above k only) and leaves the higher ones constant
 * within each aligned block of 2^m samples (a digital shift); an Owen scramble of the output keeps
 * every elementary interval's point count.  tests/unit/sobol_test.cpp checks it. */
#ifndef HT_SOBOL_H
#define HT_SOBOL_H

#include "hash.h"

HT_FN uint ht_reverse_bits32(uint x) {
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    return x;
}

/* Hash-based Laine-Karras permutation of a bit-reversed value: every step (add, multiply by an
 * odd number, xor with a multiple by an even number) changes bit k from bits below k only, which
 * is what makes it a nested scramble once the bits are reversed back.  The constants are the
 * improved set of pbrt-v4's FastOwenScrambler (better avalanche than Burley's original four). */
HT_FN uint ht_laine_karras(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/* Nested uniform scramble in base 2 of a 32-bit fixed-point fraction (or of a sample index),
 * given the value bit-reversed (the Sobol' points are built that way round,
 * ht_sobol_bits_reversed). */
HT_FN uint ht_owen_scramble_reversed(uint x_reversed, uint seed) {
    return ht_reverse_bits32(ht_laine_karras(x_reversed, seed));
}
HT_FN uint ht_owen_scramble(uint x, uint seed) { return ht_owen_scramble_reversed(ht_reverse_bits32(x), seed); }

/* The seed of one group of one pixel: every (seed, pixel, group) gets its own shuffle and
 * scrambles; the constants keep it apart from ht_hash4's other uses. */
HT_FN uint ht_sobol_group_seed(uint seed, uint pixel, uint group) {
    uint h = ht_hash32(seed ^ 0x5bd1e995u);
    h = ht_hash32(h ^ pixel);
    return ht_hash32(h ^ (group * 0x27d4eb2du + 0x165667b1u));
}

/* Burley's shuffle: the sample index Owen-scrambled, then xor-ed with the scramble of 0.  That
 * xor keeps the bits above the sample's highest bit 0 (scrambled they would be a constant of the
 * seed: a digital shift of the points, which the output scramble absorbs anyway), so the Sobol'
 * loop runs over log2(sample) bits instead of 32, and the first 2^m samples are a permutation of
 * the indices [0, 2^m). */
HT_FN uint ht_sobol_shuffle(uint sample, uint seed) {
    return ht_reverse_bits32(ht_laine_karras(ht_reverse_bits32(sample), seed) ^ ht_laine_karras(0u, seed));
}

/* Sobol' dimension dim (0..3) of point `index`, bit-reversed (the output scramble reverses its
 * input, ht_owen_scramble_reversed, so the sampler wants the point that way round).  Dimension 0 is the van
 * der Corput sequence, whose reversal is the index itself; 1..3 follow Joe & Kuo's primitive
 * polynomials x+1, x^2+x+1, x^3+x+1 with initial direction numbers (1), (1,3), (1,3,1).  The
 * direction numbers are made on the fly by their recurrence (in 32-bit fixed point: v_k = a_1
 * v_{k-1} ^ ... ^ v_{k-s} ^ (v_{k-s} >> s)) run reversed -- a right shift becomes a left shift,
 * v_1 = 2^31 becomes 1 -- in a loop over the index's bits instead of a table that OpenCL C and C++
 * would declare apart. */
HT_FN uint ht_sobol_bits_reversed(uint index, uint dim) {
    if (dim == 0u) return index;
    uint r1 = 1u, r2 = 0u, r3 = 0u;
    uint k = 1u;
    uint x = 0u;
    while (index != 0u) {
        if (index & 1u) x ^= r1;
        index >>= 1;
        ++k;
        uint r;
        if (dim == 1u) {
            r = r1 ^ (r1 << 1);
        } else if (dim == 2u) {
            r = k == 2u ? 3u : r1 ^ r2 ^ (r2 << 2);
        } else {
            r = k == 2u ? 3u : (k == 3u ? 4u : r2 ^ r3 ^ (r3 << 3));
        }
        r3 = r2;
        r2 = r1;
        r1 = r;
    }
    return x;
}

/* The point itself as a 32-bit fraction. */
HT_FN uint ht_sobol_bits(uint index, uint dim) { return ht_reverse_bits32(ht_sobol_bits_reversed(index, dim)); }

/* Component `comp` (0..3) of the point with shuffled index `index` of a group: a 32-bit fraction,
 * the Sobol' bits Owen-scrambled with the component's own seed. */
HT_FN uint ht_sobol_component_bits(uint group_seed, uint index, uint comp) {
    return ht_owen_scramble_reversed(ht_sobol_bits_reversed(index, comp), ht_hash32(group_seed + (comp + 1u) * 0x9e3779b9u));
}

/* Component `comp` (0..3) of sample `sample` of a group: a 32-bit fraction. */
HT_FN uint ht_sobol_group_bits(uint group_seed, uint sample, uint comp) {
    return ht_sobol_component_bits(group_seed, ht_sobol_shuffle(sample, group_seed), comp);
}

/* The top 24 bits as a uniform in [0, 1): exact in float and never rounded to 1. */
HT_FN real ht_sobol_to_unit(uint bits) { return (real)(bits >> 8) * HT_R(5.9604644775390625e-8); }

HT_FN real ht_sobol_uniform(uint seed, uint pixel, uint group, uint sample, uint comp) {
    return ht_sobol_to_unit(ht_sobol_group_bits(ht_sobol_group_seed(seed, pixel, group), sample, comp));
}

/* Components 0 and 1 of one group's point: one group seed and one shuffle for both. */
HT_FN void ht_sobol_uniform2(uint seed, uint pixel, uint group, uint sample, real* u0, real* u1) {
    const uint group_seed = ht_sobol_group_seed(seed, pixel, group);
    const uint index = ht_sobol_shuffle(sample, group_seed);
    *u0 = ht_sobol_to_unit(ht_sobol_component_bits(group_seed, index, 0u));
    *u1 = ht_sobol_to_unit(ht_sobol_component_bits(group_seed, index, 1u));
}

#endif
