/* Integer hashes behind every random number: stateless, so a value depends only on its inputs. */
#ifndef HT_HASH_H
#define HT_HASH_H

#include "compat.h"

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

#endif
