// render --aovs (kernels/aovs.h, host/render/aovs.h): the beauty keeps its bits, the values add up
// where they must (direct + indirect = beauty; R + TT + TRT + residual = the hair's share), the
// albedo of a non-absorbing fibre is 1 (energy conservation, the reference), the command line
// refuses what it cannot write before rendering, and alpha makes a .png RGBA.
#include "cl/device.h"
#include "kernels/aovs.h"
#include "render/aovs.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <string>

using namespace ht;

namespace {

ClContext& aov_cl() {
    static ClContext cl;
    return cl;
}

Film render(const Scene& scene, RenderSettings rs, bool aovs) {
    rs.aovs = aovs;
    Film film;
    Renderer(aov_cl(), scene, rs).render(film);
    return film;
}

RenderSettings small(int depth) {
    RenderSettings rs;
    rs.width = rs.height = 40;
    rs.spp = 8;
    rs.max_depth = depth;
    return rs;
}

Scene lock() {
    Scene s = load_scene("builtin:strand?hairs=300&segments=16");
    ensure_camera_and_light(s);
    return s;
}

const ImageChannel& channel(const std::vector<ImageChannel>& chs, const std::string& name) {
    for (const ImageChannel& c : chs)
        if (c.name == name) return c;
    throw std::runtime_error("no channel " + name);
}

TEST(Aovs, BeautyIsTheSameBitsWithAndWithoutThem) {
    const Scene s = lock();
    const Film plain = render(s, small(4), false), with = render(s, small(4), true);
    EXPECT_TRUE(plain.aov.empty());
    ASSERT_EQ(with.aov.size(), size_t(HT_AOV_OUT) * 40 * 40);
    EXPECT_EQ(plain.rgba, with.rgba);
}

// Per pixel and channel, |a + b - beauty| within 1e-5 of the image's largest beauty value (float
// sums of the same terms in another order) and the image totals within 1e-5 relative.
void expect_sum(const Film& f, const std::vector<ImageChannel>& chs, const std::vector<std::string>& layers) {
    const size_t n = size_t(f.width) * f.height;
    double peak = 0, total = 0, parts = 0;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) peak = std::max(peak, double(f.mean(i, c)));
    ASSERT_GT(peak, 0);
    const char* rgb = "RGB";
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (const std::string& l : layers) sum += channel(chs, l + "." + rgb[c]).values[i];
            EXPECT_NEAR(sum, f.mean(i, c), 1e-5 * peak) << "pixel " << i << " channel " << c;
            total += f.mean(i, c);
            parts += sum;
        }
    EXPECT_NEAR(parts, total, 1e-5 * total);
}

TEST(Aovs, DirectPlusIndirectIsTheBeautyAndTheLobesAreTheHairsShare) {
    Scene s = lock();
    s.environment.color = {0.2f, 0.3f, 0.4f};  // environment seen directly, and at the end of paths
    const Film f = render(s, small(5), true);
    const std::vector<ImageChannel> chs = aov_channels(f, aov_names());
    expect_sum(f, chs, {"direct", "indirect"});
    // indirect light exists at depth 5, and depth 1 has none
    double indirect = 0;
    for (float v : channel(chs, "indirect.G").values) indirect += v;
    EXPECT_GT(indirect, 0);
    const Film d1 = render(s, small(1), true);
    const std::vector<ImageChannel> d1_chs = aov_channels(d1, {"indirect"});
    for (float v : channel(d1_chs, "indirect.G").values) EXPECT_EQ(v, 0.0f);

    // Without the environment every path's light came through hair first.
    s.environment.color = {0, 0, 0};
    const Film h = render(s, small(5), true);
    expect_sum(h, aov_channels(h, aov_names()), {"R", "TT", "TRT", "residual"});
}

TEST(Aovs, FirstHitSplitsKeepTheSumsAndTheCameraValues) {
    // --first-hit-splits 3, --first-hit-light-samples 2: each continuation has a record of its
    // own, the second light sample adds to the second one's, all added up per pixel
    Scene s = lock();
    s.environment.color = {0.2f, 0.3f, 0.4f};
    RenderSettings rs = small(5);
    rs.first_hit_splits = 3;
    rs.first_hit_light_samples = 2;
    const Film plain = render(s, rs, false), f = render(s, rs, true);
    EXPECT_EQ(plain.rgba, f.rgba);
    const std::vector<ImageChannel> chs = aov_channels(f, aov_names());
    expect_sum(f, chs, {"direct", "indirect"});
    // what the camera ray met is recorded once, as without splits
    const std::vector<ImageChannel> unsplit = aov_channels(render(s, small(5), true), aov_names());
    for (const std::string name : {"A", "Z", "tangent.X"})
        EXPECT_EQ(channel(chs, name).values, channel(unsplit, name).values) << name;
    s.environment.color = {0, 0, 0};
    const Film h = render(s, rs, true);
    expect_sum(h, aov_channels(h, aov_names()), {"R", "TT", "TRT", "residual"});
}

TEST(Aovs, AlphaDepthAndTangentDescribeWhatTheCameraSees) {
    const Scene s = lock();
    const Film f = render(s, small(2), true);
    const std::vector<ImageChannel> chs = aov_channels(f, {"alpha", "depth", "tangent"});
    const size_t n = size_t(f.width) * f.height;
    size_t covered = 0, empty = 0;
    for (size_t i = 0; i < n; ++i) {
        const float a = channel(chs, "A").values[i], z = channel(chs, "Z").values[i];
        ASSERT_GE(a, 0.0f);
        ASSERT_LE(a, 1.0f);
        const double lum = f.mean(i, 0) + f.mean(i, 1) + f.mean(i, 2);
        if (a == 0) {
            ++empty;
            EXPECT_EQ(lum, 0.0) << "light without anything in the pixel (no environment here)";
            EXPECT_EQ(z, 0.0f);
            continue;
        }
        ++covered;
        // the camera sits outside the lock: a positive, finite distance and a mean of unit tangents
        EXPECT_GT(z, 0.0f);
        EXPECT_TRUE(std::isfinite(z));
        const double t = std::hypot(channel(chs, "tangent.X").values[i], channel(chs, "tangent.Y").values[i],
                                    channel(chs, "tangent.Z").values[i]);
        EXPECT_LE(t, 1.0 + 1e-5);
    }
    EXPECT_GT(covered, n / 20);
    EXPECT_GT(empty, n / 20);
}

// A non-absorbing chiang fibre scatters all the light it receives: its directional albedo is 1
// (the sampling weights of such a fibre are 1 up to float rounding), so the albedo AOV divided by
// coverage must be 1 to 1e-3 wherever hair is seen.
TEST(Aovs, AlbedoOfANonAbsorbingFibreIsOne) {
    Scene s = lock();
    for (auto& m : s.materials) {
        m.model = "chiang";
        m.set_sigma_a({0, 0, 0});
    }
    const Film f = render(s, small(1), true);
    const std::vector<ImageChannel> chs = aov_channels(f, {"alpha", "albedo"});
    size_t checked = 0;
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i) {
        const float a = channel(chs, "A").values[i];
        if (a < 0.5f) continue;
        for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) EXPECT_NEAR(channel(chs, c).values[i] / a, 1.0, 1e-3);
        ++checked;
    }
    EXPECT_GT(checked, 20u);
}

#ifdef HT_BINARY
// A render small enough for the command-line tests; they add --aovs and outputs.
const std::string kSmallRender =
    std::string(HT_BINARY) + " render 'builtin:strand?hairs=100&segments=8' --width 24 --height 24 --spp 2 --quiet";

TEST(AovsCli, ChannelsAreNamedAndMistakesExit2BeforeRendering) {
    using namespace clitest;
    TempDir d("ht_aovs_");
    ASSERT_EQ(run(kSmallRender + " --aovs alpha,depth,direct,indirect,TRT -o " + d / "a.exr"), 0);
    auto in = OIIO::ImageInput::open(d / "a.exr");
    ASSERT_TRUE(in);
    const std::vector<std::string> expected = {"R", "G", "B", "A", "Z", "direct.R", "direct.G", "direct.B",
                                               "indirect.R", "indirect.G", "indirect.B", "TRT.R", "TRT.G", "TRT.B"};
    std::vector<std::string> names;
    for (const auto& n : in->spec().channelnames) names.push_back(n);
    std::sort(names.begin(), names.end());
    std::vector<std::string> sorted = expected;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(names, sorted);  // OpenEXR stores channels sorted by name
    in->close();

    const std::string err = d / "err.txt";
    EXPECT_EQ(run(kSmallRender + " --aovs alpha,drect -o " + d / "b.exr" + " 2>" + err), 2);
    EXPECT_NE(slurp(err).find("did you mean direct"), std::string::npos) << slurp(err);
    EXPECT_EQ(run(kSmallRender + " --aovs alpha,depth -o " + d / "c.png" + " 2>" + err), 2);
    EXPECT_NE(slurp(err).find(".exr"), std::string::npos) << slurp(err);
    EXPECT_EQ(run(kSmallRender + " --aovs alpha -o " + d / "c.jpg" + " 2>" + err), 2);
    EXPECT_NE(slurp(err).find(".png"), std::string::npos) << slurp(err);
    EXPECT_FALSE(std::filesystem::exists(d / "b.exr") || std::filesystem::exists(d / "c.png") ||
                 std::filesystem::exists(d / "c.jpg"));
}

// --aovs alpha with a .png: RGBA, the alpha the EXR's A in bytes, the colour of fully covered
// pixels that of the same render's RGB PNG (write_image's unit tests check the edges).
TEST(AovsCli, AlphaMakesThePngRgba) {
    using namespace clitest;
    TempDir d("ht_aovs_png_");
    ASSERT_EQ(run(kSmallRender + " -o " + d / "rgb.png"), 0);
    ASSERT_EQ(run(kSmallRender + " --aovs alpha -o " + d / "rgba.png -o " + d / "rgba.exr"), 0);
    auto read = [](const std::string& path, OIIO::TypeDesc type, void* data) {
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);  // the bytes as stored, not premultiplied on reading
        auto in = OIIO::ImageInput::open(path, &config);
        EXPECT_TRUE(in) << path;
        if (!in) return 0;
        const int channels = in->spec().nchannels;
        EXPECT_TRUE(in->read_image(0, 0, 0, channels, type, data));
        return channels;
    };
    const size_t n = 24 * 24;
    std::vector<unsigned char> rgba(n * 4), rgb(n * 3);
    std::vector<float> exr(n * 4);
    ASSERT_EQ(read(d / "rgba.png", OIIO::TypeDesc::UINT8, rgba.data()), 4);
    ASSERT_EQ(read(d / "rgb.png", OIIO::TypeDesc::UINT8, rgb.data()), 3);
    ASSERT_EQ(read(d / "rgba.exr", OIIO::TypeDesc::FLOAT, exr.data()), 4);
    size_t empty = 0, covered = 0;
    for (size_t i = 0; i < n; ++i) {
        const float a = exr[4 * i + 3];
        ASSERT_EQ(int(rgba[4 * i + 3]), int(std::lround(255 * a))) << i;
        if (a == 0) ++empty;
        if (a < 1) continue;
        ++covered;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(rgba[4 * i + c], rgb[3 * i + c]) << i;
    }
    EXPECT_GT(empty, n / 10);
    EXPECT_GT(covered, 0u);

    // `tonemap` of that EXR keeps its alpha: the same RGBA PNG as the render wrote, but for the
    // colour's rounding (the EXR holds each pixel's mean, the render divided its film's sums, so a
    // byte may move by one).
    ASSERT_EQ(run(std::string(HT_BINARY) + " tonemap " + d / "rgba.exr" + " -o " + d / "mapped.png --quiet"), 0);
    std::vector<unsigned char> mapped(n * 4);
    ASSERT_EQ(read(d / "mapped.png", OIIO::TypeDesc::UINT8, mapped.data()), 4);
    for (size_t i = 0; i < n; ++i) {
        ASSERT_EQ(mapped[4 * i + 3], rgba[4 * i + 3]) << i;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(mapped[4 * i + c], rgba[4 * i + c], 1) << i;
    }
}
#endif

}  // namespace
