// Host (double) checks of the light pick by importance (kernels/lights.h ht_light_delivered,
// ht_light_facing, ht_pick_light), which a single next-event estimate uses with --light-pick importance
// (kernels/stages/shade.cl ht_nee_sample).  The estimate L_i / q_i of the picked light i is
// unbiased when q is a distribution over the lights that reach p, chosen before the light's own
// sample numbers: what these tests pin down.
#include <gtest/gtest.h>

#include "kernels/lights.h"

#include <cmath>
#include <vector>

namespace {

HtLight light(uint type, double x, double y, double z, double intensity) {
    HtLight l{};
    l.type = type;
    l.position[0] = float(x), l.position[1] = float(y), l.position[2] = float(z);
    l.direction[0] = 0.0f, l.direction[1] = -1.0f, l.direction[2] = 0.0f;
    l.radiance[0] = float(intensity), l.radiance[1] = float(0.9 * intensity), l.radiance[2] = float(0.8 * intensity);
    l.cos_outer = float(std::cos(0.4)), l.cos_inner = float(std::cos(0.3));
    return l;
}

// A spot lighting p from above, one above but beside p (p outside its cone), a point light, a
// directional light, a sphere light, all of different strengths.
std::vector<HtLight> rig() {
    return {light(HT_LIGHT_SPOT, 0, 5, 0, 400), light(HT_LIGHT_SPOT, 6, 5, 0, 900),
            light(HT_LIGHT_POINT, 2, 1, 3, 20), light(HT_LIGHT_DIRECTIONAL, 0, 0, 0, 0.7),
            [] {
                HtLight s = light(HT_LIGHT_SPHERE, -3, 2, 1, 5);
                s.position[3] = 0.5f;
                return s;
            }()};
}

const real3 kP = make_real3(0.1, 0.2, -0.1);
// a fibre at p running along x: the spot above faces it squarely, the directional light (from
// +y) too
const real3 kAxis = make_real3(1, 0, 0);

double importance(const HtLight& l, real3 p = kP, real3 axis = kAxis, int is_normal = 0) {
    const double d = ht_light_delivered(&l, p);
    return d > 0 ? d * ht_light_facing(&l, p, axis, is_normal) : 0.0;
}
uint pick(const std::vector<HtLight>& r, real3 p, double u, double* inv) {
    return ht_pick_light(r.data(), uint(r.size()), p, kAxis, 0, u, inv);
}

double delivered(const HtLight& l, real3 p, double u, double v) {
    HtLightSample s;
    if (!ht_sample_light(&l, p, u, v, &s)) return 0;
    return s.li_over_pdf.x + s.li_over_pdf.y + s.li_over_pdf.z;
}

TEST(LightPick, WhatALightDeliversDoesNotDependOnItsNumbers) {
    // The pick may use li_over_pdf only because it does not depend on the sample's (u, v): a pick
    // by a quantity the numbers change would weight each light's samples unevenly.
    for (const HtLight& l : rig()) {
        const double w = ht_light_delivered(&l, kP);
        for (double u : {0.0, 0.13, 0.5, 0.77, 0.999})
            for (double v : {0.0, 0.31, 0.92}) EXPECT_NEAR(delivered(l, kP, u, v), w, 1e-12 * (1 + w)) << l.type;
    }
    const std::vector<HtLight> r = rig();
    EXPECT_EQ(importance(r[1]), 0.0);  // outside its cone
    for (size_t i : {0u, 2u, 3u, 4u}) EXPECT_GT(importance(r[i]), 0.0) << i;
}

TEST(LightPick, FacingIsTheFibresWidthOrTheSurfacesCosineAsTheLightSeesIt) {
    const HtLight spot = rig()[0];  // straight above p
    const real3 p = make_real3(0, 0, 0);
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(1, 0, 0), 0), 1.0, 1e-12);   // across a fibre
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(0, 1, 0), 0), 0.1, 1e-12);   // along it: the floor
    const double s = std::sqrt(0.5);
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(s, s, 0), 0), s, 1e-12);     // 45 degrees
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(0, -1, 0), 1), 1.0, 1e-12);  // a surface, either side
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(s, s, 0), 1), s, 1e-12);
    EXPECT_NEAR(ht_light_facing(&spot, p, make_real3(1, 0, 0), 1), 0.1, 1e-12);
    const HtLight sun = rig()[3];  // travels along -y: comes from +y wherever p is
    EXPECT_NEAR(ht_light_facing(&sun, make_real3(50, -3, 7), make_real3(0, 0, 1), 0), 1.0, 1e-12);
    EXPECT_NEAR(ht_light_facing(&sun, make_real3(50, -3, 7), make_real3(0, 1, 0), 1), 1.0, 1e-12);
    EXPECT_EQ(ht_light_facing(&spot, make_real3(0, 5, 0), make_real3(1, 0, 0), 0), 1.0);  // at the light
}

TEST(LightPick, PicksEachLightAsOftenAsItsProbabilitySaysAndEstimatesTheSumExactly) {
    // u over N midpoints of [0, 1): every light's share of picks is its q = 1 / inv_prob (to the
    // grid's 1/N), the q sum to 1, the light outside its cone is never picked, and the mean of
    // L_i / q_i over u is the sum of what the lights deliver -- the estimator's expectation.
    const std::vector<HtLight> r = rig();
    const uint n = uint(r.size());
    const int N = 1 << 18;
    std::vector<int> picks(n, 0);
    std::vector<double> q(n, 0);
    double estimate = 0;
    for (int k = 0; k < N; ++k) {
        double inv = 0;
        const uint i = pick(r, kP, (k + 0.5) / N, &inv);
        ASSERT_LT(i, n);
        ASSERT_GT(inv, 1.0);
        ++picks[i];
        q[i] = 1 / inv;
        estimate += importance(r[i]) * inv / N;
    }
    double total = 0, qsum = 0;
    for (uint i = 0; i < n; ++i) {
        total += importance(r[i]);
        qsum += q[i];
        EXPECT_NEAR(double(picks[i]) / N, q[i], 2.0 / N) << "light " << i;
    }
    EXPECT_EQ(picks[1], 0);
    EXPECT_NEAR(qsum, 1.0, 1e-12);
    EXPECT_NEAR(estimate / total, 1.0, 1e-4);
    // half by importance, half evenly over the four lights that reach p
    for (uint i : {0u, 2u, 3u, 4u}) EXPECT_NEAR(q[i], 0.5 * importance(r[i]) / total + 0.125, 1e-12);
}

TEST(LightPick, NothingWhenNoLightReachesThePoint) {
    std::vector<HtLight> r = rig();
    r.erase(r.begin() + 2, r.end());  // the two spots; move p out of the first one's cone too
    double inv = 7;
    EXPECT_EQ(pick(r, make_real3(-4, 0, 0), 0.3, &inv), 2u);
    EXPECT_EQ(inv, 0.0);
    EXPECT_EQ(pick(r, make_real3(0, 0, 0), 0.999999, &inv), 0u);
    EXPECT_DOUBLE_EQ(inv, 1.0);
}

TEST(LightPick, TheLastNumbersPickTheLastLightThatReaches) {
    // u just below 1, and 1 itself (which a float draw never gives), still name a light that reaches p
    const std::vector<HtLight> r = rig();
    for (double u : {std::nextafter(1.0, 0.0), 1.0}) {
        double inv = 0;
        EXPECT_EQ(pick(r, kP, u, &inv), 4u) << u;
        EXPECT_GT(inv, 1.0);
    }
}

TEST(LightPick, HugeLightsStayFinite) {
    // what a light delivers is capped, so the sum over HT_LIGHT_PICK_MAX lights of the largest float
    // intensities is finite and every probability positive
    std::vector<HtLight> r(HT_LIGHT_PICK_MAX, light(HT_LIGHT_DIRECTIONAL, 0, 0, 0, 3e38));
    r[3] = light(HT_LIGHT_POINT, 0, 1e-3, 0, 3e38);
    for (double u : {0.0, 0.2, 0.5, 0.99}) {
        double inv = 0;
        const uint i = pick(r, make_real3(0, 0, 0), u, &inv);
        EXPECT_LT(i, HT_LIGHT_PICK_MAX);
        EXPECT_TRUE(std::isfinite(inv) && inv >= 1.0) << inv;
    }
}

}  // namespace
