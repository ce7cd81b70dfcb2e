// End-to-end renders of small scenes on the OpenCL device.
#include "cl/device.h"
#include "io/image_io.h"
#include "render/prepared_scene.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace ht;

namespace {

Scene small_strand() {
    Scene s = load_scene("builtin:strand?hairs=150&segments=20");
    ensure_camera_and_light(s);
    return s;
}

ClContext& test_context() {
    static ClContext cl;  // one context for the whole test binary: PoCL start-up is not free
    return cl;
}

Film render(const Scene& scene, RenderSettings rs) {
    Renderer r(test_context(), scene, rs);
    Film film;
    r.render(film);
    return film;
}

RenderSettings small_settings() {
    RenderSettings rs;
    rs.width = 48;
    rs.height = 48;
    rs.spp = 2;
    rs.seed = 7;
    return rs;
}

struct FilmSummary {
    size_t nonfinite = 0, lit = 0;
    double sum = 0;
};

FilmSummary summarize(const Film& f) {
    FilmSummary s;
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i) {
        double px = 0;
        for (int c = 0; c < 3; ++c) {
            float v = f.mean(i, c);
            if (!std::isfinite(v)) ++s.nonfinite;
            else px += v;
        }
        if (px > 0) ++s.lit;
        s.sum += px;
    }
    return s;
}

}  // namespace

TEST(Render, SmallStrandIsFiniteAndNotBlack) {
    Film f = render(small_strand(), small_settings());
    FilmSummary s = summarize(f);
    EXPECT_EQ(s.nonfinite, 0u);
    EXPECT_GT(s.lit, 20u) << "the strand should cover a good part of a framed image";
    EXPECT_GT(s.sum, 0.0);
    for (size_t i = 0; i < f.rgba.size(); i += 4) EXPECT_EQ(f.rgba[i + 3], 2.0f);
}

TEST(Render, SameSeedSameImageDifferentSeedDifferentImage) {
    Scene scene = small_strand();
    RenderSettings rs = small_settings();
    Film a = render(scene, rs), b = render(scene, rs);
    EXPECT_EQ(a.rgba, b.rgba);
    rs.seed = 8;
    Film c = render(scene, rs);
    EXPECT_NE(a.rgba, c.rgba);
}

TEST(Render, SamplesSplitAcrossCallsEqualOneCall) {
    // Counter-based random numbers: samples [0,2) then [2,4) equal [0,4) exactly.
    Scene scene = small_strand();
    RenderSettings rs = small_settings();
    rs.spp = 4;
    Film whole = render(scene, rs);
    rs.spp = 2;
    Film parts = render(scene, rs);
    rs.first_sample = 2;
    Renderer(test_context(), scene, rs).render(parts);
    EXPECT_EQ(whole.rgba, parts.rgba);
}

TEST(Render, PassSizeDoesNotChangeTheImage) {
    // Splitting the image into several passes (small device memory) gives identical pixels.
    Scene scene = small_strand();
    RenderSettings rs = small_settings();
    rs.max_depth = 3;
    Film one = render(scene, rs);
    rs.max_paths_per_pass = 500;
    Film many = render(scene, rs);
    EXPECT_EQ(one.rgba, many.rgba);
}

TEST(Render, OrientedBvhNodesGiveTheSameImage) {
    // --bvh-oriented changes the tree, not the hits (a tie at equal t goes to the higher segment id
    // in any tree): the same image, bit for bit, with axis-aligned nodes only.
    Scene scene = small_strand();
    RenderSettings rs = small_settings();
    rs.max_depth = 3;
    rs.bvh_oriented = 0.0f;
    const Film aligned = render(scene, rs);
    // The image with `tree`'s BVH options, after checking (by `built`) that they reached the builder.
    auto expect_same_image = [&](const RenderSettings& tree, size_t BvhStats::*built) {
        const PreparedScene prepared = prepare_scene(scene, tree);
        EXPECT_GT(prepared.geometry.stats.*built, 0u) << "the option must reach the BVH builder";
        Renderer r(test_context(), prepared);
        Film film;
        r.render(film);
        EXPECT_EQ(aligned.rgba, film.rgba);
    };
    rs.bvh_oriented = 0.8f;
    expect_same_image(rs, &BvhStats::oriented);
    // --bvh-oriented-splits: another tree again, the same hits (ties go to the higher id in any tree)
    rs.bvh_oriented_splits = 1.0f;
    expect_same_image(rs, &BvhStats::oriented_splits);
}

TEST(Render, IndirectBouncesAddLight) {
    Scene scene = small_strand();
    RenderSettings rs = small_settings();
    rs.spp = 4;
    double direct = summarize(render(scene, rs)).sum;
    rs.max_depth = 4;
    FilmSummary deep = summarize(render(scene, rs));
    EXPECT_EQ(deep.nonfinite, 0u);
    EXPECT_GT(deep.sum, direct) << "hair-to-hair scattering only adds light";
}

#ifdef HT_BINARY
namespace {
int run(const std::string& cmd) { return std::system(cmd.c_str()); }
std::string tmpdir() {
    auto d = std::filesystem::temp_directory_path() / ("ht_render_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}
std::string slurp(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}
}  // namespace

TEST(RenderCli, ThreadCountDoesNotChangeTheImage) {
    std::string d = tmpdir();
    std::string base = std::string(HT_BINARY) +
                       " render 'builtin:strand?hairs=100&segments=10' --width 40 --height 40 --spp 2 --max-depth 2 --quiet";
    ASSERT_EQ(run("POCL_MAX_PTHREAD_COUNT=1 " + base + " -o " + d + "/t1.exr"), 0);
    ASSERT_EQ(run("POCL_MAX_PTHREAD_COUNT=2 " + base + " -o " + d + "/t2.exr"), 0);
    int w1, h1, w2, h2;
    auto a = read_rgb_image(d + "/t1.exr", w1, h1);
    auto b = read_rgb_image(d + "/t2.exr", w2, h2);
    EXPECT_EQ(a, b);
    std::filesystem::remove_all(d);
}

TEST(RenderCli, ExitCodesMeanSomething) {
    std::string d = tmpdir();
    std::string bin = HT_BINARY;
    EXPECT_EQ(WEXITSTATUS(run(bin + " render 2>/dev/null")), 2);
    EXPECT_EQ(WEXITSTATUS(run(bin + " render builtin:strand --bogus 2>/dev/null")), 2);
    EXPECT_EQ(WEXITSTATUS(run(bin + " render " + d + "/missing.hair -o " + d + "/x.png --quiet 2>/dev/null")), 2);
    EXPECT_EQ(WEXITSTATUS(run(bin + " render builtin:strand -o " + d + "/x.png --device 99 --quiet 2>/dev/null")), 3);
    EXPECT_EQ(WEXITSTATUS(run(bin + " --help >/dev/null")), 0);
    EXPECT_EQ(WEXITSTATUS(run(bin + " render --help >/dev/null")), 0);
    EXPECT_EQ(WEXITSTATUS(run(bin + " frobnicate 2>/dev/null")), 2);
    std::filesystem::remove_all(d);
}

TEST(RenderCli, NoPlatformGivesInstallHintAndExit3) {
    std::string d = tmpdir();
    // An empty vendors directory: the ICD loader finds no platform.
    std::filesystem::create_directories(d + "/vendors");
    std::string cmd = "OCL_ICD_VENDORS=" + d + "/vendors " + std::string(HT_BINARY) + " devices 2>" + d + "/err.txt";
    EXPECT_EQ(WEXITSTATUS(run(cmd)), 3);
    EXPECT_NE(slurp(d + "/err.txt").find("pocl-opencl-icd"), std::string::npos) << slurp(d + "/err.txt");
    std::filesystem::remove_all(d);
}

TEST(RenderCli, WritesExrAndPngWithMetadata) {
    std::string d = tmpdir();
    std::string cmd = std::string(HT_BINARY) +
                      " render 'builtin:strand?hairs=100&segments=10' --width 32 --height 24 --spp 3 --seed 11 --quiet -o " +
                      d + "/a.exr -o " + d + "/a.png";
    ASSERT_EQ(run(cmd), 0);
    int w, h;
    auto rgb = read_rgb_image(d + "/a.exr", w, h);
    EXPECT_EQ(w, 32);
    EXPECT_EQ(h, 24);
    EXPECT_TRUE(std::filesystem::exists(d + "/a.png"));
    std::string exr = slurp(d + "/a.exr");
    EXPECT_NE(exr.find("hairtrace:spp"), std::string::npos);
    EXPECT_NE(exr.find("hairtrace:seed"), std::string::npos);
    EXPECT_NE(exr.find("hairtrace:device"), std::string::npos);
    EXPECT_NE(exr.find("hairtrace:render_seconds"), std::string::npos);
    std::filesystem::remove_all(d);
}
#endif
