// Robustness of every loader on damaged input: truncated text, random byte corruption.  The only
// acceptable outcomes are a loaded scene or a one-line SceneError naming the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "scene/rng.h"
#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

// Loads path; on SceneError checks the message format.  Returns whether it loaded.
bool load_or_scene_error(const std::string& path) {
    try {
        const Scene s = load_scene(path);
        EXPECT_GT(s.strands.strand_count(), 0u);
        EXPECT_FALSE(s.materials.empty());
        return true;
    } catch (const SceneError& e) {
        test::expect_one_line_naming(e.what(), path);
        return false;
    }
}

// Flips 1..4 random bytes of `original` (outside the first `keep` bytes) `rounds` times.
void corrupt_and_load(const test::Bytes& original, const std::string& path, size_t keep,
                      int rounds, uint64_t seed) {
    Pcg32 rng(seed, 0);
    int loaded = 0;
    for (int round = 0; round < rounds; ++round) {
        test::Bytes b = original;
        const int flips = 1 + static_cast<int>(rng.next() % 4);
        for (int f = 0; f < flips; ++f) {
            const size_t at = keep + rng.next() % (b.size() - keep);
            b[at] ^= static_cast<unsigned char>(1u << (rng.next() % 8));
        }
        test::write_file(path, b);
        loaded += load_or_scene_error(path) ? 1 : 0;
    }
    // Most flips land in coordinates, which load fine (or become NaN and are refused).
    EXPECT_GT(loaded, 0);
}

TEST(SceneRobustness, CorruptedHairFiles) {
    test::TempDir dir;
    test::HairSpec spec;
    spec.strands = test::three_strands();
    spec.flags = 31;
    corrupt_and_load(test::make_hair_bytes(spec), dir.file("c.hair"), 0, 200, 1);
}

TEST(SceneRobustness, CorruptedUscFiles) {
    test::TempDir dir;
    corrupt_and_load(test::make_usc_bytes(test::three_strands()), dir.file("c.data"), 0, 200, 2);
}

TEST(SceneRobustness, CorruptedGlbFiles) {
    test::GltfBuilder g;
    const int pos = g.add_vec3({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {1, 0, 0}, {1, 1, 0}});
    const int rad = g.add_scalar({1, 1, 1, 1, 1});
    const int idx = g.add_indices({0, 1, 1, 2, 3, 4});
    g.add_node({{"mesh", g.add_mesh(1, pos, rad, idx)}, {"translation", {1, 2, 3}}});
    test::TempDir dir;
    // Keep the 20-byte container header: corrupting it only tests the header check again.
    corrupt_and_load(g.glb_bytes(), dir.file("c.glb"), 20, 200, 3);
}

TEST(SceneRobustness, TruncatedGltfTextAtEveryOffset) {
    test::GltfBuilder g;
    g.add_node({{"mesh", g.add_mesh(3, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}))}});
    const std::string text = g.gltf_text();
    test::TempDir dir;
    const std::string path = dir.file("cut.gltf");
    for (size_t n = 0; n < text.size(); ++n) {
        test::write_text(path, text.substr(0, n));
        EXPECT_FALSE(load_or_scene_error(path)) << "prefix of " << n << " bytes loaded";
    }
    test::write_text(path, text);
    EXPECT_TRUE(load_or_scene_error(path));
}

TEST(SceneRobustness, DirectoriesAreNotScenes) {
    test::TempDir dir;
    for (const char* name : {"d.hair", "d.data", "d.gltf", "d.glb"}) {
        const std::string path = dir.file(name);
        std::filesystem::create_directory(path);
        const std::string msg = test::scene_error_of([&] { load_scene(path); });
        EXPECT_TRUE(test::contains(msg, "is a directory")) << msg;
    }
}

}  // namespace
}  // namespace ht
