// Renders with triangle meshes: hair shadows a floor, and a Lambertian furnace (energy check).
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/features.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <cmath>

using namespace ht;

namespace {

ClContext& test_context() {
    static ClContext cl;  // one context for the whole test binary: PoCL start-up is not free
    return cl;
}

// A square floor in the plane y = height, normals up, albedo a, as two triangles.
void add_floor(Scene& s, float height, float half, Vec3f albedo) {
    SurfaceMaterialDesc m;
    m.name = "floor";
    m.albedo = albedo;
    s.surface_materials.push_back(m);
    Mesh floor;
    floor.positions = {{-half, height, -half}, {half, height, -half}, {half, height, half}, {-half, height, half}};
    floor.indices = {0, 2, 1, 0, 3, 2};
    floor.normals.assign(4, Vec3f{0, 1, 0});
    floor.material = uint32_t(s.surface_materials.size() - 1);
    s.meshes.push_back(floor);
}

double luminance(const Film& f, int x, int y) {
    const size_t i = size_t(y) * f.width + x;
    return (f.mean(i, 0) + f.mean(i, 1) + f.mean(i, 2)) / 3.0;
}

// Mean over a (2r+1)^2 block of pixels.
double block(const Film& f, int cx, int cy, int r) {
    double s = 0;
    for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) s += luminance(f, x, y);
    return s / double((2 * r + 1) * (2 * r + 1));
}

}  // namespace

// builtin:strand spans x in [-18, 19], y in [-50, 50], z in [-6, 6].  A directional light
// travelling along (1, -1, 0) throws its shadow onto the floor y = -52 at x + (y + 52): x from
// ~0 to ~120, z in [-6, 6], most of it beside the hair.  The camera looks straight down on
// x = 40, so world x runs along the image's columns and z along its rows (sign irrelevant: the
// test compares the shadow band z = 0 with z = +-80, which are symmetric).
TEST(RenderMesh, HairShadowsTheFloor) {
    Scene scene = load_scene("builtin:strand?hairs=1500&segments=20");
    add_floor(scene, -52.0f, 400.0f, {0.7f, 0.7f, 0.7f});
    scene.lights.clear();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = {1, -1, 0};
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    scene.has_camera = true;
    scene.camera.eye = {40, 300, 0};
    scene.camera.target = {40, -52, 0};
    scene.camera.up = {0, 0, -1};
    scene.camera.yfov_deg = 40.0f;
    EXPECT_TRUE(scene_features(scene)[Feature::MESHES]);

    RenderSettings rs;
    rs.width = rs.height = 64;
    rs.spp = 4;
    rs.max_depth = 2;
    Renderer r(test_context(), scene, rs);
    Film film;
    const RenderStats st = r.render(film);
    EXPECT_NE(st.kernel_options.find("HT_FEATURE_MESHES=1"), std::string::npos);
    EXPECT_EQ(st.nonfinite_caught, 0u);
    for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(film.mean(i, c)));

    // The floor's half-width in view at y = -52 is 352 tan(20 deg) = 128 world units over 32
    // pixels: 4 units per pixel.  Shadow centre x = 70 -> column 32 + 30/4 ~ 39; z = 0 -> row 32;
    // z = +-80 -> rows 12 and 52.
    const double shadow = block(film, 40, 32, 1);
    const double lit_a = block(film, 40, 12, 1), lit_b = block(film, 40, 52, 1);
    RecordProperty("shadow", std::to_string(shadow));
    RecordProperty("lit", std::to_string(0.5 * (lit_a + lit_b)));
    // Unshadowed floor under a sun of irradiance 2 at 45 degrees: 0.7/pi * 2 cos45 ~ 0.315.
    EXPECT_NEAR(lit_a, 0.7 / M_PI * 2.0 * std::sqrt(0.5), 0.05);
    EXPECT_NEAR(lit_b, lit_a, 0.05);
    EXPECT_LT(shadow, 0.6 * lit_a) << "the strand must shadow the floor";
}

// A white floor (albedo 1, so every bounce keeps all energy) seen from above under a uniform
// white environment: the floor reflects exactly the sky it sees, so every pixel converges to
// the environment radiance (1).  Albedo 0.5: one bounce, 0.5.  Checks the Lambertian
// evaluation, cosine sampling, MIS between environment sampling and BSDF sampling and the spawn
// offsets (a self-hit would darken pixels).  The hair is far below the floor, out of sight.
TEST(RenderMesh, LambertianFurnace) {
    for (float albedo : {1.0f, 0.5f}) {
        Scene scene = load_scene("builtin:strand?hairs=10&segments=4");
        for (Vec3f& p : scene.strands.points) p[1] -= 5000.0f;
        add_floor(scene, 0.0f, 1e4f, {albedo, albedo, albedo});
        scene.lights.clear();
        scene.environment.color = {1, 1, 1};
        scene.has_camera = true;
        scene.camera.eye = {0, 100, 50};
        scene.camera.target = {0, 0, 0};
        scene.camera.yfov_deg = 30.0f;
        RenderSettings rs;
        rs.width = rs.height = 16;
        rs.spp = 64;
        rs.max_depth = 100;  // Russian roulette ends the paths
        Renderer r(test_context(), scene, rs);
        Film film;
        r.render(film);
        double sum = 0, worst = 0;
        const size_t n = size_t(rs.width) * rs.height;
        for (size_t i = 0; i < n; ++i) {
            const double v = luminance(film, int(i % rs.width), int(i / rs.width));
            ASSERT_TRUE(std::isfinite(v));
            sum += v;
            worst = std::max(worst, std::fabs(v - albedo));
        }
        const double mean = sum / double(n);
        RecordProperty(albedo == 1.0f ? "mean_albedo1" : "mean_albedo05", std::to_string(mean));
        EXPECT_NEAR(mean, albedo, 0.01 * albedo) << "albedo " << albedo;
        // per pixel: 64 paths with Russian roulette (q up to 0.95) spread by ~5 %
        EXPECT_LT(worst, 0.25 * albedo) << "albedo " << albedo;
    }
}

// Hair-only scenes compile the mesh code out (the hot path stays the capsule-only loop).
TEST(RenderMesh, MeshFeatureOnlyWithTriangles) {
    Scene scene = load_scene("builtin:strand?hairs=10&segments=4");
    EXPECT_FALSE(scene_features(scene)[Feature::MESHES]);
    EXPECT_NE(kernel_build_options(scene).find("-DHT_FEATURE_MESHES=0"), std::string::npos);
    add_floor(scene, -60.0f, 10.0f, {0.5f, 0.5f, 0.5f});
    EXPECT_NE(kernel_build_options(scene).find("-DHT_FEATURE_MESHES=1"), std::string::npos);
}

// Surfaces occlude hair: seen from under the floor, the strand above it disappears (the floor's
// underside faces away from the light and is black); without the floor the same camera sees it.
TEST(RenderMesh, FloorHidesTheHairAboveIt) {
    Scene scene = load_scene("builtin:strand?hairs=300&segments=10");
    scene.lights.clear();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = {0.2f, -1, 0.3f};  // from above: lights the hair and the floor's top side
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    scene.has_camera = true;
    scene.camera.eye = {0, -200, 1};
    scene.camera.target = {0, 0, 0};
    scene.camera.yfov_deg = 30.0f;
    RenderSettings rs;
    rs.width = rs.height = 24;
    rs.spp = 2;
    auto total = [&](const Scene& s) {
        Renderer r(test_context(), s, rs);
        Film film;
        r.render(film);
        double sum = 0;
        for (int y = 0; y < rs.height; ++y)
            for (int x = 0; x < rs.width; ++x) sum += luminance(film, x, y);
        return sum;
    };
    const double open = total(scene);
    add_floor(scene, -60.0f, 1000.0f, {0.8f, 0.8f, 0.8f});
    const double covered = total(scene);
    EXPECT_GT(open, 0.0);
    EXPECT_EQ(covered, 0.0) << "light reached the camera through the floor";
}
