// Host (double) checks of the portable capsule intersection and fibre frame.
#include <gtest/gtest.h>

#include "kernels/geometry/capsule.h"
#include "kernels/geometry/fiber_frame.h"

#include <cmath>
#include <random>

namespace {

real3 v3(double x, double y, double z) { return make_real3(x, y, z); }
constexpr double kFar = 1e30;

double hit(real3 o, real3 d, real3 p0, real3 p1, double r, bool first, double tmin = 0) {
    return ht_capsule_intersect(o, d, p0, p1, r, first ? 1u : 0u, tmin, kFar);
}

TEST(Capsule, PerpendicularCylinderHit) {
    // Segment along +x from 0 to 2, r = 0.5; ray down -z through (1, 0.3, 5).
    const double t = hit(v3(1, 0.3, 5), v3(0, 0, -1), v3(0, 0, 0), v3(2, 0, 0), 0.5, true);
    EXPECT_NEAR(t, 5 - std::sqrt(0.25 - 0.09), 1e-12);
    // Unnormalized direction: t is in units of |d|.
    const double t2 = hit(v3(1, 0.3, 5), v3(0, 0, -2), v3(0, 0, 0), v3(2, 0, 0), 0.5, true);
    EXPECT_NEAR(t2, t / 2, 1e-12);
    // Just outside the radius: miss.
    EXPECT_EQ(hit(v3(1, 0.51, 5), v3(0, 0, -1), v3(0, 0, 0), v3(2, 0, 0), 0.5, true), kFar);
}

TEST(Capsule, JointOwnership) {
    const real3 p0 = v3(0, 0, 0), p1 = v3(2, 0, 0);
    // Ray through the begin sphere only (x = -0.3, beyond the begin cap).
    const real3 o = v3(-0.3, 0, 5), d = v3(0, 0, -1);
    const double expect = 5 - std::sqrt(0.25 - 0.09);
    EXPECT_NEAR(hit(o, d, p0, p1, 0.5, true), expect, 1e-12);  // first segment owns it
    EXPECT_EQ(hit(o, d, p0, p1, 0.5, false), kFar);            // otherwise the previous one does
    // End sphere always owned.
    EXPECT_NEAR(hit(v3(2.3, 0, 5), d, p0, p1, 0.5, false), expect, 1e-12);
    // The previous segment (-2,0,0)-(0,0,0) owns the joint: its end sphere answers the ray.
    EXPECT_NEAR(hit(o, d, v3(-2, 0, 0), p0, 0.5, false), 5 - 0.5, 1e-12);
}

TEST(Capsule, ParallelRayMissesLikeEmbree) {
    // Along the axis, from outside: Embree misses the segment including its spheres.
    EXPECT_EQ(hit(v3(-5, 0, 0), v3(1, 0, 0), v3(0, 0, 0), v3(2, 0, 0), 0.5, true), kFar);
    // Parallel but off-axis inside the radius: also a miss (cylinder has no roots).
    EXPECT_EQ(hit(v3(-5, 0.2, 0), v3(1, 0, 0), v3(0, 0, 0), v3(2, 0, 0), 0.5, true), kFar);
    // Slightly tilted (1e-3 rad): hits the begin sphere.
    const double t = hit(v3(-5, 0, 0), v3(1, 1e-3, 0), v3(0, 0, 0), v3(2, 0, 0), 0.5, true);
    EXPECT_NEAR(t, 4.5, 1e-3);
}

TEST(Capsule, InsideOriginHitsExitSurface) {
    // Origin on the axis, deep inside: the exit is at distance r.
    EXPECT_NEAR(hit(v3(1, 0, 0), v3(0, 0, 1), v3(0, 0, 0), v3(2, 0, 0), 0.5, true), 0.5, 1e-12);
}

TEST(Capsule, OriginOnSurfaceIgnoresSegment) {
    // A ray spawned on the surface, going out or through, must not see its own fibre.
    const real3 p0 = v3(0, 0, 0), p1 = v3(2, 0, 0);
    EXPECT_EQ(hit(v3(1, 0, 0.5 - 1e-7), v3(0, 0.6, 0.8), p0, p1, 0.5, true), kFar);
    EXPECT_EQ(hit(v3(1, 0, 0.5 + 1e-7), v3(0, 0, -1), p0, p1, 0.5, true), kFar);
    // The same ray from 10 % outside the radius does hit (through-going).
    EXPECT_NEAR(hit(v3(1, 0, 0.55), v3(0, 0, -1), p0, p1, 0.5, true), 0.05, 1e-12);
    // 1 % of r inside is "really inside" (overlapping fibres): the exit is reported, as Embree.
    EXPECT_NEAR(hit(v3(1, 0, 0.495), v3(0, 0, 1), p0, p1, 0.5, true), 0.005, 1e-12);
    // Far from the world origin the band grows with the float resolution of the coordinates.
    const real3 q0 = v3(1000, 0, 0), q1 = v3(1002, 0, 0);
    EXPECT_EQ(hit(v3(1001, 0, 0.5 - 2e-4), v3(0, 0.6, 0.8), q0, q1, 0.5, true), kFar);
    EXPECT_NEAR(hit(v3(1001, 0, 0.49), v3(0, 0, 1), q0, q1, 0.5, true), 0.01, 1e-9);
}

TEST(Capsule, TminTmax) {
    const real3 o = v3(1, 0, 5), d = v3(0, 0, -1), p0 = v3(0, 0, 0), p1 = v3(2, 0, 0);
    // tmin past the entry: the exit (t = 5.5) is reported (no culling).
    EXPECT_NEAR(hit(o, d, p0, p1, 0.5, true, 4.6), 5.5, 1e-12);
    EXPECT_EQ(ht_capsule_intersect(o, d, p0, p1, 0.5, 1u, 0.0, 4.4), 4.4);
}

TEST(Capsule, HitOffsetAndU) {
    const real3 o = v3(0.5, 0.3, 5), d = v3(0, 0, -1), p0 = v3(0, 0, 0), p1 = v3(2, 0, 0);
    const double t = hit(o, d, p0, p1, 0.5, true);
    real3 tan;
    real u;
    const real3 off = ht_capsule_hit_offset(o, d, p0, p1, t, &tan, &u);
    EXPECT_NEAR(u, 0.25, 1e-12);
    EXPECT_NEAR(tan.x, 1, 1e-12);
    EXPECT_NEAR(off.y, 0.3, 1e-12);
    EXPECT_NEAR(off.z, 0.4, 1e-12);
}

TEST(FiberFrame, OrthonormalAndConvention) {
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    for (int i = 0; i < 1000; ++i) {
        const real3 t = normalize(v3(g(rng), g(rng), g(rng)));
        const real3 wo = normalize(v3(g(rng), g(rng), g(rng)));
        real3 x, y, z;
        ht_fiber_frame(t, wo, &x, &y, &z);
        EXPECT_NEAR(dot(x, x), 1, 1e-12);
        EXPECT_NEAR(dot(y, y), 1, 1e-12);
        EXPECT_NEAR(dot(z, z), 1, 1e-12);
        EXPECT_NEAR(dot(x, y), 0, 1e-12);
        EXPECT_NEAR(dot(y, z), 0, 1e-12);
        EXPECT_NEAR(dot(x, z), 0, 1e-12);
        // Right-handed: y = z x x.
        const real3 c = cross(z, x);
        EXPECT_NEAR(dot(c, y), 1, 1e-12);
        // wo in local coordinates: no y component, phi_o = +pi/2, sin(theta_o) = wo.t.
        const real3 l = ht_to_fiber_local(wo, x, y, z);
        EXPECT_NEAR(l.y, 0, 1e-12);
        EXPECT_GE(l.z, 0);
        EXPECT_NEAR(l.x, dot(wo, t), 1e-12);
        const real3 back = ht_from_fiber_local(l, x, y, z);
        EXPECT_NEAR(back.x, wo.x, 1e-12);
    }
    // wo parallel to t: still a valid frame.
    real3 x, y, z;
    ht_fiber_frame(v3(0, 0, 1), v3(0, 0, -1), &x, &y, &z);
    EXPECT_NEAR(dot(z, z), 1, 1e-12);
    EXPECT_NEAR(dot(z, x), 0, 1e-12);
    EXPECT_NEAR(dot(y, y), 1, 1e-12);
}

TEST(FiberFrame, HSignAndRange) {
    // Fibre along +x, viewer on +z: y = z x x = +y, so hits at +y offsets have h > 0.
    real3 x, y, z;
    ht_fiber_frame(v3(1, 0, 0), v3(0, 0, 1), &x, &y, &z);
    EXPECT_NEAR(y.y, 1, 1e-12);
    EXPECT_NEAR(ht_fiber_h(v3(0, 0.3, 0.4), y, 0.5), 0.6, 1e-12);
    EXPECT_NEAR(ht_fiber_h(v3(0, -0.6, 0.0), y, 0.5), -1.0, 1e-12);  // clamped
}

}  // namespace
