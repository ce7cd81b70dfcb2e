// Host (double) checks of light-vertex next-event estimation's densities
// (kernels/integrator/light_vertices.h): each density a connection or a continuation is weighted by
// must be the density of the rays that make its vertices.  Rays are shot as the kernels shoot them
// (ht_light_ray for the lights, uniform directions for a continuation) at a thin fibre; the
// fraction that hits it must equal the density integrated over the fibre on its measure
// radius x ds x dh (h over [-1, 1]): a density off by a factor (a cosine, the disc's area, a light's
// share, the cone's solid angle) would move the MIS weights of every connection, and with them
// the image.  tests/render/light_vertices_test.cpp checks the images.
#include <gtest/gtest.h>

#include "kernels/integrator/light_vertices.h"

#include <cmath>
#include <random>

namespace {

struct Fibre {
    real3 a, t;  // start and unit tangent
    double length, radius;
};

// Whether the ray o + s w (s > 0) passes within the fibre's radius of its axis segment: the closest
// approach of two lines (the fibre is thin, its end caps negligible).
bool hits(const Fibre& f, real3 o, real3 w) {
    const real3 d = o - f.a;
    const double b = dot(w, f.t), c = dot(w, d), e = dot(f.t, d);
    const double den = 1.0 - b * b;
    if (den < 1e-12) return false;
    const double s = (b * e - c) / den, u = (e - b * c) / den;
    if (s <= 0 || u < 0 || u > f.length) return false;
    const real3 gap = d + w * s - f.t * u;
    return dot(gap, gap) < f.radius * f.radius;
}

// The density integrated over the fibre: radius x 2 (h) x the integral along its axis (midpoints).
template <class Density>
double integrated(const Fibre& f, Density density) {
    const int n = 400;
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += density(f.a + f.t * ((i + 0.5) / n * f.length));
    return f.radius * 2.0 * sum * f.length / n;
}

HtLightVertices sphere_of(real3 c, double r, uint count) {
    HtLightVertices lv{};
    lv.disc[0] = float(c.x), lv.disc[1] = float(c.y), lv.disc[2] = float(c.z), lv.disc[3] = float(r);
    lv.count = count;
    return lv;
}

const Fibre kFibre{make_real3(-1.0, 0.3, 0.2), normalize(make_real3(0.8, 0.25, -0.3)), 2.5, 0.05};

TEST(LightVertices, TheLightRaysHitAFibreAsTheirDensitySays) {
    // the scene's bounding sphere around the fibre; 2^20 rays per light hit it 8.9-20.9 k times, a
    // relative standard error of 0.7-1.1 %: tolerance 3 % (measured: 1.1 % directional, 0.3 %
    // point and spot, 1.5 % the point light inside the sphere)
    const uint rays = 1u << 20;
    const HtLightVertices lv = sphere_of(make_real3(0.0, 0.2, 0.0), 2.0, rays);
    HtLight directional{}, point{}, spot{};
    directional.type = HT_LIGHT_DIRECTIONAL;
    const real3 travel = normalize(make_real3(0.3, -1.0, 0.45));
    directional.direction[0] = float(travel.x), directional.direction[1] = float(travel.y);
    directional.direction[2] = float(travel.z);
    point.type = HT_LIGHT_POINT;
    point.position[0] = 3.0f, point.position[1] = 4.0f, point.position[2] = -1.0f;
    spot = point;
    spot.type = HT_LIGHT_SPOT;  // the same rays: a spot's falloff is in its light, not its rays
    HtLight inside = point;      // a light inside the sphere: rays over the whole sphere of directions
    inside.position[0] = 0.5f, inside.position[1] = -0.5f, inside.position[2] = 0.3f;
    for (const HtLight& light : {directional, point, spot, inside}) {
        SCOPED_TRACE(light.type);
        uint hit = 0;
        for (uint i = 0; i < rays; ++i) {
            const HtRay r = ht_light_ray(&lv, &light, 7u, i);
            ASSERT_GT(r.tmax, r.tmin);
            hit += hits(kFibre, make_real3(r.ox, r.oy, r.oz), make_real3(r.dx, r.dy, r.dz)) ? 1u : 0u;
        }
        const double expected = integrated(kFibre, [&](real3 y) {
            return ht_light_vertex_density(&lv, &light, 0u, 1u, y, kFibre.t);
        });
        ASSERT_GT(expected, 1e-3);
        EXPECT_NEAR(double(hit) / rays / expected, 1.0, 0.03) << hit << " hits, " << expected * rays << " expected";
    }
}

TEST(LightVertices, LightsTakeTurnsAndSphereLightsStartNone) {
    HtLightVertices lv = sphere_of(make_real3(0, 0, 0), 1.0, 10);
    // 10 rays over 3 lights: 4, 3, 3
    EXPECT_DOUBLE_EQ(ht_light_vertex_share(&lv, 0u, 3u), 0.4);
    EXPECT_DOUBLE_EQ(ht_light_vertex_share(&lv, 1u, 3u), 0.3);
    EXPECT_DOUBLE_EQ(ht_light_vertex_share(&lv, 2u, 3u), 0.3);
    for (uint j = 0; j < 10; ++j) EXPECT_EQ(ht_light_vertex_light(j, 3u), j % 3u);
    HtLight sphere{};
    sphere.type = HT_LIGHT_SPHERE;
    sphere.position[1] = 3.0f, sphere.position[3] = 0.5f;
    const HtRay r = ht_light_ray(&lv, &sphere, 1u, 0u);
    EXPECT_LT(r.tmax, r.tmin) << "an empty ray: no light vertex";
    EXPECT_EQ(ht_light_vertex_density(&lv, &sphere, 0u, 1u, make_real3(0, 0, 0), make_real3(1, 0, 0)), 0.0);
}

TEST(LightVertices, AContinuationReachesAFibreAsItsDensitySays) {
    // directions uniform over the sphere (pdf 1 / 4 pi) from x: the fraction that hits the fibre
    // is p_cont integrated over it (ht_continuation_density, one continuation); 12 k hits, a
    // relative standard error of 0.9 % (measured: -0.5 %)
    const real3 x = make_real3(0.2, -0.6, 0.9);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 1 << 21;
    int hit = 0;
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - 2.0 * u(rng), phi = 2.0 * M_PI * u(rng), s = std::sqrt(1.0 - z * z);
        hit += hits(kFibre, x, make_real3(s * std::cos(phi), s * std::sin(phi), z)) ? 1 : 0;
    }
    const double expected = integrated(kFibre, [&](real3 y) {
        return ht_continuation_density(1.0, 1.0 / (4.0 * M_PI), x, y, kFibre.t);
    });
    EXPECT_NEAR(double(hit) / n / expected, 1.0, 0.03) << hit << " hits, " << expected * n << " expected";
    EXPECT_DOUBLE_EQ(ht_continuation_density(3.0, 0.5, x, x + make_real3(0, 0, 2), make_real3(1, 0, 0)),
                     3.0 * 0.5 * 1.0 / 4.0) << "N_A continuations, the pdf, the foreshortening 1, r^2 = 4";
}

TEST(LightVertices, TheBalanceWeightsSumToOne) {
    for (double a : {0.0, 1e-9, 0.3, 7.0})
        for (double b : {0.0, 1e-9, 0.3, 7.0}) {
            const double w = ht_light_vertex_mis_continuation(a, b);
            EXPECT_GE(w, 0.0);
            EXPECT_LE(w, 1.0);
            if (a + b > 0) {
                EXPECT_NEAR(w + b / (a + b), 1.0, 1e-12) << a << " " << b;
            }
        }
}

}  // namespace
