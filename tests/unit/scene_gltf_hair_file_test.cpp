// glTF nodes that reference an external hair file (extras.hairtrace_hair, host/scene/gltf.cpp;
// schema in scenes/README.md): the file's strands in the node's world transform, the glTF
// material, and clear errors for missing files and malformed entries.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using nlohmann::json;
using test::contains;
using test::scene_error_of;

const double kS = std::sqrt(0.5);  // sin(45 deg) = cos(45 deg)

// A folder with hair/three.data and a glTF (in the folder's root) whose node 0 has `extras`.
struct HairFileScene {
    test::TempDir dir;
    std::string data, gltf;
    explicit HairFileScene(const json& hair_extras, json node = json::object()) {
        std::filesystem::create_directories(dir.file("hair"));
        data = dir.file("hair/three.data");
        test::write_file(data, test::make_usc_bytes(test::three_strands()));
        test::GltfBuilder g;
        g.doc["materials"] = {{{"name", "golden"}, {"extras", {{"eumelanin", 0.3}}}},
                              {{"name", "dark"}, {"extras", {{"eumelanin", 8.0}}}}};
        node["extras"] = {{"hairtrace_hair", hair_extras}};
        g.add_node(node);
        gltf = dir.file("scene.gltf");
        test::write_text(gltf, g.gltf_text());
    }
};

TEST(SceneGltfHairFile, LoadsTheFileInTheNodesTransformWithTheGltfMaterial) {
    // translate (10, 0, 0) * rotate 90 deg about +y * scale 2: (x, y, z) -> (10 + 2z, 2y, -2x)
    HairFileScene f({{"uri", "hair/three.data"}, {"material", "dark"}},
                    {{"translation", {10, 0, 0}}, {"rotation", {0, kS, 0, kS}}, {"scale", {2, 2, 2}}});
    const Scene plain = load_scene(f.data);
    const Scene s = load_scene(f.gltf);
    ASSERT_EQ(s.strands.strand_count(), plain.strands.strand_count());
    ASSERT_EQ(s.strands.point_count(), plain.strands.point_count());
    EXPECT_EQ(s.strands.first_point, plain.strands.first_point);
    for (size_t i = 0; i < s.strands.points.size(); ++i) {
        const Vec3f& p = plain.strands.points[i];
        const Vec3f want{10 + 2 * p[2], 2 * p[1], -2 * p[0]};
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.strands.points[i][c], want[c], 1e-5f) << i;
        EXPECT_NEAR(s.strands.radius[i], 2 * plain.strands.radius[i], 1e-6f) << i;
    }
    ASSERT_EQ(s.strands.material.size(), plain.strands.strand_count());
    for (uint32_t m : s.strands.material) EXPECT_EQ(s.materials.at(m).name, "dark");
    EXPECT_FLOAT_EQ(s.materials.at(s.strands.material[0]).eumelanin, 8.0f);
}

TEST(SceneGltfHairFile, WithoutAMaterialTheFileKeepsItsOwn) {
    HairFileScene f(json{{"uri", "hair/three.data"}});
    const Scene plain = load_scene(f.data);
    const Scene s = load_scene(f.gltf);
    ASSERT_EQ(s.strands.strand_count(), plain.strands.strand_count());
    EXPECT_EQ(s.materials.at(s.strands.material[0]).name, plain.materials.at(0).name);
    EXPECT_EQ(s.strands.points, plain.strands.points);  // identity transform: the same floats
}

TEST(SceneGltfHairFile, MistakesAreSceneErrorsNamingTheNodeAndTheProblem) {
    const std::pair<json, const char*> cases[] = {
        {json("hair/three.data"), "must be an object"},
        {{{"material", 0}}, "\"uri\" must name a hair file"},
        {{{"uri", ""}}, "\"uri\" must name a hair file"},
        {{{"uri", 3}}, "\"uri\" must name a hair file"},
        {{{"uri", "hair/three.data"}, {"scale", 2}}, "unknown key \"scale\""},
        {{{"uri", "hair/missing.hair"}}, "missing.hair"},
        {{{"uri", "scene.gltf"}}, "is not a hair file"},
        {{{"uri", "hair/three.data"}, {"material", 5}}, "material 5 does not exist"},
        {{{"uri", "hair/three.data"}, {"material", "blond"}}, "no material named \"blond\""},
    };
    for (const auto& [extras, message] : cases) {
        HairFileScene f(extras);
        const std::string err = scene_error_of([&] { load_scene(f.gltf); });
        EXPECT_TRUE(contains(err, "node 0 extras.hairtrace_hair")) << err;
        EXPECT_TRUE(contains(err, message)) << extras.dump() << ": " << err;
    }
}

// The shipped example: straight.hair (../shared/data) turned y-up by the node's -90 deg rotation
// about x, (x, y, z) -> (x, z, -y), on a floor just under its tips.
TEST(SceneGltfHairFile, ShippedStraightOnFloorExample) {
    const std::string hair = HT_SHARED_DIR "/data/straight.hair";
    if (!std::ifstream(hair)) GTEST_SKIP() << hair << " not present";
    const Scene plain = load_scene(hair);
    const Scene s = load_scene(HT_SOURCE_DIR "/scenes/straight_on_floor.gltf");
    ASSERT_EQ(s.strands.strand_count(), 10000u);
    ASSERT_EQ(s.strands.point_count(), plain.strands.point_count());
    for (size_t i = 0; i < s.strands.points.size(); i += 997) {
        const Vec3f& p = plain.strands.points[i];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.strands.points[i][c], (Vec3f{p[0], p[2], -p[1]})[c], 1e-3f) << i;
        EXPECT_NEAR(s.strands.radius[i], plain.strands.radius[i], 1e-6f);
    }
    EXPECT_EQ(s.materials.at(s.strands.material[0]).name, "warm_blond");
    EXPECT_TRUE(s.has_camera);
    EXPECT_EQ(s.lights.size(), 3u);
    ASSERT_EQ(s.meshes.size(), 1u);
    float lowest = 1e30f;
    for (const Vec3f& p : s.strands.points) lowest = std::min(lowest, p[1]);
    EXPECT_GT(lowest, s.meshes[0].positions[0][1]);  // the tips stay above the floor
}

}  // namespace
}  // namespace ht
