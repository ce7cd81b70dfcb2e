// Host (double) checks of the Russian roulette rule (kernels/integrator/roulette.h).
#include <gtest/gtest.h>

#include "kernels/integrator/roulette.h"

#include <cmath>

namespace {

real3 v3(double x, double y, double z) { return make_real3(x, y, z); }

TEST(Roulette, LeavesAPathAloneWhileItsThroughputIsAtLeastOne) {
    for (double u : {0.0, 0.25, 0.5, 0.999999}) {
        for (real3 t : {v3(1, 1, 1), v3(1, 0.2, 0.1), v3(0.1, 3, 0.5), v3(169, 1e-3, 0)}) {
            const real3 r = ht_roulette(t, 1.0, u);
            EXPECT_EQ(r.x, t.x);
            EXPECT_EQ(r.y, t.y);
            EXPECT_EQ(r.z, t.z);
        }
    }
}

TEST(Roulette, SurvivorsAreNeverLiftedAboveOne) {
    // survival probability = the largest channel m < 1; survivors carry throughput / m, whose
    // largest channel is exactly 1: a path can never come out brighter than a full-energy one
    for (double m : {0.9, 0.5, 0.01}) {
        const real3 r = ht_roulette(v3(m, m / 2, m / 4), 1.0, 0.0);
        EXPECT_DOUBLE_EQ(r.x, 1.0);
        EXPECT_DOUBLE_EQ(r.y, 0.5);
        EXPECT_DOUBLE_EQ(r.z, 0.25);
    }
}

TEST(Roulette, IsUnbiased) {
    // E over u uniform in [0,1) of the result equals the throughput (midpoint rule, exact up to
    // the grid: the survival interval [0, m) holds round(m N) of the N midpoints), for a whole
    // path and for one of 4 first-hit continuations (share 1/4)
    const int n = 1 << 16;
    for (double share : {1.0, 0.25}) {
        for (real3 t : {v3(0.7, 0.3, 0.1) * share, v3(0.05, 0.05, 0.02), v3(0.999, 0, 0.5) * share}) {
            double sx = 0, sy = 0, sz = 0;
            for (int i = 0; i < n; ++i) {
                const real3 r = ht_roulette(t, share, (i + 0.5) / n);
                sx += r.x;
                sy += r.y;
                sz += r.z;
            }
            EXPECT_NEAR(sx / n, t.x, 2.0 / n);
            EXPECT_NEAR(sy / n, t.y, 2.0 / n);
            EXPECT_NEAR(sz / n, t.z, 2.0 / n);
        }
    }
}

TEST(Roulette, AContinuationIsJudgedByTheThroughputItStandsFor) {
    // one of 4 first-hit continuations (share 1/4): a throughput of 1/4 stands for 1 and is left
    // alone; below it, the survival probability is 4x the largest channel, and survivors carry
    // 1/4 there, not 1 (which would undo the split)
    const real3 full = ht_roulette(v3(0.25, 0.1, 0), 0.25, 0.999);
    EXPECT_EQ(full.x, 0.25);
    EXPECT_EQ(full.y, 0.1);
    const real3 r = ht_roulette(v3(0.1, 0.05, 0), 0.25, 0.39);
    EXPECT_DOUBLE_EQ(r.x, 0.25);
    EXPECT_DOUBLE_EQ(r.y, 0.125);
    const real3 ended = ht_roulette(v3(0.1, 0.05, 0), 0.25, 0.41);
    EXPECT_EQ(ended.x + ended.y + ended.z, 0.0);
}

TEST(Roulette, EndsPathsWithoutEnergy) {
    const real3 r = ht_roulette(v3(0, 0, 0), 1.0, 0.0);
    EXPECT_EQ(r.x + r.y + r.z, 0.0);
    const real3 nan = ht_roulette(v3(std::nan(""), 0, 0), 1.0, 0.0);  // no NaN passes on
    EXPECT_EQ(nan.x, 0.0);
    EXPECT_EQ(nan.y + nan.z, 0.0);
}

TEST(LightRoulette, LeavesEstimatesAtOrAboveTheThresholdAlone) {
    for (double u : {0.0, 0.5, 0.999999}) {
        const real3 r = ht_light_roulette(v3(2, 1, 0.5), 0.05, 0.05, u);
        EXPECT_EQ(r.x, 2.0);
        EXPECT_EQ(r.y, 1.0);
        EXPECT_EQ(r.z, 0.5);
    }
}

TEST(LightRoulette, IsUnbiasedAndItsSurvivorsCarryTheThreshold) {
    // E over u of the result is c (midpoint rule, exact up to the grid), and a survivor's weight
    // is lifted to exactly the threshold: c T / q
    const int n = 1 << 16;
    const double threshold = 0.05;
    for (double q : {0.04, 0.01, 1e-4}) {
        const real3 c = v3(3, 0.5, 0.25) * q;  // an estimate with weight q and the light's radiance 3
        double sx = 0, sy = 0, sz = 0;
        int kept = 0;
        for (int i = 0; i < n; ++i) {
            const real3 r = ht_light_roulette(c, q, threshold, (i + 0.5) / n);
            sx += r.x;
            sy += r.y;
            sz += r.z;
            if (r.x > 0) {
                ++kept;
                EXPECT_DOUBLE_EQ(r.x, 3 * threshold);
            }
        }
        EXPECT_NEAR(sx / n, c.x, 3 * threshold * 1.0 / n);
        EXPECT_NEAR(sy / n, c.y, 0.5 * threshold * 1.0 / n);
        EXPECT_NEAR(sz / n, c.z, 0.25 * threshold * 1.0 / n);
        EXPECT_NEAR(double(kept) / n, q / threshold, 1.0 / n);
    }
}

TEST(LightRoulette, DropsEstimatesWithoutWeightAndPassesNoNaN) {
    const real3 zero = ht_light_roulette(v3(1, 1, 1), 0.0, 0.05, 0.0);
    EXPECT_EQ(zero.x + zero.y + zero.z, 0.0);
    const real3 nan = ht_light_roulette(v3(1, 1, 1), std::nan(""), 0.05, 0.0);
    EXPECT_EQ(nan.x, 1.0);  // a NaN weight is not below the threshold: the estimate is left as it is
}

}  // namespace
