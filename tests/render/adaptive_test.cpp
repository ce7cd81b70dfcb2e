// render --target-error (render/adaptive.h): the error estimate, camera rays for a list of pixels,
// and the adaptive render through the CLI: early end, prefix samples, determinism, checkpoints,
// refusals.
#include "render/adaptive.h"
#include "render/render_identity.h"
#include "split/checkpoint.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"
#include "render_test_util.h"

#include <cstring>
#include <filesystem>
#include <fstream>

using namespace ht;

namespace {

// A film of w x h pixels whose every pixel holds n samples, the even half `even` and the odd
// half `odd` (grey values, per-sample means).
Film two_halves(int w, int h, int n, float even, float odd) {
    Film f;
    f.width = w;
    f.height = h;
    const float n_even = float((n + 1) / 2), n_odd = float(n / 2);
    for (int i = 0; i < w * h; ++i) {
        for (int c = 0; c < 3; ++c) f.rgba.push_back(even * n_even + odd * n_odd);
        f.rgba.push_back(float(n));
        for (int c = 0; c < 3; ++c) f.even.push_back(even * n_even);
        f.even.push_back(n_even);
    }
    return f;
}

}  // namespace

TEST(Adaptive, PixelErrorIsHalfTheHalvesDifferenceOverTheMean) {
    const Film f = two_halves(2, 1, 8, 1.1f, 0.9f);
    // mean 1, eps = 0.1: |1.1 - 0.9| / (2 (1 + 0.1))
    EXPECT_NEAR(error_floor(f), 0.1f, 1e-6);
    EXPECT_NEAR(pixel_error(f, 0, error_floor(f)), 0.2 / 2.2, 1e-6);
    Film one = two_halves(1, 1, 1, 1.0f, 0.0f);
    EXPECT_EQ(pixel_error(one, 0, 0.1f), 0.0f);  // one sample: no estimate
    Film none = f;
    none.even.clear();
    EXPECT_EQ(pixel_error(none, 0, 0.1f), 0.0f);
}

TEST(Adaptive, TilesAboveTheTargetWithEverySampleGoOn) {
    // 16 x 8: two tiles; the left one noisy, the right one exact
    Film f = two_halves(16, 8, 8, 1.0f, 1.0f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const size_t i = size_t(y) * 16 + x;
            f.even[4 * i] += 2.0f;  // red of the even half: luminance 0.2126 x 2 / 4 higher
            f.rgba[4 * i] += 2.0f;
        }
    AdaptiveState st = assess_film(f, 8, 0.01f);
    EXPECT_EQ(st.tiles, 2);
    EXPECT_EQ(st.active_tiles, 1);
    EXPECT_EQ(st.tiles_above, 1);
    ASSERT_EQ(st.pixels.size(), 64u);
    EXPECT_EQ(st.pixels.front(), 0u);
    EXPECT_EQ(st.pixels.back(), 7u * 16 + 7);
    EXPECT_GT(st.max_error, 0.01);
    EXPECT_NEAR(st.rms_error, st.max_error / std::sqrt(2.0), 1e-6);
    // a tile that missed a chunk never goes on, however noisy
    st = assess_film(f, 16, 0.01f);
    EXPECT_EQ(st.active_tiles, 0);
    EXPECT_EQ(st.tiles_above, 1);
    EXPECT_TRUE(st.pixels.empty());
    // above a large target, nothing
    EXPECT_EQ(assess_film(f, 8, 10.0f).active_tiles, 0);
}

// The estimate falls with the samples a pixel got, as a standard error does (1 / sqrt(n): a
// sixteenth of the samples quadruples it), on a real render's halves.  Direct light only: with
// hair-to-hair light, pixels whose few bright paths dominate their mean keep an estimate near 1
// until those paths are averaged out (docs/ESTIMATOR.md "Adaptive sampling").
TEST(Adaptive, EstimateFallsWithMoreSamples) {
    const Scene scene = rendertest::thick_strand();
    RenderSettings rs = rendertest::small_settings(8, 3, 1);
    rs.target_error = 0.01f;
    const Film few = rendertest::render(scene, rs);
    rs.spp = 128;
    const Film many = rendertest::render(scene, rs);
    const double e_few = assess_film(few, 8, 0.01f).rms_error, e_many = assess_film(many, 128, 0.01f).rms_error;
    EXPECT_GT(e_few, 0.0);
    std::printf("estimate at 8 / 128 spp: %g / %g\n", e_few, e_many);
    EXPECT_LT(e_many, 0.4 * e_few);  // 1/4 expected
    EXPECT_GT(e_many, 0.1 * e_few);
}

// Camera rays for a list of pixels: the listed pixels get exactly the bits of a full render (the
// random numbers depend on the pixel, not on its slot in the pass), the others nothing.
TEST(Adaptive, ListedPixelsRenderTheSameBits) {
    const Scene scene = rendertest::thick_strand();
    RenderSettings rs = rendertest::small_settings(3, 4, 3);
    rs.target_error = 0.01f;
    rs.first_hit_splits = 2;
    rs.max_paths_per_pass = 300;  // several passes over the list
    const Film full = rendertest::render(scene, rs);
    std::vector<uint32_t> list;
    for (uint32_t i = 5; i < 48 * 48; i += 7) list.push_back(i);
    Renderer r(rendertest::context(), scene, rs);
    Film part;
    part.width = part.height = 48;
    part.rgba.assign(4 * 48 * 48, 0.0f);
    r.upload_film(part);
    r.set_pixels(list);
    for (uint32_t s = 0; s < 3; ++s) r.render_sample(s);
    r.download_film(part);
    size_t listed = 0;
    for (size_t i = 0; i < 48 * 48; ++i) {
        const bool in = listed < list.size() && list[listed] == i;
        listed += in;
        for (int c = 0; c < 4; ++c) {
            ASSERT_EQ(part.rgba[4 * i + c], in ? full.rgba[4 * i + c] : 0.0f) << "pixel " << i << " channel " << c;
            ASSERT_EQ(part.even[4 * i + c], in ? full.even[4 * i + c] : 0.0f) << "pixel " << i << " channel " << c;
        }
    }
    EXPECT_EQ(full.even[3], 2.0f);  // samples 0 and 2
    EXPECT_THROW(r.set_pixels({3, 2}), std::invalid_argument);
    EXPECT_THROW(r.set_pixels({48 * 48}), std::invalid_argument);
}

TEST(Adaptive, TargetErrorIsPartOfTheIdentity) {
    const Scene scene = rendertest::thick_strand();
    RenderSettings rs = rendertest::small_settings(8, 1, 2);
    const RenderIdentity plain = render_identity(scene, rs, 4);
    rs.target_error = 0.05f;
    rs.adaptive_min_spp = 4;
    const RenderIdentity a = render_identity(scene, rs, 4);
    EXPECT_NE(plain, a);
    EXPECT_NE(plain.differences(a).find("--target-error"), std::string::npos);
    rs.target_error = 0.02f;
    EXPECT_NE(render_identity(scene, rs, 4), a);
    rs.target_error = 0.05f;
    rs.adaptive_min_spp = 8;
    EXPECT_NE(render_identity(scene, rs, 4), a);
    rs.adaptive_min_spp = 4;
    EXPECT_EQ(render_identity(scene, rs, 4), a);
}

#ifdef HT_BINARY
namespace {
using clitest::run;
using clitest::TempDir;

const std::string kScene = std::string(HT_BINARY) +
    " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3 --seed 5 --quiet"
    " --chunk 4";
const std::string kAdaptive = kScene + " --target-error 0.4 --min-spp 4 --spp 64";

std::vector<float> channel(const std::string& path, const std::string& name) {
    const clitest::ChannelBits bits = clitest::channel_bits(path);
    const auto it = bits.find(name);
    if (it == bits.end()) return {};
    std::vector<float> v(it->second.size());
    std::memcpy(v.data(), it->second.data(), v.size() * sizeof(float));
    return v;
}

// Runs cmd once (a start of the binary takes seconds on a loaded machine), keeping its stderr.
int run_logged(const std::string& cmd, const std::string& file, std::string& text) {
    const int code = run(cmd + " 2>" + file);
    text = clitest::slurp(file);
    return code;
}

}  // namespace

// The target is reached early on a small scene: fewer samples than --spp everywhere, more where
// the error was, and each pixel's value is the non-adaptive render's with that pixel's count
// (its samples are a prefix of its sequence).
TEST(AdaptiveCli, ReachesTheTargetEarlyWithPrefixSamples) {
    TempDir d("ht_adapt_");
    std::string log;
    ASSERT_EQ(run_logged(
        std::string(HT_BINARY) + " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3 "
                                 "--seed 5 --chunk 4 --target-error 0.4 --min-spp 4 --spp 64 -o " + (d / "a.exr"),
        d / "log", log), 0) << log;
    EXPECT_NE(log.find("target error 0.4 reached before --spp"), std::string::npos) << log;
    {
        auto in = OIIO::ImageInput::open(d / "a.exr");
        ASSERT_TRUE(in);
        EXPECT_FLOAT_EQ(in->spec().get_float_attribute("hairtrace:target_error"), 0.4f);
        const float estimate = in->spec().get_float_attribute("hairtrace:error_estimate", -1.0f);
        EXPECT_GT(estimate, 0.0f);
        EXPECT_LE(estimate, 0.4f);
    }
    const std::vector<float> spp = channel(d / "a.exr", "spp");
    ASSERT_EQ(spp.size(), 40u * 32);
    const float most = *std::max_element(spp.begin(), spp.end()), least = *std::min_element(spp.begin(), spp.end());
    EXPECT_EQ(least, 4.0f);  // the background is exact after the first chunk
    EXPECT_GT(most, 4.0f);
    EXPECT_LT(most, 64.0f);
    const std::vector<float> a = clitest::image(d / "a.exr");
    size_t checked = 0;
    for (int n : {4, 8, int(most)}) {
        const std::string out = d / ("n" + std::to_string(n) + ".exr");
        ASSERT_EQ(run(kScene + " --spp " + std::to_string(n) + " -o " + out), 0);
        const std::vector<float> plain = clitest::image(out);
        for (size_t i = 0; i < spp.size(); ++i) {
            if (spp[i] != float(n)) continue;
            ++checked;
            for (int c = 0; c < 3; ++c) ASSERT_EQ(a[3 * i + c], plain[3 * i + c]) << "pixel " << i << ", " << n << " spp";
        }
    }
    EXPECT_GT(checked, 40u * 32 / 2);
}

TEST(AdaptiveCli, DeterministicAcrossRunsAndThreads) {
    TempDir d("ht_adapt_");
    ASSERT_EQ(run("POCL_MAX_PTHREAD_COUNT=1 " + kAdaptive + " -o " + (d / "t1.exr")), 0);
    ASSERT_EQ(run("POCL_MAX_PTHREAD_COUNT=2 " + kAdaptive + " -o " + (d / "t2.exr")), 0);
    ASSERT_EQ(run(kAdaptive + " -o " + (d / "t3.exr")), 0);
    EXPECT_EQ(clitest::channel_bits(d / "t1.exr"), clitest::channel_bits(d / "t2.exr"));
    EXPECT_EQ(clitest::channel_bits(d / "t1.exr"), clitest::channel_bits(d / "t3.exr"));
}

// A checkpoint inside a chunk (--spp 6: the second chunk's first half, on the tiles then above
// the target) and one cut by a time limit wherever it fell resume to the same bits; a checkpoint
// of a render without the target, or of an older format, is refused.
TEST(AdaptiveCli, ResumeIsBitIdentical) {
    TempDir d("ht_adapt_");
    ASSERT_EQ(run(kAdaptive + " -o " + (d / "full.exr")), 0);
    const std::string target = kScene + " --target-error 0.4 --min-spp 4";
    ASSERT_EQ(run(target + " --spp 6 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "part.exr")), 0);
    const Checkpoint c = load_checkpoint(d / "c.ckpt");
    EXPECT_EQ(c.even_sums, 4u);
    ASSERT_EQ(c.segments.size(), 2u);
    EXPECT_EQ(c.segments[1].film.even.size(), 4u * 40 * 32);
    ASSERT_EQ(run(kAdaptive + " --resume " + (d / "c.ckpt") + " -o " + (d / "resumed.exr")), 0);
    EXPECT_EQ(clitest::channel_bits(d / "full.exr"), clitest::channel_bits(d / "resumed.exr"));

    ASSERT_EQ(run(kAdaptive + " --time-limit 0.001 --checkpoint " + (d / "t.ckpt") + " -o " + (d / "early.exr")), 0);
    ASSERT_EQ(run(kAdaptive + " --resume " + (d / "t.ckpt") + " -o " + (d / "resumed_t.exr")), 0);
    EXPECT_EQ(clitest::channel_bits(d / "full.exr"), clitest::channel_bits(d / "resumed_t.exr"));

    ASSERT_EQ(run(kScene + " --spp 4 --checkpoint " + (d / "plain.ckpt") + " -o " + (d / "plain.exr")), 0);
    std::string msg;
    EXPECT_EQ(run_logged(kAdaptive + " --resume " + (d / "plain.ckpt") + " -o " + (d / "x.exr"), d / "e1", msg), 2);
    EXPECT_NE(msg.find("--target-error"), std::string::npos) << msg;
    // version 5 (before the even halves): the version field follows the 4-byte magic
    {
        std::fstream f(d / "c.ckpt", std::ios::in | std::ios::out | std::ios::binary);
        const uint32_t v5 = 5;
        f.seekp(4);
        f.write(reinterpret_cast<const char*>(&v5), sizeof v5);
    }
    EXPECT_EQ(run_logged(kAdaptive + " --resume " + (d / "c.ckpt") + " -o " + (d / "x.exr"), d / "e2", msg), 2);
    EXPECT_NE(msg.find("checkpoint version 5 is not supported"), std::string::npos) << msg;
}

TEST(AdaptiveCli, BadValuesAndCombinationsAreRefused) {
    TempDir d("ht_adapt_");
    const std::string out = " -o " + (d / "x.exr");
    std::string msg;
    for (const char* bad : {"0", "-1", "abc", "1e9"}) {
        EXPECT_EQ(run_logged(kScene + " --target-error " + bad + out, d / "e", msg), 2) << bad;
        EXPECT_NE(msg.find("--target-error"), std::string::npos) << bad << ": " << msg;
    }
    EXPECT_EQ(run_logged(kScene + " --min-spp 8" + out, d / "e", msg), 2);
    EXPECT_NE(msg.find("--min-spp only applies with --target-error"), std::string::npos) << msg;
    EXPECT_EQ(run_logged(kAdaptive + " --min-spp 1" + out, d / "e", msg), 2);
    EXPECT_NE(msg.find("--min-spp"), std::string::npos) << msg;
    EXPECT_EQ(run_logged(kAdaptive + " --sample-range 0:8" + out, d / "e", msg), 2);
    EXPECT_NE(msg.find("cannot be combined with --sample-range"), std::string::npos) << msg;
}
#endif
