/* An orthonormal basis around a unit direction, for drawing directions about it (cosine-weighted
 * surface samples, light-guided continuations, light rays) without a branch on where it points
 * (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"). */
#ifndef HT_GEOMETRY_BASIS_H
#define HT_GEOMETRY_BASIS_H

#include "../compat.h"

/* t, b with (t, b, n) orthonormal, for unit n. */
HT_FN void ht_onb(real3 n, real3* t, real3* b) {
    const real s = n.z >= HT_R(0) ? HT_R(1) : HT_R(-1);
    const real a = HT_R(-1) / (s + n.z);
    const real c = n.x * n.y * a;
    *t = make_real3(HT_R(1) + s * n.x * n.x * a, s * c, -s * n.x);
    *b = make_real3(c, s + n.y * n.y * a, -n.y);
}

#endif
