// pbrt-v4 `Shape "curve"` (host/scene/pbrt_file.cpp): bases, degrees, widths, transforms,
// gzipped includes, skipped directives, flattening tolerance, and a round trip through the
// pbrt anchor's hair2pbrt.py.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using test::contains;
using test::scene_error_of;

TEST(ScenePbrt, LinearBezierIsExactAndWidthIsADiameter) {
    const Scene s = test::load_text_scene(
        "hair.pbrt",
        "# two linear segments, one strand\n"
        "Shape \"curve\" \"string type\" \"cylinder\" \"string basis\" \"bezier\" \"integer degree\" 3\n"
        "  \"integer splitdepth\" 0 \"float width\" 0.5\n"
        "  \"point3 P\" [ 0 0 0  0 1 0  0 2 0  0 3 0  1 4 0  2 5 0  3 6 0 ]\n");
    ASSERT_EQ(s.strands.strand_count(), 1u);
    EXPECT_EQ(s.strands.points, (std::vector<Vec3f>{{0, 0, 0}, {0, 3, 0}, {3, 6, 0}}));
    EXPECT_EQ(s.strands.radius, (std::vector<float>{0.25f, 0.25f, 0.25f}));
}

// Distance from p to the polyline of the strand.
double distance_to_chain(const Strands& s, const std::array<double, 3>& p) {
    double best = 1e300;
    for (size_t i = 0; i + 1 < s.points.size(); ++i) {
        const Vec3f& a = s.points[i];
        const Vec3f& b = s.points[i + 1];
        double ab[3], ap[3], t = 0, len2 = 0;
        for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ap[k] = p[k] - a[k], t += ab[k] * ap[k], len2 += ab[k] * ab[k];
        t = std::clamp(t / len2, 0.0, 1.0);
        double d2 = 0;
        for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
        best = std::min(best, std::sqrt(d2));
    }
    return best;
}

TEST(ScenePbrt, CurvedBsplineStaysWithinTheTolerance) {
    const Scene s = test::load_text_scene("bspline.pbrt",
                                          "Shape \"curve\" \"string basis\" \"bspline\" \"float width0\" 0.2 "
                                          "\"float width1\" 0.1\n  \"point3 P\" [ 0 0 0  1 2 0  2 0 0  3 2 0  4 0 1 ]\n");
    ASSERT_EQ(s.strands.strand_count(), 1u);
    EXPECT_GT(s.strands.point_count(), 6u);  // bent: more than one capsule per segment
    EXPECT_NEAR(s.strands.radius.front(), 0.1f, 1e-6);
    EXPECT_NEAR(s.strands.radius.back(), 0.05f, 1e-6);
    // Sample the exact curve (uniform cubic B-spline, two segments) and compare.
    const double P[5][3] = {{0, 0, 0}, {1, 2, 0}, {2, 0, 0}, {3, 2, 0}, {4, 0, 1}};
    for (int seg = 0; seg < 2; ++seg)
        for (int i = 0; i <= 50; ++i) {
            const double t = i / 50.0, u = 1 - t;
            const double w[4] = {u * u * u / 6, (3 * t * t * t - 6 * t * t + 4) / 6,
                                 (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6};
            std::array<double, 3> p{0, 0, 0};
            for (int k = 0; k < 4; ++k)
                for (int c = 0; c < 3; ++c) p[c] += w[k] * P[seg + k][c];
            // A tenth of the segment's smaller radius (0.075 then 0.05).
            EXPECT_LE(distance_to_chain(s.strands, p), 0.1 * (seg == 0 ? 0.075 : 0.05) + 1e-6) << "segment " << seg << " t " << t;
        }
}

void write_gzip(const std::string& path, const std::string& text) {
    gzFile f = gzopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, text.data(), unsigned(text.size())), int(text.size()));
    gzclose(f);
}

TEST(ScenePbrt, GzippedIncludesTransformsAndSkippedDirectives) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.file("models"));
    write_gzip(dir.file("models/lock.pbrt.gz"),
               "Shape \"curve\" \"float width\" 2 \"point3 P\" [0 0 0 0 0 1 0 0 2 0 0 3]\n"
               "Shape \"sphere\" \"float radius\" 1\n");
    const std::string path = dir.file("scene.pbrt");
    test::write_text(path, "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n"
                           "Translate 100 0 0  # camera space: reset by WorldBegin\n"
                           "WorldBegin\nLightSource \"distant\" \"point3 to\" [0 0 -1]\n"
                           "AttributeBegin\n  Translate 1 2 3\n  Scale 2 2 2\n  Material \"hair\" \"float eumelanin\" 1.3\n"
                           "  Import \"models/lock.pbrt.gz\"\nAttributeEnd\n"
                           "Include \"models/lock.pbrt.gz\"\n");
    const Scene s = load_scene(path);
    ASSERT_EQ(s.strands.strand_count(), 2u);
    EXPECT_EQ(s.strands.points[0], (Vec3f{1, 2, 3}));
    EXPECT_EQ(s.strands.points[1], (Vec3f{1, 2, 9}));
    EXPECT_FLOAT_EQ(s.strands.radius[0], 2.0f);  // width 2 = radius 1, scaled by 2
    EXPECT_EQ(s.strands.points[2], (Vec3f{0, 0, 0}));
    EXPECT_FLOAT_EQ(s.strands.radius[2], 1.0f);
    EXPECT_TRUE(test::any_warning_contains(s, "skipped 2 shapes other than \"curve\""));
    EXPECT_TRUE(test::any_warning_contains(s, "skipped 4 directives"));
}

TEST(ScenePbrt, RefusedInput) {
    test::TempDir dir;
    const std::string self = dir.file("self.pbrt");
    test::write_text(self, "Include \"self.pbrt\"\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(self); }), "includes itself"));
    const std::string degree = dir.file("degree.pbrt");
    test::write_text(degree, "Shape \"curve\" \"integer degree\" 1e300 \"point3 P\" [0 0 0 0 0 1 0 0 2 0 0 3]\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(degree); }), "is not 2 or 3"));
    const std::string count = dir.file("count.pbrt");
    test::write_text(count, "Shape \"curve\" \"point3 P\" [0 0 0 0 0 1 0 0 2 0 0 3 0 0 4]\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(count); }), "needs 3k + 1 points, has 5"));
    const std::string nan = dir.file("nan.pbrt");
    test::write_text(nan, "Shape \"sphere\"\nShape \"curve\" \"point3 P\" [0 0 0 0 0 1 0 nan 2 0 0 3]\n");
    const std::string msg = scene_error_of([&] { load_scene(nan); });
    test::expect_one_line_naming(msg, nan);
    EXPECT_TRUE(contains(msg, "curve 0 point 0")) << msg;  // the first point already mixes in the NaN
    const std::string none = dir.file("none.pbrt");
    test::write_text(none, "WorldBegin\nShape \"sphere\"\n");
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(none); }), "no Shape \"curve\""));
}

// hair2pbrt.py (the pbrt anchor's converter, ../shared/anchors/pbrt/) writes a .hair file as
// pbrt curves; reading them back gives the .hair file's own points and radii.
TEST(ScenePbrt, RoundTripThroughHair2pbrt) {
    const std::string script = HT_SHARED_DIR "/anchors/pbrt/hair2pbrt.py";
    if (!std::filesystem::exists(script)) GTEST_SKIP() << script << " is absent";
    if (std::system("/usr/bin/python3 -c 'import numpy' 2>/dev/null") != 0) GTEST_SKIP() << "python3-numpy is missing";
    test::TempDir dir;
    const std::string hair = dir.file("lock.hair"), pbrt = dir.file("lock.pbrt");
    test::HairSpec spec{test::three_strands()};
    test::write_file(hair, test::make_hair_bytes(spec));
    ASSERT_EQ(std::system(("/usr/bin/python3 " + script + " " + hair + " " + pbrt + " >/dev/null").c_str()), 0);
    const Scene a = load_scene(hair), b = load_scene(pbrt);
    // Varying radii: hair2pbrt writes one shape per segment, so strands come back per segment.
    ASSERT_EQ(b.strands.segment_count(), a.strands.segment_count());
    for (size_t s = 0, k = 0; s < a.strands.strand_count(); ++s)
        for (uint32_t i = a.strands.first_point[s]; i + 1 < a.strands.first_point[s + 1]; ++i, ++k) {
            const uint32_t j = b.strands.first_point[k];
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(b.strands.points[j][c], a.strands.points[i][c], 1e-5);
                EXPECT_NEAR(b.strands.points[j + 1][c], a.strands.points[i + 1][c], 1e-5);
            }
            EXPECT_NEAR(b.strands.radius[j], a.strands.radius[i], 1e-6);
            EXPECT_NEAR(b.strands.radius[j + 1], a.strands.radius[i + 1], 1e-6);
        }
}

}  // namespace
}  // namespace ht
