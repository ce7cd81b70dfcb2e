// glTF 2.0 loader: hierarchy transforms, cameras, KHR lights, LINES / LINE_STRIP hair, radii,
// material extras, builtin references and malformed files.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using nlohmann::json;
using test::contains;
using test::scene_error_of;

constexpr int kLines = 1, kLineStrip = 3, kTriangles = 4;
const double kS = std::sqrt(0.5);  // sin(45 deg) = cos(45 deg)

void expect_vec_near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

std::string write_gltf(const test::TempDir& dir, const test::GltfBuilder& g,
                       const std::string& name = "scene.gltf") {
    const std::string path = dir.file(name);
    test::write_text(path, g.gltf_text());
    return path;
}

TEST(SceneGltf, LineStripWithNodeHierarchyTransformAndRadius) {
    test::GltfBuilder g;
    const int pos = g.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});
    const int rad = g.add_scalar({0.1f, 0.1f, 0.05f});
    const int mesh = g.add_mesh(kLineStrip, pos, rad);
    // child: translate (10,0,0) * rotate 90 deg about +y * scale 2; parent: translate (0,5,0)
    const int child = g.add_node({{"mesh", mesh},
                                  {"translation", {10, 0, 0}},
                                  {"rotation", {0, kS, 0, kS}},
                                  {"scale", {2, 2, 2}}},
                                 false);
    g.add_node({{"translation", {0, 5, 0}}, {"children", {child}}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    ASSERT_EQ(s.strands.strand_count(), 1u);
    ASSERT_EQ(s.strands.point_count(), 3u);
    expect_vec_near(s.strands.points[0], {10, 5, 0});
    expect_vec_near(s.strands.points[1], {10, 5, -2});  // x axis -> -z, scaled by 2
    expect_vec_near(s.strands.points[2], {10, 7, -2});
    EXPECT_NEAR(s.strands.radius[0], 0.2f, 1e-6f);  // _RADIUS times the uniform scale
    EXPECT_NEAR(s.strands.radius[2], 0.1f, 1e-6f);
    EXPECT_FALSE(s.has_camera);
    EXPECT_TRUE(s.lights.empty());
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "blond");
}

TEST(SceneGltf, MatrixTransformAndGlb) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}));
    // Column-major: scale 3 and translation (1, 2, 3).
    g.add_node({{"mesh", mesh}, {"matrix", {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 1, 2, 3, 1}}});
    test::TempDir dir;
    const std::string path = dir.file("m.glb");
    test::write_file(path, g.glb_bytes());
    const Scene s = load_scene(path);
    expect_vec_near(s.strands.points[1], {1, 5, 3});
    EXPECT_NEAR(s.strands.radius[1], 3.0f, 1e-5f);
}

TEST(SceneGltf, LinesAreChainedIntoStrands) {
    test::GltfBuilder g;
    const int pos = g.add_vec3({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {5, 0, 0}, {5, 1, 0}, {5, 2, 0}});
    // Indexed: (0,1)(1,2) is one strand, (3,4)(4,5) another.
    const int indexed = g.add_mesh(kLines, pos, g.add_scalar({1, 1, 1, 1, 1, 1}),
                                   g.add_indices({0, 1, 1, 2, 3, 4, 4, 5}));
    // Unindexed with repeated positions: chained by equal positions; the last segment starts
    // elsewhere and begins a new strand.
    const int loose = g.add_mesh(kLines,
                                 g.add_vec3({{0, 0, 9}, {0, 1, 9}, {0, 1, 9}, {0, 2, 9}, {0, 2, 9},
                                             {0, 3, 9}, {4, 0, 9}, {4, 1, 9}}),
                                 g.add_scalar({1, 1, 1, 1, 1, 1, 1, 1}));
    g.add_node({{"mesh", indexed}});
    g.add_node({{"mesh", loose}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    ASSERT_EQ(s.strands.strand_count(), 4u);
    EXPECT_EQ(s.strands.first_point, (std::vector<uint32_t>{0, 3, 6, 10, 12}));
    expect_vec_near(s.strands.points[5], {5, 2, 0});
    expect_vec_near(s.strands.points[9], {0, 3, 9});
    EXPECT_EQ(s.strands.segment_count(), 8u);
}

TEST(SceneGltf, CameraAndLights) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}));
    g.add_node({{"mesh", mesh}});
    g.doc["cameras"] = {{{"type", "perspective"},
                         {"perspective", {{"yfov", 0.5}, {"aspectRatio", 1.5}, {"znear", 0.1}}}},
                        {{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.1}}}}};
    // Camera at (0,0,10) rotated 90 deg about +y: looks along -x.
    g.add_node({{"camera", 0}, {"translation", {0, 0, 10}}, {"rotation", {0, kS, 0, kS}}});
    g.add_node({{"camera", 1}});  // a second camera: ignored with a warning
    g.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 100}},
        {{"type", "spot"}, {"intensity", 5}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
        {{"type", "directional"}}};
    g.add_node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    // Spot rotated -90 deg about x: -z turns into -y (points down).
    g.add_node({{"translation", {0, 8, 0}}, {"rotation", {-kS, 0, 0, kS}},
                {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    g.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    test::TempDir dir;
    const std::string path = write_gltf(dir, g);
    const Scene s = load_scene(path);

    // --camera N picks another camera; one the file does not have is refused.
    LoadOptions second;
    second.camera_index = 1;
    const Scene c = load_scene(path, second);
    EXPECT_NEAR(c.camera.yfov_deg, 0.9 * 57.29578, 1e-3);
    expect_vec_near(c.camera.eye, {0, 0, 0});
    second.camera_index = 2;
    EXPECT_TRUE(test::contains(scene_error_of([&] { load_scene(path, second); }), "the file has 2 cameras"));

    ASSERT_TRUE(s.has_camera);
    expect_vec_near(s.camera.eye, {0, 0, 10});
    expect_vec_near(s.camera.target, {-1, 0, 10});
    expect_vec_near(s.camera.up, {0, 1, 0});
    EXPECT_NEAR(s.camera.yfov_deg, 0.5 * 57.29578, 1e-3);
    EXPECT_TRUE(s.camera.has_aspect);
    EXPECT_FLOAT_EQ(s.camera.aspect, 1.5f);
    EXPECT_TRUE(test::any_warning_contains(s, "ignored 1 cameras"));

    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    expect_vec_near(s.lights[0].position, {1, 2, 3});
    expect_vec_near(s.lights[0].color, {1, 0.5f, 0.25f});
    EXPECT_FLOAT_EQ(s.lights[0].intensity, 100.0f);
    EXPECT_EQ(s.lights[1].type, LightType::Spot);
    expect_vec_near(s.lights[1].position, {0, 8, 0});
    expect_vec_near(s.lights[1].direction, {0, -1, 0});
    EXPECT_NEAR(s.lights[1].inner_cone_deg, 0.2 * 57.29578, 1e-3);
    EXPECT_NEAR(s.lights[1].outer_cone_deg, 0.4 * 57.29578, 1e-3);
    EXPECT_EQ(s.lights[2].type, LightType::Directional);
    expect_vec_near(s.lights[2].direction, {0, 0, -1});
    EXPECT_FLOAT_EQ(s.lights[2].intensity, 1.0f);
}

TEST(SceneGltf, MaterialExtrasAndDefaultRadius) {
    test::GltfBuilder g;
    g.doc["materials"] = {
        {{"name", "red"},
         {"extras", {{"model", "zinke"}, {"sigma_a", {0.3, 0.4, 0.5}}, {"eta", 1.6},
                     {"beta_r_deg", 6}, {"radius", 0.05}, {"eumelanin", 1.5}, {"sigmaa", 1}}}},
        {{"name", "plain"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.3, 0.1, 1}}}}}};
    const int pos = g.add_vec3({{0, 0, 0}, {0, 10, 0}});
    g.add_node({{"mesh", g.add_mesh(kLineStrip, pos, -1, -1, 0)}, {"scale", {2, 2, 2}}});
    g.add_node({{"mesh", g.add_mesh(kLineStrip, g.add_vec3({{1, 0, 0}, {1, 10, 0}}), -1, -1, 1)}});
    test::TempDir dir;
    const std::string path = write_gltf(dir, g);
    const Scene s = load_scene(path);
    ASSERT_EQ(s.materials.size(), 2u);
    const HairMaterialDesc& m = s.materials[0];
    EXPECT_EQ(m.name, "red");
    EXPECT_EQ(m.model, "zinke");
    EXPECT_TRUE(m.has_sigma_a);
    expect_vec_near(m.sigma_a, {0.3f, 0.4f, 0.5f});
    EXPECT_FLOAT_EQ(m.eta, 1.6f);
    EXPECT_FLOAT_EQ(m.beta_r_deg, 6.0f);
    EXPECT_TRUE(m.has_melanin);
    EXPECT_FLOAT_EQ(m.eumelanin, 1.5f);
    EXPECT_TRUE(s.materials[1].has_color);  // from baseColorFactor
    expect_vec_near(s.materials[1].color, {0.5f, 0.3f, 0.1f});
    EXPECT_EQ(s.strands.material, (std::vector<uint32_t>{0, 1}));
    EXPECT_NEAR(s.strands.radius[0], 0.1f, 1e-6f);  // extras.radius 0.05 x node scale 2
    // The second primitive has no radius anywhere: 1/1000 of the hair extent (20).
    EXPECT_NEAR(s.strands.radius[2], 0.02f, 1e-6f);
    EXPECT_TRUE(test::any_warning_contains(s, "no _RADIUS"));
    EXPECT_TRUE(test::any_warning_contains(s, "unknown material extras keys: sigmaa"));

    LoadOptions opt;
    opt.default_radius = 0.3f;
    EXPECT_FLOAT_EQ(load_gltf(path, opt).strands.radius[3], 0.3f);

    g.doc["materials"][0]["extras"]["eta"] = "high";
    std::string msg = scene_error_of([&] { load_scene(write_gltf(dir, g)); });
    EXPECT_TRUE(contains(msg, "extras.eta must be a number")) << msg;
    g.doc["materials"][0]["extras"]["eta"] = 1.5;
    g.doc["materials"][0]["extras"]["model"] = "phong";
    msg = scene_error_of([&] { load_scene(write_gltf(dir, g)); });
    EXPECT_TRUE(contains(msg, "unknown hair model \"phong\"")) << msg;
}

TEST(SceneGltf, TrianglesWithoutHairAreRefused) {
    test::GltfBuilder g;
    const int tri = g.add_mesh(kTriangles, g.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    g.add_node({{"mesh", tri}});
    test::TempDir dir;
    const std::string msg = scene_error_of([&] { load_scene(write_gltf(dir, g)); });
    EXPECT_TRUE(contains(msg, "no hair")) << msg;
    EXPECT_TRUE(contains(msg, "1 triangle primitives")) << msg;
}

// A floor quad (indexed, with normals and a material) under a strand, behind a node transform.
TEST(SceneGltf, TriangleFloorUnderAStrandLoads) {
    test::GltfBuilder g;
    g.doc["materials"] = json::array(
        {{{"name", "floor"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}}}}});
    const int pos = g.add_vec3({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}});
    const int idx = g.add_indices({0, 2, 1, 0, 3, 2, 0, 0, 1});  // the last one is degenerate
    const int floor = g.add_mesh(kTriangles, pos, -1, idx, 0);
    g.doc["meshes"][floor]["primitives"][0]["attributes"]["NORMAL"] =
        g.add_vec3({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}});
    // Non-uniform scale and a lift: positions scale, normals stay unit and up.
    g.add_node({{"mesh", floor}, {"scale", {3, 1, 2}}, {"translation", {0, -2, 0}}});
    // An unindexed triangle without a material.
    g.add_node({{"mesh", g.add_mesh(kTriangles, g.add_vec3({{0, 0, 5}, {1, 0, 5}, {0, 1, 5}}))}});
    g.add_node({{"mesh", g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}))}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    EXPECT_EQ(s.strands.strand_count(), 1u);
    ASSERT_EQ(s.meshes.size(), 2u);
    const ht::Mesh& m = s.meshes[0];
    EXPECT_EQ(m.triangle_count(), 2u);
    ASSERT_EQ(m.positions.size(), 4u);
    expect_vec_near(m.positions[2], {3, -2, 2});
    ASSERT_EQ(m.normals.size(), 4u);
    expect_vec_near(m.normals[1], {0, 1, 0});
    ASSERT_EQ(s.surface_materials.size(), 2u);
    EXPECT_EQ(s.surface_materials[m.material].name, "floor");
    expect_vec_near(s.surface_materials[m.material].albedo, {0.5f, 0.25f, 1.0f});
    EXPECT_EQ(s.meshes[1].triangle_count(), 1u);
    EXPECT_TRUE(s.meshes[1].normals.empty());
    expect_vec_near(s.surface_materials[s.meshes[1].material].albedo, {0.8f, 0.8f, 0.8f});
    EXPECT_TRUE(test::any_warning_contains(s, "dropped 1 degenerate"));
}

TEST(SceneGltf, RotatedNormalsUseTheInverseTranspose) {
    test::GltfBuilder g;
    const int tri = g.add_mesh(kTriangles, g.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
    g.doc["meshes"][tri]["primitives"][0]["attributes"]["NORMAL"] =
        g.add_vec3({{1, 1, 0}, {0, 0, 1}, {0, 0, 1}});
    // Scale x by 4: a 45-degree normal (1,1,0) leans towards y, (1/4, 1, 0) normalized.
    g.add_node({{"mesh", tri}, {"scale", {4, 1, 1}}});
    g.add_node({{"mesh", g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}))}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    ASSERT_EQ(s.meshes.size(), 1u);
    const float l = std::sqrt(1.0f / 16.0f + 1.0f);
    expect_vec_near(s.meshes[0].normals[0], {0.25f / l, 1.0f / l, 0.0f});
}

TEST(SceneGltf, BadTrianglesAreRefused) {
    test::TempDir dir;
    auto with_hair = [](test::GltfBuilder& g) {
        g.add_node({{"mesh", g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}))}});
    };
    {
        test::GltfBuilder g;
        const float nan = std::nanf("");
        g.add_node({{"mesh", g.add_mesh(kTriangles, g.add_vec3({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}))}});
        with_hair(g);
        const std::string path = write_gltf(dir, g, "nan.gltf");
        const std::string msg = scene_error_of([&] { load_scene(path); });
        test::expect_one_line_naming(msg, path);
        EXPECT_TRUE(contains(msg, "not finite")) << msg;
    }
    {
        test::GltfBuilder g;
        const int pos = g.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        g.add_node({{"mesh", g.add_mesh(kTriangles, pos, -1, g.add_indices({0, 1, 7}))}});
        with_hair(g);
        const std::string path = write_gltf(dir, g, "range.gltf");
        const std::string msg = scene_error_of([&] { load_scene(path); });
        test::expect_one_line_naming(msg, path);
    }
    {
        test::GltfBuilder g;
        const int pos = g.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
        g.add_node({{"mesh", g.add_mesh(kTriangles, pos)}});
        with_hair(g);
        const std::string path = write_gltf(dir, g, "count.gltf");
        const std::string msg = scene_error_of([&] { load_scene(path); });
        test::expect_one_line_naming(msg, path);
        EXPECT_TRUE(contains(msg, "multiple of 3")) << msg;
    }
}

TEST(SceneGltf, MalformedFilesAreRefused) {
    test::TempDir dir;
    auto base = [] {
        test::GltfBuilder g;
        const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}}),
                                    g.add_scalar({1, 1, 1}));
        g.add_node({{"mesh", mesh}});
        return g;
    };
    auto error_for = [&](const test::GltfBuilder& g) {
        const std::string path = write_gltf(dir, g, "bad.gltf");
        const std::string msg = scene_error_of([&] { load_scene(path); });
        test::expect_one_line_naming(msg, path);
        return msg;
    };

    test::GltfBuilder g = base();
    g.doc["accessors"][0]["count"] = 100;  // runs past its bufferView
    EXPECT_TRUE(contains(error_for(g), "exceeds bufferView")) << error_for(g);

    g = base();
    g.doc["meshes"][0]["primitives"][0]["indices"] = g.add_indices({0, 1, 7});
    EXPECT_TRUE(contains(error_for(g), "out of range")) << error_for(g);

    g = base();
    g.doc["nodes"][0]["children"] = {0};  // cycle
    EXPECT_TRUE(contains(error_for(g), "reached twice")) << error_for(g);

    g = base();
    g.doc["meshes"][0]["primitives"][0]["mode"] = kLines;  // 3 vertices: odd
    EXPECT_TRUE(contains(error_for(g), "even number")) << error_for(g);

    g = base();
    g.doc["meshes"][0]["primitives"][0]["attributes"]["_RADIUS"] = g.add_scalar({1, -1, 1});
    EXPECT_TRUE(contains(error_for(g), "primitive 0 strand 0 point 1: radius -1")) << error_for(g);

    g = base();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
        g.add_vec3({{0, 0, 0}, {0, nan, 0}, {0, 2, 0}});
    EXPECT_TRUE(contains(error_for(g), "mesh 0 primitive 0 strand 0 point 1: non-finite")) << error_for(g);

    g = base();
    auto& attributes = g.doc["meshes"][0]["primitives"][0]["attributes"];
    attributes["POSITION"] = attributes["_RADIUS"];  // a SCALAR accessor
    EXPECT_TRUE(contains(error_for(g), "must be VEC3")) << error_for(g);

    const std::string broken = dir.file("broken.gltf");
    test::write_text(broken, "{ \"asset\": { \"version\": \"2.0\" }, \n \"nodes\": [ ");
    const std::string msg = scene_error_of([&] { load_scene(broken); });
    test::expect_one_line_naming(msg, broken);
}

TEST(SceneGltf, ZeroLengthSegmentsAreRepaired) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}, {0, 1, 0}, {0, 2, 0}}),
                                g.add_scalar({1, 1, 1, 1}));
    g.add_node({{"mesh", mesh}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    EXPECT_EQ(s.strands.point_count(), 3u);
    EXPECT_TRUE(test::any_warning_contains(s, "dropped 1 duplicate points"));
}

TEST(SceneGltf, TruncatedGlbAtEveryOffsetThrows) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}));
    g.add_node({{"mesh", mesh}});
    const test::Bytes full = g.glb_bytes();
    test::TempDir dir;
    const std::string path = dir.file("cut.glb");
    for (size_t n = 0; n < full.size(); ++n) {
        test::write_file(path, test::Bytes(full.begin(), full.begin() + n));
        test::expect_one_line_naming(scene_error_of([&] { load_scene(path); }), path);
    }
    test::write_file(path, full);
    EXPECT_EQ(load_scene(path).strands.point_count(), 2u);
}

TEST(SceneGltf, BuiltinReferenceWithGltfMaterialCameraAndLight) {
    test::GltfBuilder g;
    g.doc["scenes"][0]["extras"] = {{"hairtrace_builtin", "strand?hairs=10&segments=5"},
                                    {"hairtrace_material", "warm"}};
    g.doc["materials"] = {{{"name", "warm"}, {"extras", {{"color", {0.9, 0.7, 0.4}}}}}};
    g.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.4}, {"znear", 0.1}}}}};
    g.add_node({{"camera", 0}, {"translation", {0, 0, 300}}});
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    EXPECT_EQ(s.strands.strand_count(), 10u);
    EXPECT_EQ(s.strands.segment_count(), 50u);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "warm");
    expect_vec_near(s.camera.eye, {0, 0, 300});
    EXPECT_EQ(s.lights.size(), 1u);  // none in the file: the builtin's key light

    g.doc["scenes"][0]["extras"]["hairtrace_material"] = "missing";
    std::string msg = scene_error_of([&] { load_scene(write_gltf(dir, g)); });
    EXPECT_TRUE(contains(msg, "no material named \"missing\"")) << msg;

    g.doc["scenes"][0]["extras"]["hairtrace_builtin"] = "wig";
    const std::string path = write_gltf(dir, g);
    msg = scene_error_of([&] { load_scene(path); });
    test::expect_one_line_naming(msg, path);
    EXPECT_TRUE(contains(msg, "unknown builtin scene 'wig'")) << msg;
}

TEST(SceneGltf, ShippedScenesLoad) {
    for (const char* name : {"default.gltf", "ball.gltf", "strand_closeup.gltf", "strand_on_floor.gltf",
                             "strand_on_checker_floor.gltf",
                             "paper_fig5_strand.gltf", "paper_fig5_closeup.gltf", "paper_fig6_ball.gltf",
                             "paper_fig6_ball_half_sigma.gltf", "paper_fig7_strand.gltf"}) {
        SCOPED_TRACE(name);
        const Scene s = load_scene(std::string(HT_SOURCE_DIR "/scenes/") + name);
        EXPECT_TRUE(s.has_camera);
        EXPECT_FALSE(s.lights.empty());
        EXPECT_GT(s.strands.segment_count(), 100000u);
        EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
    }
    // The floor sits just under the strand's tips (y = -50.1).
    const Scene s = load_scene(HT_SOURCE_DIR "/scenes/strand_on_floor.gltf");
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].triangle_count(), 2u);
    EXPECT_EQ(s.meshes[0].normals.size(), 4u);
    EXPECT_FLOAT_EQ(s.meshes[0].positions[0][1], -52.0f);
    expect_vec_near(s.surface_materials.at(s.meshes[0].material).albedo, {0.6f, 0.6f, 0.6f});
    // The checker floor: an 8 x 8 REPEAT texture over uv [0, 6]^2, terracotta at texel (0, 0).
    const Scene c = load_scene(HT_SOURCE_DIR "/scenes/strand_on_checker_floor.gltf");
    ASSERT_EQ(c.textures.size(), 1u);
    EXPECT_EQ(c.textures[0].width, 8u);
    EXPECT_EQ(c.textures[0].wrap_s, TextureWrap::Repeat);
    EXPECT_EQ(c.textures[0].texels[0], 190u | 90u << 8 | 60u << 16);
    EXPECT_EQ(c.textures[0].texels[4], 230u | 220u << 8 | 200u << 16);
    ASSERT_EQ(c.meshes.at(0).uvs.size(), 4u);
    EXPECT_FLOAT_EQ(c.meshes[0].uvs[2][0], 6.0f);
    EXPECT_EQ(c.surface_materials.at(c.meshes[0].material).texture, 0);
}

}  // namespace
}  // namespace ht

namespace ht {
namespace {

// A fixture written independently of GltfBuilder (tests/data, made with Python's struct): an
// interleaved x,y,z,radius vertex buffer (byteStride 16), uint8 LINES indices, a TRS node.
TEST(SceneGltf, InterleavedFixtureFile) {
    const Scene s = load_scene(HT_SOURCE_DIR "/tests/data/interleaved_lines.gltf");
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.first_point, (std::vector<uint32_t>{0, 3, 5}));
    expect_vec_near(s.strands.points[2], {0, 11, 0});   // (0,2,0) * 0.5 + (0,10,0)
    expect_vec_near(s.strands.points[3], {1.5f, 10, 0});
    EXPECT_NEAR(s.strands.radius[2], 0.025f, 1e-6f);    // 0.05 * 0.5
    EXPECT_NEAR(s.strands.radius[4], 0.1f, 1e-6f);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].model, "chiang");
    EXPECT_TRUE(s.materials[0].has_melanin);
    EXPECT_FLOAT_EQ(s.materials[0].pheomelanin, 0.8f);
    EXPECT_FLOAT_EQ(s.materials[0].beta_m, 0.25f);
}

TEST(SceneGltf, ExternalBufferFile) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}));
    g.add_node({{"mesh", mesh}});
    test::TempDir dir;
    test::write_file(dir.file("hair.bin"), g.bin);
    nlohmann::json doc = g.doc;
    doc["buffers"] = {{{"byteLength", g.bin.size()}, {"uri", "hair.bin"}}};
    const std::string path = dir.file("ext.gltf");
    test::write_text(path, doc.dump());
    EXPECT_EQ(load_scene(path).strands.point_count(), 2u);

    std::filesystem::remove(dir.file("hair.bin"));
    test::expect_one_line_naming(scene_error_of([&] { load_scene(path); }), path);
}

}  // namespace
}  // namespace ht

namespace ht {
namespace {

TEST(SceneGltf, WithoutScenesEveryParentlessNodeIsARoot) {
    test::GltfBuilder g;
    const int mesh = g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}));
    const int child = g.add_node({{"mesh", mesh}, {"translation", {0, 0, 1}}}, false);
    g.add_node({{"mesh", mesh}, {"children", {child}}}, false);
    g.doc.erase("scenes");
    g.doc.erase("scene");
    test::TempDir dir;
    const Scene s = load_scene(write_gltf(dir, g));
    // Node 1 is the only root; node 0 is reached once, through it (depth first, parent first).
    ASSERT_EQ(s.strands.strand_count(), 2u);
    expect_vec_near(s.strands.points[0], {0, 0, 0});
    expect_vec_near(s.strands.points[2], {0, 0, 1});
}

}  // namespace
}  // namespace ht
