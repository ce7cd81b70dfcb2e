// The automatic view: up axis detection, the 3/4 side camera fitted to the hair, the view
// options, and the key/rim/fill light rig (host/scene/default_view.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

// A lock of `n` straight strands hanging from roots on a small patch: roots at +`up` * 10, tips
// at 0, spread across the two other axes (one unit apart); tips swept by `sweep` along the first
// axis after the up axis.
Scene hanging_lock(int up_axis, float up_sign, int n = 20, float sweep = 0.2f) {
    Scene s;
    s.source = "lock";
    s.materials.push_back(blond_hair_material());
    s.strands.first_point.push_back(0);
    const int a1 = (up_axis + 1) % 3, a2 = (up_axis + 2) % 3;
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k <= 10; ++k) {
            Vec3f p{0, 0, 0};
            p[up_axis] = up_sign * float(10 - k);
            p[a1] = float(i % 5) + 0.1f * sweep * float(k);
            p[a2] = float(i / 5) + 0.2f * std::sin(float(k));
            s.strands.points.push_back(p);
            s.strands.radius.push_back(0.02f);
        }
        s.strands.first_point.push_back(uint32_t(s.strands.points.size()));
        s.strands.material.push_back(0);
    }
    return s;
}

double dot3(const Vec3f& a, const Vec3f& b) { return double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2]; }
Vec3f sub3(const Vec3f& a, const Vec3f& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3f cross3(const Vec3f& a, const Vec3f& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3f unit3(const Vec3f& a) {
    const float l = float(std::sqrt(dot3(a, a)));
    return {a[0] / l, a[1] / l, a[2] / l};
}

// Every point projects inside the camera's square field of view.
void expect_all_points_in_view(const Scene& s) {
    const Camera& c = s.camera;
    const Vec3f fwd = unit3(sub3(c.target, c.eye));
    const Vec3f right = unit3(cross3(fwd, c.up)), up = cross3(right, fwd);
    const double tan_half = std::tan(c.yfov_deg * 3.14159265358979 / 360.0);
    for (const Vec3f& p : s.strands.points) {
        const Vec3f q = sub3(p, c.eye);
        const double depth = dot3(q, fwd);
        ASSERT_GT(depth, 0.0);
        EXPECT_LE(std::abs(dot3(q, right)) / depth, tan_half);
        EXPECT_LE(std::abs(dot3(q, up)) / depth, tan_half);
    }
}

TEST(SceneDefaultView, DetectsTheUpAxisFromRootsAndTips) {
    EXPECT_EQ(detect_up_axis(hanging_lock(2, 1).strands), (Vec3f{0, 0, 1}));
    EXPECT_EQ(detect_up_axis(hanging_lock(1, 1).strands), (Vec3f{0, 1, 0}));
    EXPECT_EQ(detect_up_axis(hanging_lock(0, -1).strands), (Vec3f{-1, 0, 0}));
    // Radial hair (roots on a sphere, tips outwards) states no up: the glTF convention, +y.
    EXPECT_EQ(detect_up_axis(make_builtin("ball?hairs=400&segments=4").strands), (Vec3f{0, 1, 0}));
}

TEST(SceneDefaultView, ZUpLockIsSeenFromTheSide) {
    Scene s = hanging_lock(2, 1);
    ensure_camera_and_light(s);
    ASSERT_TRUE(s.has_camera);
    EXPECT_EQ(s.camera.up, (Vec3f{0, 0, 1}));
    // 10 degrees above the horizon, from the front (-y) side turned towards +x.
    const Vec3f back = unit3(sub3(s.camera.eye, s.camera.target));
    EXPECT_NEAR(back[2], std::sin(10.0 * 3.14159265358979 / 180.0), 1e-3);
    EXPECT_LT(back[1], -0.5);
    EXPECT_GT(back[0], 0.3);
    expect_all_points_in_view(s);
    // Fitted, not merely inside: some point is near the edge of the view.
    const Camera& c = s.camera;
    const Vec3f fwd = unit3(sub3(c.target, c.eye)), right = unit3(cross3(fwd, c.up)), up = cross3(right, fwd);
    double widest = 0;
    for (const Vec3f& p : s.strands.points) {
        const Vec3f q = sub3(p, c.eye);
        widest = std::max({widest, std::abs(dot3(q, right)) / dot3(q, fwd), std::abs(dot3(q, up)) / dot3(q, fwd)});
    }
    EXPECT_GT(widest, 0.9 * std::tan(15.0 * 3.14159265358979 / 180.0));
}

TEST(SceneDefaultView, FrontIsAwayFromWhereTheTipsHang) {
    // z-up, tips swept 5 units towards +x (the first axis after z): the front is -x.
    Scene s = hanging_lock(2, 1, 20, 5.0f);
    ensure_camera_and_light(s);
    const Vec3f back = unit3(sub3(s.camera.eye, s.camera.target));
    EXPECT_LT(back[0], -0.5);
    expect_all_points_in_view(s);
}

TEST(SceneDefaultView, LightRigIsKeyRimFill) {
    Scene s = hanging_lock(1, 1);
    ensure_camera_and_light(s);
    ASSERT_EQ(s.lights.size(), 3u);
    const Vec3f back = unit3(sub3(s.camera.eye, s.camera.target));
    for (const Light& l : s.lights) EXPECT_EQ(l.type, LightType::Directional);
    // Key and fill light the camera's side of the hair, the rim comes from behind it.
    EXPECT_LT(dot3(s.lights[0].direction, back), 0.0);
    EXPECT_GT(dot3(s.lights[1].direction, back), 0.0);
    EXPECT_LT(dot3(s.lights[2].direction, back), 0.0);
    EXPECT_GT(s.lights[0].intensity, s.lights[2].intensity);
    // An environment is light enough: no rig then, and an existing light is kept alone.
    Scene lit = hanging_lock(1, 1);
    lit.environment.color = {1, 1, 1};
    ensure_camera_and_light(lit);
    EXPECT_TRUE(lit.lights.empty());
}

TEST(SceneDefaultView, ViewOptionsOverrideTheCamera) {
    Scene s = hanging_lock(2, 1);
    ViewOptions v;
    v.up_axis = Vec3f{0, 1, 0};  // wrong on purpose: the user's word wins
    ensure_camera_and_light(s, v);
    EXPECT_EQ(s.camera.up, (Vec3f{0, 1, 0}));

    Scene t = hanging_lock(2, 1);
    v = {};
    v.look_from = Vec3f{30, -40, 5};
    v.look_at = Vec3f{1, 1, 5};
    v.yfov_deg = 20.0f;
    ensure_camera_and_light(t, v);
    EXPECT_EQ(t.camera.eye, (Vec3f{30, -40, 5}));
    EXPECT_EQ(t.camera.target, (Vec3f{1, 1, 5}));
    EXPECT_FLOAT_EQ(t.camera.yfov_deg, 20.0f);

    // A scene's own camera is kept unless an option replaces a part of it.
    Scene u = make_builtin("strand?hairs=10&segments=4");
    const Camera own = u.camera;
    v = {};
    v.yfov_deg = 12.0f;
    ensure_camera_and_light(u, v);
    EXPECT_EQ(u.camera.eye, own.eye);
    EXPECT_FLOAT_EQ(u.camera.yfov_deg, 12.0f);
}

TEST(SceneDefaultView, ImpossibleCamerasAreRefused) {
    Scene s = hanging_lock(2, 1);
    ViewOptions v;
    v.look_from = Vec3f{1, 1, 1};
    v.look_at = Vec3f{1, 1, 1};
    EXPECT_TRUE(contains(scene_error_of([&] { ensure_camera_and_light(s, v); }), "same point"));
    Scene t = hanging_lock(2, 1);
    v = {};
    v.look_from = Vec3f{0, 0, 50};
    v.look_at = Vec3f{0, 0, 0};
    v.up = Vec3f{0, 0, 2};
    EXPECT_TRUE(contains(scene_error_of([&] { ensure_camera_and_light(t, v); }), "parallel"));
    // Looking down the model's own up axis without a stated up: the front becomes up.
    Scene top = hanging_lock(2, 1);
    v.up.reset();
    ensure_camera_and_light(top, v);
    EXPECT_EQ(top.camera.up, (Vec3f{0, -1, 0}));
}

}  // namespace
}  // namespace ht
