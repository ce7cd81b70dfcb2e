/* Marschner et al. 2003 far field -- being written; returns 0 until then. */
#ifndef HT_FIBER_MARSCHNER_H
#define HT_FIBER_MARSCHNER_H
#include "azimuthal.h"
HT_FN void ht_marschner_eval(const HtMaterial* m, real3 wo, real3 wi, real h, real3* lobes, real3* value, real* pdf) {
    for (int p = 0; p < 4; ++p) lobes[p] = ht_splat(R(0));
    *value = ht_splat(R(0)); *pdf = R(0);
}
HT_FN int ht_marschner_sample(const HtMaterial* m, real3 wo, real h, real u0, real u1, real u2, real u3, real3* wi, real3* weight, real* pdf) { return 0; }
#endif
