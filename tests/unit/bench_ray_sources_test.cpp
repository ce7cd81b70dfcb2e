// bench/ray_sources.h: what bench infers from a ray file so that the render's own lists can answer
// it -- the lights shadow rays run to, and the camera rays from one point come from.  The lists'
// answers themselves are checked ray by ray against the tree by bench (exit 1 on a mismatch; run by
// GeometryPaging.BenchHitsAreTheSameWhenPaged); here: that the right lights and camera are found,
// and none where the rays have none.
#include <gtest/gtest.h>

#include "bench/ray_sources.h"
#include "kernels/camera.h"
#include "render/shadow_lists.h"

#include <cmath>
#include <random>

namespace {

using namespace ht;

HtRay ray(const double o[3], const double d[3], double tmax) {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return HtRay{float(o[0]), float(o[1]), float(o[2]), 0.0f, float(d[0] / n), float(d[1] / n), float(d[2] / n), float(tmax)};
}

}  // namespace

// Rays along two exact directions (a render's directional lights), rays to one point light, and
// random rays among them: two directional lights (the more shared first, directions negated as the
// lights' own) and the point light, where it is; random rays alone give none.
TEST(BenchRaySources, LightsTheShadowRaysRunTo) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    const double sun[2][3] = {{0.3, 0.9, -0.2}, {-0.7, 0.5, 0.4}};
    const double lamp[3] = {4.0, 7.5, -2.25};
    std::vector<HtRay> rays, random_only;
    for (int i = 0; i < 3000; ++i) {
        const double o[3] = {u(rng), u(rng), u(rng)};
        const double d[3] = {u(rng), u(rng), u(rng) + 0.01};
        const int kind = i % 6;  // 2 of 6 along the first sun, 1 along the second, 2 to the lamp, 1 random
        if (kind < 2) rays.push_back(ray(o, sun[0], 1e30));
        else if (kind == 2) rays.push_back(ray(o, sun[1], 1e30));
        else if (kind < 5) {
            const double to[3] = {lamp[0] - o[0], lamp[1] - o[1], lamp[2] - o[2]};
            rays.push_back(ray(o, to, std::sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]) * 0.999));
        } else {
            rays.push_back(ray(o, d, 5.0));
            random_only.push_back(rays.back());
        }
    }
    const std::vector<HtLight> lights = lights_the_rays_run_to(rays);
    ASSERT_EQ(lights.size(), 3u);
    for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(lights[size_t(k)].type, HT_LIGHT_DIRECTIONAL) << k;
        const HtRay along = ray(lamp, sun[k], 1);
        EXPECT_EQ(lights[size_t(k)].direction[0], -along.dx) << k;
        EXPECT_EQ(lights[size_t(k)].direction[1], -along.dy) << k;
        EXPECT_EQ(lights[size_t(k)].direction[2], -along.dz) << k;
    }
    EXPECT_EQ(lights[2].type, HT_LIGHT_POINT);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(lights[2].position[i], lamp[i], 1e-4) << i;  // where the lines meet, though the rays stop short
    EXPECT_TRUE(lights_the_rays_run_to(random_only).empty());
    EXPECT_TRUE(lights_the_rays_run_to({}).empty());
}

// Pixel-centre rays of a rolled camera (kernels/camera.h): one point, so a camera is fitted whose
// square image holds every ray, each given the pixel its direction falls in; rays from two points,
// or too few, or spread too wide, get none.
TEST(BenchRaySources, CameraOfRaysFromOnePoint) {
    HtCamera cam{};
    const float eye[3] = {1.0f, 2.0f, 9.0f}, roll = 0.6f;
    const float f[3] = {0.1f, -0.2f, -0.97f};
    for (int i = 0; i < 3; ++i) cam.eye[i] = eye[i];
    const double fn = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; ++i) cam.forward[i] = float(f[i] / fn);
    // right and up across the axis, rolled, scaled for a 40-degree vertical field at 4:3
    const double r0[3] = {1, 0, 0.1}, t = std::tan(0.349);
    double up0[3] = {r0[1] * cam.forward[2] - r0[2] * cam.forward[1], r0[2] * cam.forward[0] - r0[0] * cam.forward[2],
                     r0[0] * cam.forward[1] - r0[1] * cam.forward[0]};
    double un = std::sqrt(up0[0] * up0[0] + up0[1] * up0[1] + up0[2] * up0[2]);
    for (double& x : up0) x /= un;
    const double right0[3] = {up0[1] * cam.forward[2] - up0[2] * cam.forward[1], up0[2] * cam.forward[0] - up0[0] * cam.forward[2],
                              up0[0] * cam.forward[1] - up0[1] * cam.forward[0]};
    for (int i = 0; i < 3; ++i) {
        cam.right[i] = float((std::cos(roll) * right0[i] + std::sin(roll) * up0[i]) * t * 4 / 3);
        cam.up[i] = float((-std::sin(roll) * right0[i] + std::cos(roll) * up0[i]) * t);
    }
    cam.width = 64, cam.height = 48;
    std::vector<HtRay> rays;
    for (uint32_t y = 0; y < cam.height; ++y)
        for (uint32_t x = 0; x < cam.width; ++x) rays.push_back(ht_camera_ray(&cam, x, y, 0.5, 0.5));
    const FittedCamera fc = camera_of_the_rays(rays);
    ASSERT_TRUE(fc.ok);
    ASSERT_EQ(fc.pixels.size(), rays.size());
    EXPECT_EQ(fc.camera.width, 55u);  // sqrt(3072), one pixel per ray
    EXPECT_EQ(fc.camera.height, 55u);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(fc.camera.eye[i], eye[i]);
    // every ray inside the image, in the pixel its direction falls in (not clamped to an edge)
    size_t distinct = 0;
    std::vector<int> seen(size_t(fc.camera.width) * fc.camera.height, 0);
    for (size_t k = 0; k < rays.size(); ++k) {
        const HtRay& r = rays[k];
        const double d[3] = {r.dx, r.dy, r.dz};
        double z = 0, a = 0, b = 0, rr = 0, uu = 0;
        for (int i = 0; i < 3; ++i) {
            z += d[i] * fc.camera.forward[i];
            a += d[i] * fc.camera.right[i], rr += double(fc.camera.right[i]) * fc.camera.right[i];
            b += d[i] * fc.camera.up[i], uu += double(fc.camera.up[i]) * fc.camera.up[i];
        }
        const double sx = a / rr / z, sy = b / uu / z;  // the fitted frame is orthogonal
        ASSERT_LT(std::fabs(sx), 1.0) << k;
        ASSERT_LT(std::fabs(sy), 1.0) << k;
        const uint32_t px = uint32_t((sx + 1) * 0.5 * fc.camera.width), py = uint32_t((1 - sy) * 0.5 * fc.camera.height);
        EXPECT_EQ(fc.pixels[k], py * fc.camera.width + px) << k;
        distinct += seen[fc.pixels[k]]++ == 0;
    }
    EXPECT_GT(distinct, rays.size() / 3) << "the rays spread over the image";
    std::vector<HtRay> two = rays;
    two[100].ox += 0.5f;
    EXPECT_FALSE(camera_of_the_rays(two).ok);
    EXPECT_FALSE(camera_of_the_rays(std::vector<HtRay>(rays.begin(), rays.begin() + 63)).ok);
    std::vector<HtRay> wide = rays;
    wide[7].dx = -rays[7].dx, wide[7].dy = -rays[7].dy, wide[7].dz = -rays[7].dz;  // one ray backwards
    EXPECT_FALSE(camera_of_the_rays(wide).ok);
}
