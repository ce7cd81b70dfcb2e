// Renders with base colour textures on PoCL: a checker quad's quadrants come out as their
// linear albedo times the light, and hair over a textured floor renders without a NaN.
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

uint32_t rgb8(uint32_t r, uint32_t g, uint32_t b) { return r | g << 8 | b << 16; }
double srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// Four colours of the checker quadrants (top-left, top-right, bottom-left, bottom-right of the
// image = (u, v) near (0, 0), (1, 0), (0, 1), (1, 1)).
const uint32_t kQuadrant[4][3] = {{200, 50, 50}, {50, 200, 50}, {50, 50, 200}, {128, 128, 128}};

// 8 x 8 texels, each quadrant a 4 x 4 block of one colour: the bilinear filter blends only
// within half a texel (1/16 of the quad) of the block edges, so the middle of each quadrant is
// that quadrant's colour exactly.
Texture checker_texture(TextureWrap wrap) {
    Texture t;
    t.name = "checker";
    t.width = t.height = 8;
    t.wrap_s = t.wrap_t = wrap;
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            const uint32_t* c = kQuadrant[(y >= 4 ? 2 : 0) + (x >= 4 ? 1 : 0)];
            t.texels.push_back(rgb8(c[0], c[1], c[2]));
        }
    return t;
}

// A square in the plane y = height spanning [-half, half] in x and z, uv = (x, z) mapped from
// [-half, half] to [0, uv_scale], textured with texture 0 times `factor`.
void add_textured_floor(Scene& s, float height, float half, float uv_scale, Vec3f factor) {
    SurfaceMaterialDesc m;
    m.name = "checker";
    m.albedo = factor;
    m.texture = 0;
    s.surface_materials.push_back(m);
    Mesh floor;
    floor.positions = {{-half, height, -half}, {half, height, -half}, {half, height, half}, {-half, height, half}};
    floor.uvs = {{0, 0}, {uv_scale, 0}, {uv_scale, uv_scale}, {0, uv_scale}};
    floor.indices = {0, 2, 1, 0, 3, 2};
    floor.normals.assign(4, Vec3f{0, 1, 0});
    floor.material = uint32_t(s.surface_materials.size() - 1);
    s.meshes.push_back(floor);
}

double block_mean(const Film& f, int cx, int cy, int r, int c) {
    double s = 0;
    for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) s += f.mean(size_t(y) * f.width + x, c);
    return s / double((2 * r + 1) * (2 * r + 1));
}

// Standard error of block_mean from the spread of its pixels (independent estimates of one
// value): the Monte Carlo noise the tolerance has to cover.
double block_standard_error(const Film& f, int cx, int cy, int r, int c) {
    const double m = block_mean(f, cx, cy, r, c);
    const int n = (2 * r + 1) * (2 * r + 1);
    double ss = 0;
    for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) ss += std::pow(f.mean(size_t(y) * f.width + x, c) - m, 2);
    return std::sqrt(ss / (n - 1) / n);
}

}  // namespace

// The quad lies in y = 0 under a uniform white sky of radiance 1 and faces it: a Lambertian
// surface then reflects radiance = albedo exactly (the sky it sees is the whole hemisphere),
// here albedo = factor x decode(texel).  Depth 2 so that the BSDF-sampled half of the MIS
// estimate (rays that leave the quad and find the sky) is counted; nothing else is in the scene
// to hit (the hair is far below).  The camera looks straight down with -z up in the image, so
// image column ~ u and image row ~ v: the picture is the texture.
//
// Tolerance: each quadrant's mean is over 5 x 5 pixels x 64 samples = 1,600 paths.  The
// standard error estimated from the pixels' spread is at most 0.67 % of the value (seed 1, the
// darkest channels; recorded as a test property) and the worst error 1.04 %: 3 % relative is
// more than 4 standard errors, while a missing sRGB decode (+36 % at 200/255), a flipped v or
// a dropped factor (-20 % in green) are far outside it.
TEST(RenderTexture, CheckerQuadrantsAreLinearAlbedoTimesLight) {
    Scene scene = load_scene("builtin:strand?hairs=10&segments=4");
    for (Vec3f& p : scene.strands.points) p[1] -= 5000.0f;
    scene.textures.push_back(checker_texture(TextureWrap::ClampToEdge));
    const Vec3f factor{1.0f, 0.8f, 1.0f};
    add_textured_floor(scene, 0.0f, 1.0f, 1.0f, factor);
    scene.lights.clear();
    scene.environment.color = {1, 1, 1};
    scene.has_camera = true;
    scene.camera.eye = {0, 3, 0};
    scene.camera.target = {0, 0, 0};
    scene.camera.up = {0, 0, -1};
    scene.camera.yfov_deg = 30.0f;  // sees x, z in [-0.80, 0.80]
    ASSERT_TRUE(scene_features(scene)[Feature::TEXTURES]);

    RenderSettings rs;
    rs.width = rs.height = 32;
    rs.spp = 64;
    rs.max_depth = 2;
    Renderer r(test_context(), scene, rs);
    Film film;
    const RenderStats st = r.render(film);
    EXPECT_NE(st.kernel_options.find("HT_FEATURE_TEXTURES=1"), std::string::npos);
    EXPECT_EQ(st.nonfinite_caught, 0u);

    // Quadrant centres x, z = -+0.5 -> pixel (0.8 -+ 0.5) / 1.6 * 32 = 5.9 and 26.1.
    const int centre[2] = {6, 26};
    double worst = 0, worst_se = 0;
    for (int q = 0; q < 4; ++q) {
        const int px = centre[q & 1], py = centre[q >> 1];
        for (int c = 0; c < 3; ++c) {
            const double expected = factor[c] * srgb_decode(kQuadrant[q][c] / 255.0);
            const double got = block_mean(film, px, py, 2, c);
            worst = std::max(worst, std::fabs(got - expected) / expected);
            worst_se = std::max(worst_se, block_standard_error(film, px, py, 2, c) / expected);
            EXPECT_NEAR(got, expected, 0.03 * expected) << "quadrant " << q << " channel " << c;
        }
    }
    RecordProperty("worst_relative_error", std::to_string(worst));
    RecordProperty("worst_relative_standard_error", std::to_string(worst_se));
}

// Hair standing on a repeating checker floor (coordinates far outside [0, 1]) under a sun and
// with bounces: every pixel finite, nothing caught as non-finite, and the floor beside the hair
// shows both checker colours.
TEST(RenderTexture, HairOnATexturedFloorRenders) {
    Scene scene = load_scene("builtin:strand?hairs=300&segments=10");
    scene.textures.push_back(checker_texture(TextureWrap::MirroredRepeat));
    add_textured_floor(scene, -52.0f, 200.0f, 40.0f, {1, 1, 1});
    scene.lights.clear();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = {0.3f, -1, 0.2f};
    sun.intensity = 2.0f;
    scene.lights.push_back(sun);
    scene.has_camera = true;
    scene.camera.eye = {0, 40, 220};
    scene.camera.target = {0, -30, 0};
    scene.camera.yfov_deg = 45.0f;
    RenderSettings rs;
    rs.width = rs.height = 48;
    rs.spp = 2;
    rs.max_depth = 4;
    Renderer r(test_context(), scene, rs);
    Film film;
    const RenderStats st = r.render(film);
    EXPECT_EQ(st.nonfinite_caught, 0u);
    double lo = 1e30, hi = 0;
    for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i) {
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(film.mean(i, c))) << i;
        // the bottom rows are floor in front of the hair: blue (quadrant 2) and red (0) squares
        if (i / rs.width >= size_t(rs.height - 4)) {
            const double ratio = film.mean(i, 2) / std::max(film.mean(i, 0), 1e-6f);
            lo = std::min(lo, ratio), hi = std::max(hi, ratio);
        }
    }
    EXPECT_GT(hi / lo, 4.0) << "the floor should show differently coloured checker squares";
}

// The texture code is compiled in only when a mesh has a textured material and coordinates.
TEST(RenderTexture, FeatureOnlyWithTexturedTriangles) {
    Scene scene = load_scene("builtin:strand?hairs=10&segments=4");
    scene.textures.push_back(checker_texture(TextureWrap::Repeat));
    add_textured_floor(scene, -60.0f, 10.0f, 1.0f, {1, 1, 1});
    EXPECT_NE(kernel_build_options(scene).find("-DHT_FEATURE_TEXTURES=1"), std::string::npos);
    scene.meshes[0].uvs.clear();  // no coordinates: the factor alone, no texture code
    EXPECT_NE(kernel_build_options(scene).find("-DHT_FEATURE_TEXTURES=0"), std::string::npos);
    scene.meshes.clear();
    EXPECT_NE(kernel_build_options(scene).find("-DHT_FEATURE_TEXTURES=0"), std::string::npos);
}

// Texels are planned with the rest of the scene's device memory: under a 1 MiB --max-memory the
// small scene renders, and the same scene with a 1024 x 1024 texture (4 MiB of texels) is
// refused before anything is allocated, the message naming the scene's share.
TEST(RenderTexture, TexturesCountAgainstTheDeviceMemoryLimit) {
    Scene scene = load_scene("builtin:strand?hairs=10&segments=4");
    scene.textures.push_back(checker_texture(TextureWrap::Repeat));
    add_textured_floor(scene, -60.0f, 10.0f, 1.0f, {1, 1, 1});
    RenderSettings rs;
    rs.width = rs.height = 16;
    rs.spp = 1;
    rs.max_device_bytes = uint64_t(1) << 20;
    EXPECT_NO_THROW(Renderer(test_context(), scene, rs));
    Texture& big = scene.textures[0];
    big.width = big.height = 1024;
    big.texels.assign(size_t(1024) * 1024, rgb8(10, 20, 30));
    try {
        Renderer r(test_context(), scene, rs);
        ADD_FAILURE() << "a 4 MiB texture fitted in 1 MiB";
    } catch (const DeviceError& e) {
        EXPECT_NE(std::string(e.what()).find("scene 4.0 MiB"), std::string::npos) << e.what();
    }
}
