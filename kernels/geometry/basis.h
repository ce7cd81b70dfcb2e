/* An orthonormal basis around a unit direction, for drawing directions about it (light-guided
 * continuations, light rays) without a branch on where it points (Duff et al. 2017, "Building an
 * Orthonormal Basis, Revisited"). */
#ifndef HT_GEOMETRY_BASIS_H
#define HT_GEOMETRY_BASIS_H

#include "../compat.h"

/* e1, e2 with (e1, e2, n) orthonormal, for unit n. */
HT_FN void ht_basis_around(real3 n, real3* e1, real3* e2) {
    const real sign = n.z >= HT_R(0) ? HT_R(1) : HT_R(-1);
    const real a = HT_R(-1) / (sign + n.z);
    const real b = n.x * n.y * a;
    *e1 = make_real3(HT_R(1) + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *e2 = make_real3(b, sign + n.y * n.y * a, -n.y);
}

#endif
