// render/pixel_footprint.h: a pixel called empty must be one that no camera ray meets geometry
// in.  Checked against brute force -- every capsule and triangle intersected by the camera's own
// rays (kernels/camera.h) at jitters over the whole pixel, its corners and edges included -- on
// random strands seen from random cameras: close, far (sub-pixel fibres), partly behind the eye.
#include <gtest/gtest.h>

#include "../kernel/random_strands.h"
#include "bvh/bvh.h"
#include "kernels/camera.h"
#include "kernels/geometry/bvh_traverse.h"
#include "render/pixel_footprint.h"
#include "render/scene_upload.h"

#include <cmath>
#include <random>

namespace {

using namespace ht;

// strands with radii that differ along them: a box must grow by the larger
Strands random_strands(uint32_t seed, int count, int segments, double length, double radius) {
    return httest::random_strands(seed, count, segments, length, radius, 0.4, 1.0, 0.5);
}

// Whether the camera ray of pixel `pixel` with jitter (jx, jy) meets any primitive, by brute force.
bool ray_meets_geometry(const HtCamera& cam, const SceneGeometry& g, uint32_t pixel, double jx, double jy) {
    const HtRay ray = ht_camera_ray(&cam, pixel % cam.width, pixel / cam.width, jx, jy);
    const real3 o = make_real3(ray.ox, ray.oy, ray.oz), d = make_real3(ray.dx, ray.dy, ray.dz);
    for (const HtSegment& s : g.segments) {
        const HtPoint& a = g.points[s.point];
        const HtPoint& b = g.points[s.point + 1];
        double t;
        if (s.flags & HT_SEG_TRIANGLE) {
            real b1, b2;
            t = ht_triangle_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_point_pos(g.points[s.point + 2]), 0.0,
                                      1e30, &b1, &b2);
        } else {
            t = ht_capsule_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_hit_radius(a, b), 1u, 0.0, 1e30);
        }
        if (t < 1e30) return true;
    }
    return false;
}

// Every empty pixel is checked with a 6 x 6 grid of jitters from 0 to 0.99999 and 8 random ones.
void expect_conservative(const HtCamera& cam, const SceneGeometry& g, const char* what, size_t* empty_out = nullptr) {
    const PixelFootprint f = pixel_footprint(cam, g);
    ASSERT_EQ(f.seen.size() + f.empty.size(), size_t(cam.width) * cam.height) << what;
    std::vector<uint8_t> mark(size_t(cam.width) * cam.height, 0);
    for (const auto* list : {&f.seen, &f.empty})
        for (size_t i = 0; i < list->size(); ++i) {
            ASSERT_TRUE(i == 0 || (*list)[i] > (*list)[i - 1]) << what << ": ascending";
            ASSERT_EQ(mark[(*list)[i]]++, 0) << what << ": each pixel once";
        }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (uint32_t pixel : f.empty) {
        for (int a = 0; a < 6; ++a)
            for (int b = 0; b < 6; ++b)
                ASSERT_FALSE(ray_meets_geometry(cam, g, pixel, a * 0.99999 / 5, b * 0.99999 / 5))
                    << what << ": pixel " << pixel << " called empty";
        for (int k = 0; k < 8; ++k)
            ASSERT_FALSE(ray_meets_geometry(cam, g, pixel, u(rng), u(rng))) << what << ": pixel " << pixel;
    }
    if (empty_out) *empty_out = f.empty.size();
}

HtCamera camera(double eye_x, double eye_y, double eye_z, double fov, int w, int h) {
    Camera c;
    c.eye = {float(eye_x), float(eye_y), float(eye_z)};
    c.target = {0, 0, 0};
    c.yfov_deg = float(fov);
    return make_kernel_camera(c, w, h);
}

}  // namespace

TEST(PixelFootprint, EmptyPixelsMeetNoGeometryUnderBruteForce) {
    const SceneGeometry g = build_geometry(random_strands(3, 30, 6, 0.15, 0.01));
    size_t empty = 0;
    expect_conservative(camera(0, 0, 4, 40, 48, 32), g, "framing", &empty);
    EXPECT_GT(empty, 100u) << "thin strands leave most pixels empty";
    expect_conservative(camera(0.3, 2.5, 1.5, 70, 40, 40), g, "close and wide");
    size_t far_empty = 0;
    expect_conservative(camera(30, 5, 40, 20, 40, 30), g, "far: fibres below a pixel wide", &far_empty);
    EXPECT_GT(far_empty, 100u);
    // the eye among the strands: a box that reaches the eye's plane makes every pixel seen
    size_t inside_empty = 1;
    expect_conservative(camera(0.1, 0.05, 0.2, 60, 24, 24), g, "eye inside", &inside_empty);
    EXPECT_EQ(inside_empty, 0u);
}

TEST(PixelFootprint, StrandsBehindTheEyeAndTriangles) {
    Strands s = random_strands(5, 12, 4, 0.2, 0.02);
    for (auto& p : s.points) p[2] += 20.0f;  // all behind a camera at z = 10 looking at -z
    Mesh floor;
    floor.positions = {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}};
    floor.indices = {0, 1, 2, 0, 2, 3};
    const SceneGeometry g = build_geometry(s, {floor}, {SurfaceMaterialDesc{}});
    size_t empty = 0;
    const HtCamera cam = camera(0, 0, 10, 30, 32, 32);
    expect_conservative(cam, g, "floor in front, strands behind", &empty);
    const SceneGeometry behind = build_geometry(s);
    EXPECT_EQ(pixel_footprint(cam, behind).seen.size(), 0u) << "nothing in front of the eye";
    EXPECT_GT(empty, 0u);
    EXPECT_LT(empty, size_t(32 * 32)) << "the floor is in view";
}

TEST(PixelFootprint, DegenerateCameraAndNonFiniteGeometrySeeEverything) {
    const SceneGeometry g = build_geometry(random_strands(9, 4, 3, 0.1, 0.01));
    HtCamera flat = camera(0, 0, 5, 30, 16, 16);
    for (int i = 0; i < 3; ++i) flat.up[i] = flat.right[i];  // a frame without an inverse
    EXPECT_EQ(pixel_footprint(flat, g).empty.size(), 0u);
    SceneGeometry bad = g;
    bad.points[0].x = NAN;
    EXPECT_EQ(pixel_footprint(camera(0, 0, 5, 30, 16, 16), bad).empty.size(), 0u);
}
