// Host (double) checks of the portable ray/triangle test (kernels/geometry/triangle.h).
#include <gtest/gtest.h>

#include "kernels/geometry/triangle.h"

#include <cmath>
#include <random>

namespace {

real3 v3(double x, double y, double z) { return make_real3(x, y, z); }
constexpr double kFar = 1e30;

double tri_hit(real3 o, real3 d, real3 p0, real3 p1, real3 p2, double* b1 = nullptr,
               double* b2 = nullptr, double tmin = 0) {
    real u = -1, v = -1;
    const double t = ht_triangle_intersect(o, d, p0, p1, p2, tmin, kFar, &u, &v);
    if (b1) *b1 = u;
    if (b2) *b2 = v;
    return t;
}

TEST(Triangle, HitDistanceAndBarycentrics) {
    const real3 p0 = v3(0, 0, 0), p1 = v3(2, 0, 0), p2 = v3(0, 2, 0);
    double b1, b2;
    const double t = tri_hit(v3(0.5, 0.25, 3), v3(0, 0, -1), p0, p1, p2, &b1, &b2);
    EXPECT_NEAR(t, 3.0, 1e-12);
    EXPECT_NEAR(b1, 0.25, 1e-12);
    EXPECT_NEAR(b2, 0.125, 1e-12);
    // Back face is hit too (no culling), t in units of |d|.
    EXPECT_NEAR(tri_hit(v3(0.5, 0.25, -3), v3(0, 0, 2), p0, p1, p2), 1.5, 1e-12);
    // Outside, behind, at tmin, parallel: misses.
    EXPECT_EQ(tri_hit(v3(1.5, 1.5, 3), v3(0, 0, -1), p0, p1, p2), kFar);
    EXPECT_EQ(tri_hit(v3(0.5, 0.25, 3), v3(0, 0, 1), p0, p1, p2), kFar);
    EXPECT_EQ(tri_hit(v3(0.5, 0.25, 3), v3(0, 0, -1), p0, p1, p2, nullptr, nullptr, 3.0), kFar);
    EXPECT_EQ(tri_hit(v3(-1, 0.5, 0), v3(1, 0, 0), p0, p1, p2), kFar);
    // Geometric normal: counter-clockwise front.
    const real3 n = ht_triangle_normal(p0, p1, p2);
    EXPECT_NEAR(n.z, 1.0, 1e-15);
}

TEST(Triangle, SharedEdgeIsNotAGap) {
    // A quad as two triangles; rays through points on the diagonal hit at least one of them.
    const real3 a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(1, 1, 0), d = v3(0, 1, 0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.001, 0.999);
    int gaps = 0;
    for (int i = 0; i < 10000; ++i) {
        const double s = u(rng);
        const real3 target = v3(s, s, 0);
        const real3 o = v3(u(rng) * 4 - 2, u(rng) * 4 - 2, 3);
        const real3 dir = target - o;
        const bool h = tri_hit(o, dir, a, b, c) < kFar || tri_hit(o, dir, a, c, d) < kFar;
        gaps += !h;
    }
    EXPECT_EQ(gaps, 0);
}

// Random triangles and rays: the hit point lies in the triangle's plane, reconstructs from the
// barycentrics, and hit/miss agrees with an independent plane-intersection + inside test.
TEST(Triangle, MatchesPlaneAndInsideTest) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int hits = 0, disagree = 0;
    for (int i = 0; i < 20000; ++i) {
        const real3 p0 = v3(u(rng), u(rng), u(rng)), p1 = v3(u(rng), u(rng), u(rng)),
                    p2 = v3(u(rng), u(rng), u(rng));
        const real3 o = v3(3 * u(rng), 3 * u(rng), 3 * u(rng));
        // Aimed at barycentrics in [-0.3, 1.3]: about half hit, and edges get crossed.
        const double a1 = 0.8 * u(rng) + 0.5, a2 = 0.8 * u(rng) + 0.5;
        const real3 d = (p0 * (1 - a1 - a2) + p1 * a1 + p2 * a2) - o;
        double b1, b2;
        const double t = tri_hit(o, d, p0, p1, p2, &b1, &b2);
        // Reference: plane hit, then signed areas.
        const real3 n = cross(p1 - p0, p2 - p0);
        const double dn = dot(d, n);
        bool ref = false;
        double tr = 0;
        if (std::fabs(dn) > 1e-12) {
            tr = dot(p0 - o, n) / dn;
            const real3 p = o + d * tr;
            const double s0 = dot(cross(p1 - p0, p - p0), n), s1 = dot(cross(p2 - p1, p - p1), n),
                         s2 = dot(cross(p0 - p2, p - p2), n);
            const double eps = 1e-9 * dot(n, n);
            // Only clear-cut cases count: skip rays within rounding of an edge.
            if (std::fabs(s0) < eps || std::fabs(s1) < eps || std::fabs(s2) < eps) continue;
            ref = tr > 0 && s0 > 0 && s1 > 0 && s2 > 0;
        }
        const bool got = t < kFar;
        disagree += got != ref;
        if (got && ref) {
            ++hits;
            EXPECT_NEAR(t, tr, 1e-9 * std::max(1.0, std::fabs(tr)));
            const real3 p = o + d * t;
            const real3 q = p0 * (1 - b1 - b2) + p1 * b1 + p2 * b2;
            EXPECT_NEAR(length(p - q), 0.0, 1e-9);
        }
    }
    EXPECT_EQ(disagree, 0);
    EXPECT_GT(hits, 3000);
}

}  // namespace
