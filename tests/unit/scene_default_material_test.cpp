// Hair files that state no material get golden blond from melanin (blond_hair_material: the
// `blond` preset, eumelanin 0.3 as in pbrt-v4), whichever loader read them.  (A glTF without a
// material: scene_gltf_test.cpp.)
#include <gtest/gtest.h>

#include "scene/hair_presets.h"
#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

void expect_melanin_blond(const Scene& s, const std::string& what) {
    ASSERT_EQ(s.materials.size(), 1u) << what;
    const HairMaterialDesc& m = s.materials[0];
    const HairPreset& blond = *find_hair_preset("blond");
    EXPECT_EQ(m.name, "blond") << what;
    EXPECT_TRUE(m.has_melanin) << what;
    EXPECT_FALSE(m.has_sigma_a || m.has_color) << what << ": melanin is the only absorption source";
    EXPECT_EQ(m.eumelanin, blond.eumelanin) << what;
    EXPECT_EQ(m.pheomelanin, blond.pheomelanin) << what;
}

TEST(SceneDefaultMaterial, EveryLoaderWithoutAMaterialGivesMelaninBlond) {
    expect_melanin_blond(load_scene("builtin:strand?hairs=10&segments=4"), "builtin:strand");
    expect_melanin_blond(load_scene("builtin:ball?hairs=10&segments=4"), "builtin:ball");
    test::TempDir dir;
    test::HairSpec spec;
    spec.strands = test::three_strands();
    test::write_file(dir.file("h.hair"), test::make_hair_bytes(spec));
    expect_melanin_blond(load_scene(dir.file("h.hair")), ".hair");
    test::write_file(dir.file("h.data"), test::make_usc_bytes(test::three_strands()));
    expect_melanin_blond(load_scene(dir.file("h.data")), ".data");
    expect_melanin_blond(test::load_text_scene("h.obj", "v 0 0 0\nv 0 1 0\nl 1 2\n"), ".obj");
    expect_melanin_blond(test::load_text_scene("h.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                                        "property float y\nproperty float z\nelement strand 1\n"
                                                        "property int vertex_count\nend_header\n0 0 0\n0 1 0\n2\n"),
                         ".ply");
    expect_melanin_blond(test::load_text_scene("h.pbrt", "Shape \"curve\" \"float width\" 0.5 \"point3 P\" "
                                                         "[0 0 0 0 1 0 0 2 0 0 3 0]\n"),
                         ".pbrt");
}

}  // namespace
}  // namespace ht
