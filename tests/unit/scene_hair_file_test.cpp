// Cem Yuksel .hair loader: valid files with every flag combination, defaults, and malformed
// files (truncation at every byte, lying counts, bad flags, bad values).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::make_hair_bytes;
using test::scene_error_of;

TEST(SceneHairFile, EveryFlagCombinationWithPoints) {
    test::TempDir dir;
    const auto strands = test::three_strands();
    for (uint32_t flags = 0; flags < 32; ++flags) {
        if (!(flags & 2)) continue;
        test::HairSpec spec;
        spec.flags = flags;
        // Without per-strand counts every strand must have the default length.
        spec.strands = (flags & 1) ? strands
                                   : std::vector<std::vector<Vec3f>>{strands[0], strands[1]};
        if (!(flags & 1)) spec.strands[1].resize(3), spec.strands[1][2] = {1, 5, 0};
        spec.default_segments = 2;
        spec.default_thickness = 0.125f;
        const std::string path = dir.file("f" + std::to_string(flags) + ".hair");
        test::write_file(path, make_hair_bytes(spec));
        SCOPED_TRACE("flags " + std::to_string(flags));
        const Scene s = load_hair_file(path, {});
        ASSERT_EQ(s.strands.strand_count(), spec.strands.size());
        size_t point = 0;
        for (size_t i = 0; i < spec.strands.size(); ++i) {
            ASSERT_EQ(s.strands.first_point[i], point);
            for (const Vec3f& p : spec.strands[i]) {
                EXPECT_EQ(s.strands.points[point], p);
                const float expected_radius = (flags & 4) ? 0.25f + 0.001f * float(point) : 0.125f;
                EXPECT_FLOAT_EQ(s.strands.radius[point], expected_radius);
                ++point;
            }
        }
        EXPECT_EQ(s.strands.first_point.back(), point);
        EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
        ASSERT_EQ(s.materials.size(), 1u);
        EXPECT_EQ(s.materials[0].model, "marschner");
    }
}

TEST(SceneHairFile, ThicknessIsRadiusUnlessDiameterAndDefaultRadiusOverride) {
    test::TempDir dir;
    test::HairSpec spec;
    spec.strands = test::three_strands();
    const std::string with_thickness = dir.file("t.hair");
    test::write_file(with_thickness, make_hair_bytes(spec));
    LoadOptions diameter;
    diameter.thickness_is_diameter = true;
    EXPECT_FLOAT_EQ(load_hair_file(with_thickness, {}).strands.radius[0], 0.25f);
    EXPECT_FLOAT_EQ(load_hair_file(with_thickness, diameter).strands.radius[0], 0.125f);

    spec.flags = 1 | 2;  // no thickness array: header default, or the option's radius
    spec.default_thickness = 0.5f;
    const std::string no_thickness = dir.file("n.hair");
    test::write_file(no_thickness, make_hair_bytes(spec));
    EXPECT_FLOAT_EQ(load_hair_file(no_thickness, {}).strands.radius[3], 0.5f);
    EXPECT_FLOAT_EQ(load_hair_file(no_thickness, diameter).strands.radius[3], 0.25f);
    LoadOptions override_radius;
    override_radius.default_radius = 0.03f;
    EXPECT_FLOAT_EQ(load_hair_file(no_thickness, override_radius).strands.radius[3], 0.03f);

    spec.default_thickness = 0.0f;
    test::write_file(no_thickness, make_hair_bytes(spec));
    const std::string msg = scene_error_of([&] { load_hair_file(no_thickness, {}); });
    EXPECT_TRUE(contains(msg, "default thickness is 0")) << msg;
    EXPECT_FLOAT_EQ(load_hair_file(no_thickness, override_radius).strands.radius[0], 0.03f);
}

TEST(SceneHairFile, TruncatedAtEveryOffsetThrows) {
    test::TempDir dir;
    test::HairSpec spec;
    spec.strands = test::three_strands();
    spec.flags = 31;  // every array present, so truncation hits each of them
    const test::Bytes full = make_hair_bytes(spec);
    const std::string path = dir.file("cut.hair");
    for (size_t n = 0; n < full.size(); ++n) {
        test::write_file(path, test::Bytes(full.begin(), full.begin() + n));
        const std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
        test::expect_one_line_naming(msg, path);
    }
    test::write_file(path, full);
    EXPECT_EQ(load_hair_file(path, {}).strands.point_count(), 9u);
}

TEST(SceneHairFile, LyingCountsAreRefusedBeforeAllocation) {
    test::TempDir dir;
    const std::string path = dir.file("lie.hair");
    test::HairSpec spec;
    spec.strands = test::three_strands();

    spec.hair_count_override = 10000;
    test::write_file(path, make_hair_bytes(spec));
    std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "header says 10000 strands but the file holds only")) << msg;

    spec.hair_count_override = -1;
    spec.point_count_override = 8;  // segment counts add up to 9
    test::write_file(path, make_hair_bytes(spec));
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "segment counts")) << msg;

    spec.point_count_override = 1000000;
    test::write_file(path, make_hair_bytes(spec));
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "header says 1000000 points but the file holds only")) << msg;

    // Default segment count that does not match point_count.
    test::HairSpec defaults;
    defaults.strands = {test::three_strands()[0], test::three_strands()[0]};
    defaults.flags = 2 | 4;
    defaults.default_segments = 3;
    test::write_file(path, make_hair_bytes(defaults));
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "strands of 3 segments")) << msg;
}

TEST(SceneHairFile, ImpossibleSizesStateTheSize) {
    test::TempDir dir;
    const std::string path = dir.file("huge.hair");
    test::HairSpec spec;
    spec.strands = test::three_strands();
    spec.point_count_override = 0xFFFFFFFFll;
    test::write_file(path, make_hair_bytes(spec));
    std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "4294967295 points is more than the limit")) << msg;

    spec.point_count_override = 100000000;  // 1.5 GiB of strands
    test::write_file(path, make_hair_bytes(spec));
    LoadOptions small;
    small.max_bytes = uint64_t(1) << 30;
    msg = scene_error_of([&] { load_hair_file(path, small); });
    EXPECT_TRUE(contains(msg, "max_bytes")) << msg;
    EXPECT_TRUE(contains(msg, "GiB")) << msg;
}

TEST(SceneHairFile, BadHeaderFields) {
    test::TempDir dir;
    const std::string path = dir.file("bad.hair");
    test::HairSpec spec;
    spec.strands = test::three_strands();

    spec.flags = 2 | 64;
    test::write_file(path, make_hair_bytes(spec));
    std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "unknown array flag bits 0x40")) << msg;

    spec.flags = 1 | 4;
    test::write_file(path, make_hair_bytes(spec));
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "no geometry")) << msg;

    test::Bytes b = make_hair_bytes(test::HairSpec{test::three_strands()});
    b[0] = 'X';
    test::write_file(path, b);
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "signature")) << msg;

    msg = scene_error_of([&] { load_hair_file(dir.file("missing.hair"), {}); });
    EXPECT_TRUE(contains(msg, "cannot open")) << msg;
}

TEST(SceneHairFile, NonFinitePointNamesStrandAndPoint) {
    test::TempDir dir;
    const std::string path = dir.file("nan.hair");
    test::HairSpec spec;
    spec.strands = test::three_strands();
    spec.strands[1][2][0] = std::numeric_limits<float>::quiet_NaN();
    test::write_file(path, make_hair_bytes(spec));
    std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
    test::expect_one_line_naming(msg, path);
    EXPECT_TRUE(contains(msg, "strand 1 point 2")) << msg;

    spec.strands = test::three_strands();
    spec.strands[2][0][1] = std::numeric_limits<float>::infinity();
    test::write_file(path, make_hair_bytes(spec));
    msg = scene_error_of([&] { load_hair_file(path, {}); });
    EXPECT_TRUE(contains(msg, "strand 2 point 0")) << msg;
}

TEST(SceneHairFile, NegativeOrZeroRadiusIsRefused) {
    test::TempDir dir;
    const std::string path = dir.file("r.hair");
    for (float thickness : {-0.1f, 0.0f, std::numeric_limits<float>::quiet_NaN()}) {
        test::HairSpec spec;
        spec.strands = test::three_strands();
        spec.thickness = thickness;  // thickness + 0.001 * i: point 0 has exactly this value
        test::write_file(path, make_hair_bytes(spec));
        const std::string msg = scene_error_of([&] { load_hair_file(path, {}); });
        EXPECT_TRUE(contains(msg, "strand 0 point 0: radius")) << msg;
    }
}

TEST(SceneHairFile, ZeroLengthSegmentsAndShortStrandsAreRepaired) {
    test::TempDir dir;
    const std::string path = dir.file("dup.hair");
    test::HairSpec spec;
    spec.strands = test::three_strands();
    spec.strands[1].insert(spec.strands[1].begin() + 2, spec.strands[1][1]);  // duplicate
    spec.strands[1].push_back(spec.strands[1].back());                        // duplicate at end
    spec.strands.push_back({{5, 5, 5}});                                      // 1-point strand
    spec.strands.push_back({{6, 6, 6}, {6, 6, 6}});                           // collapses to 1
    test::write_file(path, make_hair_bytes(spec));
    const Scene s = load_hair_file(path, {});
    EXPECT_EQ(s.strands.strand_count(), 3u);
    EXPECT_EQ(s.strands.point_count(), 9u);
    EXPECT_EQ(s.strands.segment_count(), 6u);
    EXPECT_EQ(s.strands.points[4], (Vec3f{1, 1, 0}));
    EXPECT_EQ(s.strands.points[5], (Vec3f{1, 2, 0}));
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_TRUE(test::any_warning_contains(s, "dropped 3 duplicate points")) << s.warnings[0];
    EXPECT_TRUE(test::any_warning_contains(s, "dropped 2 strands with fewer than 2")) << s.warnings[1];
}

TEST(SceneHairFile, TrailingBytesWarn) {
    test::TempDir dir;
    const std::string path = dir.file("tail.hair");
    test::Bytes b = make_hair_bytes(test::HairSpec{test::three_strands()});
    b.insert(b.end(), 7, 0);
    test::write_file(path, b);
    EXPECT_TRUE(test::any_warning_contains(load_hair_file(path, {}), "ignored 7 bytes"));
}

TEST(SceneHairFile, SaveAndLoadRoundTrip) {
    test::TempDir dir;
    const Scene original = make_builtin("strand?hairs=50&segments=20");
    const std::string path = dir.file("round.hair");
    save_hair_file(path, original);
    const Scene loaded = load_scene(path);
    EXPECT_EQ(strands_content_hash(loaded.strands), strands_content_hash(original.strands));
    EXPECT_EQ(loaded.source, path);
}

// The Embree anchor's scene content hash (anchors/embree/README.md "Scenes", stored in its .rays
// files): FNV-1a 64 over the segment counts, points and thickness as the file stores them.  Here
// over the bytes of a written file, independently of the strands it was written from.
TEST(SceneHairFile, AnchorContentHashIsThatOfTheArraysAsStored) {
    test::TempDir dir;
    const Scene original = make_builtin("strand?hairs=50&segments=20");
    const std::string path = dir.file("hash.hair");
    save_hair_file(path, original);
    std::ifstream f(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), {});
    ASSERT_EQ(bytes.size(), 128u + 50 * 2 + 50 * 21 * (12 + 4));  // header, segments, points, thickness
    uint64_t h = 1469598103934665603ull;  // the anchor's offset basis (not FNV's published one), as core/hash.h
    for (size_t i = 128; i < bytes.size(); ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
    EXPECT_EQ(hair_file_hash(original.strands), h);
    EXPECT_EQ(hair_file_hash(load_scene(path).strands), h);
    // a strand the format cannot hold (no point): no hash
    Strands odd = original.strands;
    odd.first_point.push_back(odd.first_point.back());
    EXPECT_EQ(hair_file_hash(odd), 0u);
}

TEST(SceneHairFile, RealStraightHairModel) {
    const std::string path = HT_SHARED_DIR "/data/straight.hair";
    if (!std::ifstream(path)) GTEST_SKIP() << path << " not present";
    const Scene s = load_scene(path);
    EXPECT_EQ(s.strands.strand_count(), 10000u);
    EXPECT_EQ(s.strands.point_count(), 160000u);
    EXPECT_EQ(s.strands.segment_count(), 150000u);
    EXPECT_FLOAT_EQ(s.strands.radius[0], 0.1f);  // default thickness, used as the radius
    EXPECT_TRUE(s.warnings.empty());
    // the scene hash the Embree anchor writes in the ray files it makes of this file
    // (`embree_hair_bench --hair straight.hair --rays-out`, header offset 48)
    EXPECT_EQ(hair_file_hash(s.strands), 0x54a5f5a739b3ccc8ull);
}

}  // namespace
}  // namespace ht
