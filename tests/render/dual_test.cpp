// --indirect dual (kernels/fiber/dual.h, docs/MODEL.md §13): a biased fast mode, checked against
// exact path tracing for its mean, and for determinism, finiteness and the combinations it refuses.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "cli_test_util.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <cmath>

using namespace ht;
using namespace clitest;

namespace {
const std::string kBin = HT_BINARY;

ClContext& context() {
    static ClContext cl;
    return cl;
}

Film render(const Scene& scene, const RenderSettings& rs, RenderStats* stats = nullptr) {
    Renderer r(context(), scene, rs);
    Film f;
    const RenderStats s = r.render(f);
    if (stats) *stats = s;
    return f;
}

std::array<double, 3> channel_sums(const Film& f) {
    std::array<double, 3> s{0, 0, 0};
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(f.mean(i, c)));
            s[c] += f.mean(i, c);
        }
    return s;
}

Scene strand() {
    Scene s = load_scene("builtin:strand?hairs=400&segments=24");
    ensure_camera_and_light(s);
    return s;
}

RenderSettings small(int spp) {
    RenderSettings rs;
    rs.width = rs.height = 48;
    rs.spp = spp;
    return rs;
}
}  // namespace

TEST(Dual, MeanNearExactDepthTwentyAndAboveDirectLight) {
    Scene s = strand();
    RenderSettings rs = small(8);
    rs.max_depth = 1;
    const Film direct = render(s, rs);
    rs.indirect = RenderSettings::Indirect::Dual;
    RenderStats stats;
    const Film dual = render(s, rs, &stats);
    EXPECT_EQ(stats.nonfinite_caught, 0u);
    EXPECT_EQ(stats.cut_paths, 0u) << "dual stands for the paths depth 1 cuts";
    // The same light samples as the direct-light render, plus non-negative dual terms: no pixel
    // darker (float rounding aside)
    for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_GE(dual.mean(i, c), direct.mean(i, c) * (1 - 1e-5f) - 1e-9f) << i;
    rs.indirect = RenderSettings::Indirect::Exact;
    rs.max_depth = 20;
    rs.spp = 64;
    const Film exact = render(s, rs);
    const auto d = channel_sums(dual), e = channel_sums(exact), o = channel_sums(direct);
    for (int c = 0; c < 3; ++c) {
        std::printf("channel %d: dual / exact %.4f, direct / exact %.4f\n", c, d[c] / e[c], o[c] / e[c]);
        // Dual scattering is biased: measured here 0.88 / 0.89 / 0.93 of exact depth 20 (depth 1:
        // 0.53 / 0.60 / 0.72), on the full strand 0.94 / 0.93 / 0.95 (docs/MODEL.md §13).  The
        // test asks for what the method must do whatever its constants: recover at least half of
        // the light depth 1 misses, and not overshoot by more than 10 % (the 64-spp exact sum is
        // noisy at a few per cent: its sparkles are rare bright paths).
        const double gap = 1.0 - o[c] / e[c];
        EXPECT_GT(d[c] / e[c], 1.0 - 0.5 * gap) << "channel " << c;
        EXPECT_LT(d[c] / e[c], 1.10) << "channel " << c;
    }
}

TEST(Dual, DeterministicAndDifferentFromDirectLight) {
    Scene s = strand();
    RenderSettings rs = small(2);
    rs.indirect = RenderSettings::Indirect::Dual;
    const Film a = render(s, rs), b = render(s, rs);
    EXPECT_EQ(a.rgba, b.rgba);
    rs.indirect = RenderSettings::Indirect::Exact;
    EXPECT_NE(render(s, rs).rgba, a.rgba);
}

TEST(Dual, RefusesWhatItCannotDo) {
    TempDir d("ht_dual");
    const std::string r = kBin + " render 'builtin:strand?hairs=20&segments=8' --width 8 --height 8 --spp 1 --quiet ";
    EXPECT_EQ(run(r + "--indirect dual -o " + (d / "ok.exr") + " 2>" + (d / "e0.txt")), 0) << slurp(d / "e0.txt");
    EXPECT_EQ(run(r + "--indirect dual --max-depth 3 -o " + (d / "a.exr") + " 2>" + (d / "e1.txt")), 2);
    EXPECT_NE(slurp(d / "e1.txt").find("--max-depth 3"), std::string::npos) << slurp(d / "e1.txt");
    EXPECT_EQ(run(r + "--indirect dual --aovs alpha -o " + (d / "b.exr") + " 2>" + (d / "e2.txt")), 2);
    EXPECT_NE(slurp(d / "e2.txt").find("--aovs"), std::string::npos) << slurp(d / "e2.txt");
    EXPECT_EQ(run(r + "--indirect dual --model kajiya -o " + (d / "c.exr") + " 2>" + (d / "e3.txt")), 2);
    EXPECT_NE(slurp(d / "e3.txt").find("kajiya"), std::string::npos) << slurp(d / "e3.txt");
    EXPECT_EQ(run(r + "--indirect dual --max-depth 1 -o " + (d / "d.exr") + " 2>" + (d / "e4.txt")), 0) << slurp(d / "e4.txt");
}
