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
#include "../fiber/math.h"

HT_FN real3 ht_roulette(real3 throughput, real share, real u) {
    real m = ht_max_channel(throughput) / share;
    if (m >= HT_R(1)) return throughput;
    if (!(m > HT_R(0))) return make_real3(0, 0, 0);
    return u < m ? throughput / m : make_real3(0, 0, 0);
}

/* Light threshold (--light-threshold T; Cycles' "light threshold", appleseed's "low light
 * threshold"): a next-event estimate c whose weight q is below T traces its shadow ray only with
 * probability q / T and then carries c T / q.  q is the estimate without the light's radiance --
 * the largest channel of throughput x scattering value (cosine and MIS weight in), for the whole
 * camera sample it stands for -- so T is relative to the light and does not change with its
 * intensity.  In a lit lock most deep estimates are faint (a fibre's lobe seen off its peak, a
 * path that lost most of its energy) and most of their shadow rays meet hair anyway: they cost a
 * traversal each and add almost nothing.  Unbiased: E[result] = c for u uniform in [0, 1); the
 * variance it adds is at most c T per estimate in light units, a small share of a pixel's when T
 * is small (docs/ESTIMATOR.md).  Returns the estimate to queue (zero: no shadow ray). */
HT_FN real3 ht_light_roulette(real3 c, real q, real threshold, real u) {
    if (!(q < threshold)) return c;
    if (!(q > HT_R(0))) return make_real3(0, 0, 0);
    return u * threshold < q ? c * (threshold / q) : make_real3(0, 0, 0);
}

#endif
