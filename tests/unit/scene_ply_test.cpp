// PLY polylines (host/scene/ply_file.cpp): the three strand layouts, ascii and both binary byte
// orders, the vertex size properties, and the hygiene rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::Bytes;
using test::contains;
using test::scene_error_of;

// Appends `v` as big-endian bytes.
template <typename T>
void append_big(Bytes& b, T v) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    std::reverse(raw, raw + sizeof(T));
    b.insert(b.end(), raw, raw + sizeof(T));
}

// The header of a PLY file in `format` declaring `elements`, as the start of its bytes.
Bytes ply_header(const std::string& format, const std::string& elements) {
    const std::string h = "ply\nformat " + format + " 1.0\n" + elements + "end_header\n";
    return Bytes(h.begin(), h.end());
}

TEST(ScenePly, AsciiVertexCountsAndRadius) {
    const Scene s = test::load_text_scene(
        "hair.ply",
        "ply\nformat ascii 1.0\ncomment two strands\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float radius\n"
        "element strand 2\nproperty int vertex_count\nend_header\n"
        "0 0 0 0.1\n0 1 0 0.2\n0 2 0 0.3\n1 0 0 0.4\n1 1 0 0.5\n3\n2\n");
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.first_point, (std::vector<uint32_t>{0, 3, 5}));
    EXPECT_EQ(s.strands.points[4], (Vec3f{1, 1, 0}));
    EXPECT_FLOAT_EQ(s.strands.radius[2], 0.3f);
    EXPECT_TRUE(s.warnings.empty());
}

TEST(ScenePly, BinaryLittleEndianEdgesChainAndWidthIsADiameter) {
    test::TempDir dir;
    const std::string path = dir.file("edges.ply");
    Bytes b = ply_header("binary_little_endian",
                         "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float width\n"
                         "element edge 3\nproperty int vertex1\nproperty int vertex2\n"
                         "element face 1\nproperty list uchar int vertex_indices\n");
    for (int i = 0; i < 5; ++i) test::append(b, Vec3f{float(i), float(i * i), 0.0f}), test::append(b, 0.5f);
    for (int e : {0, 1, 1, 2, 3, 4}) test::append(b, int32_t(e));  // 0-1-2 chained, 3-4 alone
    b.push_back(3);
    for (int e : {0, 1, 2}) test::append(b, int32_t(e));
    test::write_file(path, b);
    const Scene s = load_scene(path);
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.first_point, (std::vector<uint32_t>{0, 3, 5}));
    EXPECT_EQ(s.strands.points[2], (Vec3f{2, 4, 0}));
    EXPECT_FLOAT_EQ(s.strands.radius[0], 0.25f);
    EXPECT_TRUE(test::any_warning_contains(s, "ignored 1 elements"));
}

TEST(ScenePly, BinaryBigEndianIndexListsAndThickness) {
    test::TempDir dir;
    const std::string path = dir.file("lists.ply");
    Bytes b = ply_header("binary_big_endian",
                         "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                         "property float thickness\nelement curve 2\nproperty list uchar uint vertex_indices\n");
    for (int i = 0; i < 4; ++i) {
        append_big(b, double(i)), append_big(b, 2.0 * i), append_big(b, -1.0);
        append_big(b, 0.1f * float(i + 1));
    }
    b.push_back(3);
    for (uint32_t v : {3u, 2u, 1u}) append_big(b, v);
    b.push_back(2);
    for (uint32_t v : {0u, 3u}) append_big(b, v);
    test::write_file(path, b);
    Scene s = load_scene(path);
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.points[0], (Vec3f{3, 6, -1}));
    EXPECT_EQ(s.strands.points[4], (Vec3f{3, 6, -1}));
    EXPECT_FLOAT_EQ(s.strands.radius[1], 0.3f);
    LoadOptions diameter;
    diameter.thickness_is_diameter = true;
    EXPECT_FLOAT_EQ(load_scene(path, diameter).strands.radius[1], 0.15f);
}

TEST(ScenePly, HygieneAndDefaultRadius) {
    test::TempDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                             "property float z\nelement strand 2\nproperty uchar nverts\nend_header\n";
    const std::string repaired = dir.file("repaired.ply");
    test::write_text(repaired, head + "0 0 0\n0 0 0\n0 10 0\n5 5 5\n3 1\n");
    const Scene s = load_scene(repaired);
    EXPECT_EQ(s.strands.strand_count(), 1u);  // the duplicate point and the 1-point strand dropped
    EXPECT_EQ(s.strands.point_count(), 2u);
    EXPECT_TRUE(test::any_warning_contains(s, "duplicate points"));
    EXPECT_TRUE(test::any_warning_contains(s, "no radius"));
    EXPECT_FLOAT_EQ(s.strands.radius[0], 10.0f * 1e-3f);

    const std::string nan = dir.file("nan.ply");
    test::write_text(nan, head + "0 0 0\n0 1 0\nnan 2 0\n5 5 5\n2 2\n");
    std::string msg = scene_error_of([&] { load_scene(nan); });
    test::expect_one_line_naming(msg, nan);
    EXPECT_TRUE(contains(msg, "strand 1 point 0")) << msg;

    const std::string bad_index = dir.file("bad_index.ply");
    test::write_text(bad_index, "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                "property float z\nelement strand 1\nproperty list uchar int vertex_indices\n"
                                "end_header\n0 0 0\n1 0 0\n2 0 7\n");
    msg = scene_error_of([&] { load_scene(bad_index); });
    EXPECT_TRUE(contains(msg, "strand 0: vertex index 7")) << msg;

    const std::string counts = dir.file("counts.ply");
    test::write_text(counts, head + "0 0 0\n0 1 0\n0 2 0\n5 5 5\n3 3\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(counts); }), "vertex count 3"));
}

TEST(ScenePly, CountsAreCheckedBeforeAllocating) {
    test::TempDir dir;
    const std::string path = dir.file("big.ply");
    // The header claims more vertices than the file holds (than its bytes, than its data)...
    const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
                             "property float y\nproperty float z\nelement strand 1\nproperty int vertex_count\n"
                             "end_header\n";
    std::string huge = head;
    huge.replace(huge.find("vertex 100"), 10, "vertex 100000000");
    test::write_text(path, huge);
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(path); }), "bytes could hold"));
    test::write_text(path, head + std::string(1000, ' '));
    std::string msg = scene_error_of([&] { load_scene(path); });
    EXPECT_TRUE(contains(msg, "header says 100 vertex items but the file holds only 1000 bytes")) << msg;
    // ...and a file whose vertices are there but need more than the memory limit.
    const std::string fits = dir.file("fits.ply");
    std::string text = "ply\nformat ascii 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
                       "property float z\nelement strand 1\nproperty int vertex_count\nend_header\n";
    for (int i = 0; i < 1000; ++i) text += std::to_string(i) + " 0 0\n";
    test::write_text(fits, text + "1000\n");
    test::expect_refused_only_under_small_limit(fits, 1000);
}

}  // namespace
}  // namespace ht
