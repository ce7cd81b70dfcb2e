/* Multiple importance sampling weights shared by every shading stage. */
#ifndef HT_INTEGRATOR_MIS_H
#define HT_INTEGRATOR_MIS_H

#include "../compat.h"

/* Power heuristic (Veach): weight of the strategy with pdf a against the one with pdf b. */
HT_FN real ht_mis_power(real a, real b) {
    real a2 = a * a, b2 = b * b;
    return a2 + b2 > HT_R(0) ? a2 / (a2 + b2) : HT_R(0);
}

#endif
