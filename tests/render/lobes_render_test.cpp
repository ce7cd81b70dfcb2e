// Lobes compiled out for very dark hair (host/render/features.cpp): the render barely changes.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/features.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace ht;

namespace {
ClContext& lobes_context() {
    static ClContext cl;
    return cl;
}

Film render_with(const Scene& scene, RenderSettings rs, FeatureMode mode, std::string* options = nullptr) {
    rs.features = mode;
    Renderer r(lobes_context(), scene, rs);
    if (options) *options = r.kernel_options();
    Film f;
    r.render(f);
    return f;
}

Scene dark_strand(const std::string& model) {
    Scene s = load_scene("builtin:strand?hairs=200&segments=16");
    for (auto& m : s.materials) {
        m.model = model;
        m.set_sigma_a({8.0f, 10.0f, 12.0f});
    }
    // back light too, so that TT (forward scattering) would have something to show
    ensure_camera_and_light(s);
    Light back = s.lights.front();
    back.position = {-back.position[0], back.position[1], -back.position[2]};
    s.lights.push_back(back);
    return s;
}
}  // namespace

TEST(LobesRender, DarkHairWithoutTTAndTRTMatchesAllLobes) {
    for (const char* model : {"marschner", "zinke", "chiang"}) {
        Scene s = dark_strand(model);
        RenderSettings rs;
        rs.width = rs.height = 48;
        rs.spp = 8;
        for (int depth : {1, 3}) {
            rs.max_depth = depth;
            std::string opt_out, opt_all;
            Film out = render_with(s, rs, FeatureMode::Scene, &opt_out);
            Film all = render_with(s, rs, FeatureMode::AllLobes, &opt_all);
            ASSERT_NE(opt_out.find("-DHT_FEATURE_LOBE_TT=0 -DHT_FEATURE_LOBE_TRT=0"), std::string::npos) << opt_out;
            ASSERT_NE(opt_all.find("-DHT_FEATURE_LOBE_TT=1 -DHT_FEATURE_LOBE_TRT=1"), std::string::npos) << opt_all;
            double sum_all = 0, sum_diff = 0, max_all = 0, max_diff = 0;
            for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
                for (int c = 0; c < 3; ++c) {
                    const double a = all.mean(i, c), o = out.mean(i, c);
                    ASSERT_TRUE(std::isfinite(a) && std::isfinite(o));
                    sum_all += a;
                    sum_diff += std::fabs(a - o);
                    max_all = std::max(max_all, a);
                    max_diff = std::max(max_diff, std::fabs(a - o));
                }
            double sum_out = 0;
            for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
                for (int c = 0; c < 3; ++c) sum_out += out.mean(i, c);
            std::printf("%s depth %d: sum |diff| / sum = %.3g, max |diff| / max = %.3g, mean out/all - 1 = %.3g\n",
                        model, depth, sum_diff / sum_all, max_diff / max_all, sum_out / sum_all - 1);
            ASSERT_GT(sum_all, 0.0);
            if (depth == 1) {
                // Direct light only: the same light samples, the fibre evaluated without the dropped
                // lobes -- a deterministic difference that the threshold bounds: each hit loses
                // < 1e-3 x AFS_R^avg of the light, while R alone returns ~AFS_R^avg of it (measured:
                // 1.5e-7 .. 1e-6 of the image).
                EXPECT_LT(sum_diff / sum_all, 1e-3) << model;
            } else {
                // Beyond one bounce the lobe-selection probabilities differ (marschner and zinke
                // floor every compiled-in lobe at 2 %), so the two renders draw different paths and
                // differ per pixel by Monte Carlo noise: compare the image means over 6 seeds each,
                // within 4 standard errors of the difference (estimated from the seed-to-seed
                // spread) plus 1e-3 of the mean for the bias the threshold allows.
                const int n = 6;
                double m[2] = {0, 0}, m2[2] = {0, 0};
                for (int seed = 0; seed < n; ++seed) {
                    RenderSettings r2 = rs;
                    r2.seed = 100 + seed;
                    const Film f[2] = {render_with(s, r2, FeatureMode::Scene), render_with(s, r2, FeatureMode::AllLobes)};
                    for (int k = 0; k < 2; ++k) {
                        double t = 0;
                        for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
                            for (int c = 0; c < 3; ++c) t += f[k].mean(i, c);
                        m[k] += t / n;
                        m2[k] += t * t / n;
                    }
                }
                const double se = std::sqrt((std::max(0.0, m2[0] - m[0] * m[0]) + std::max(0.0, m2[1] - m[1] * m[1])) / (n - 1));
                std::printf("%s depth %d over %d seeds: out %.6g all %.6g, standard error of the difference %.3g\n",
                            model, depth, n, m[0], m[1], se);
                EXPECT_LT(std::fabs(m[0] - m[1]), 4 * se + 1e-3 * m[1]) << model << " depth " << depth;
            }
        }
    }
}

#ifdef HT_BINARY
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

TEST(LobesRender, CliListsTheChoiceAndRefusesBadValues) {
    const std::string bin = HT_BINARY;
    const std::string dir = "/tmp/ht_lobes_cli_" + std::to_string(::getpid());
    const std::string small = " render 'builtin:strand?hairs=60&segments=8' --width 16 --height 16 --spp 1 --quiet -o " +
                              dir + ".exr";
    auto run = [](const std::string& c) { return WEXITSTATUS(std::system(c.c_str())); };
    auto slurp = [](const std::string& p) {
        std::ifstream f(p);
        std::stringstream s;
        s << f.rdbuf();
        return s.str();
    };
    ASSERT_EQ(run(bin + small + " --sigma-a 8,10,12 --verbose 2>" + dir + ".err"), 0);
    std::string err = slurp(dir + ".err");
    EXPECT_NE(err.find("lobe TT: compiled out"), std::string::npos) << err;
    EXPECT_NE(err.find("-DHT_FEATURE_LOBE_TT=0 -DHT_FEATURE_LOBE_TRT=0"), std::string::npos) << err;
    ASSERT_EQ(run(bin + small + " --sigma-a 8,10,12 --features all-lobes --verbose 2>" + dir + ".err"), 0);
    EXPECT_NE(slurp(dir + ".err").find("-DHT_FEATURE_LOBE_TT=1 -DHT_FEATURE_LOBE_TRT=1"), std::string::npos);
    ASSERT_EQ(run(bin + small + " --verbose 2>" + dir + ".err"), 0);  // blond: everything kept
    EXPECT_NE(slurp(dir + ".err").find("lobe TRT (chiang: + TRRT+): compiled in"), std::string::npos);
    EXPECT_EQ(run(bin + small + " --features most 2>/dev/null"), 2);
    EXPECT_EQ(run(bin + small + " --sigma-a 1,2 2>/dev/null"), 2);
    EXPECT_EQ(run(bin + small + " --sigma-a 1e9 2>/dev/null"), 2);  // out of the material range
    std::remove((dir + ".exr").c_str());
    std::remove((dir + ".err").c_str());
}
#endif
