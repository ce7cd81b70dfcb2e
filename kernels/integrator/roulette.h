/* Russian roulette on a path's throughput (the largest channel), pbrt-v4's rule: a path is left
 * alone while that channel is at least 1, and below 1 it survives with probability equal to it
 * and is divided by it.  The surviving throughput is therefore never above 1 where it was below,
 * and a path at full energy is never boosted: in blond hair, where the fibre albedo is close to
 * 1 and paths run tens to hundreds of bounces, a fixed survival cap (0.95) multiplied surviving
 * paths by 1/0.95 per bounce (x169 after 100 bounces), a heavy tail that showed as sparkles and
 * as a white furnace whose 99th percentile was 2.3 (docs/ESTIMATOR.md).
 * A path that carries only a share of its camera sample (1/N for each of the N continuations of
 * --first-hit-splits N) is judged by throughput / share, the throughput it stands for: judged by
 * its own, all but about one of the N continuations would end at the first roulette, undoing the
 * split.  Its survivors then carry at most `share` in that channel.
 * Unbiased: E[result] = throughput for every u uniform in [0, 1). */
#ifndef HT_INTEGRATOR_ROULETTE_H
#define HT_INTEGRATOR_ROULETTE_H

#include "../compat.h"

HT_FN real3 ht_roulette(real3 throughput, real share, real u) {
    real m = ht_max(throughput.x, ht_max(throughput.y, throughput.z)) / share;
    if (m >= HT_R(1)) return throughput;
    if (!(m > HT_R(0))) return make_real3(0, 0, 0);
    return u < m ? throughput / m : make_real3(0, 0, 0);
}

#endif
