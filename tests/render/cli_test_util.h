// Shared helpers of the tests that run the hairtrace binary (header only: the test globs take
// *.cpp): a scratch directory, a command's exit status, a file's bytes, an image's channels.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "io/image_io.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

namespace clitest {

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& prefix) {
        path = std::filesystem::temp_directory_path() /
               (prefix + std::to_string(::getpid()) + "_" + std::to_string(std::rand()));
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    std::string operator/(const std::string& f) const { return (path / f).string(); }
};

// The exit status of a shell command (as the shell reports it).
inline int run(const std::string& cmd) { return WEXITSTATUS(std::system(cmd.c_str())); }

inline std::string slurp(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// The rgb floats of an image file (width and height dropped: the tests compare equal-size images).
inline std::vector<float> image(const std::string& p) {
    int w, h;
    return ht::read_rgb_image(p, w, h);
}

// An A/B option of `render` that must not change the image: `render` + a_option and + b_option
// (each may be empty: the default) write the same pixels into d, and each of `bad` exits 2.
inline void expect_same_image_and_usage_errors(const TempDir& d, const std::string& render, const std::string& a_option,
                                               const std::string& b_option, const std::vector<std::string>& bad) {
    ASSERT_EQ(run(render + a_option + " -o " + (d / "a.exr")), 0) << a_option;
    ASSERT_EQ(run(render + b_option + " -o " + (d / "b.exr")), 0) << b_option;
    EXPECT_EQ(image(d / "a.exr"), image(d / "b.exr")) << a_option << " against" << b_option;
    for (const std::string& option : bad) EXPECT_EQ(run(render + option + " -o " + (d / "x.exr") + " 2>/dev/null"), 2) << option;
}

// An integer attribute of an image's metadata (0 when it has none).
inline int int_attribute(const std::string& p, const std::string& name) {
    auto in = OIIO::ImageInput::open(p);
    return in ? in->spec().get_int_attribute(name) : 0;
}

// Every channel of an image by name, each value as its bits: equal maps are the same channels
// with the same bits (float == would call -0 and 0 equal and a NaN unequal to itself).
using ChannelBits = std::map<std::string, std::vector<uint32_t>>;
inline ChannelBits channel_bits(const std::string& p) {
    auto in = OIIO::ImageInput::open(p);
    if (!in) return {};
    const OIIO::ImageSpec spec = in->spec();
    const size_t pixels = size_t(spec.width) * size_t(spec.height), nc = size_t(spec.nchannels);
    std::vector<float> all(pixels * nc);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) return {};
    ChannelBits out;
    for (size_t c = 0; c < nc; ++c) {
        std::vector<uint32_t>& bits = out[spec.channelnames[c]];
        bits.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) std::memcpy(&bits[i], &all[i * nc + c], sizeof(float));
    }
    return out;
}

// render --aovs with every name (render/aovs.h).
const std::string kEveryAov = " --aovs alpha,depth,tangent,albedo,direct,indirect,R,TT,TRT,residual";

// Expects `actual` to hold the channels of `expected` with the same bits, where `expected` is a
// render with kEveryAov whose coverage, depth and direct light are not all zero (so that the
// equality says something about the AOVs).
inline void expect_same_channel_bits(const std::string& expected, const std::string& actual) {
    const ChannelBits e = channel_bits(expected), a = channel_bits(actual);
    for (const char* name : {"A", "Z", "tangent.X", "albedo.G", "direct.G", "indirect.G", "TRT.B", "residual.R"})
        ASSERT_EQ(e.count(name), 1u) << expected << " lacks the AOV channel " << name;
    for (const char* name : {"A", "Z", "direct.G"}) {
        const std::vector<uint32_t>& bits = e.at(name);
        EXPECT_TRUE(std::any_of(bits.begin(), bits.end(), [](uint32_t b) { return b != 0; }))
            << expected << ": " << name << " is zero everywhere";
    }
    for (const auto& [name, bits] : e) {
        ASSERT_EQ(a.count(name), 1u) << actual << " lacks the channel " << name;
        ASSERT_EQ(a.at(name).size(), bits.size()) << actual << " has another size";
        size_t differ = 0;
        for (size_t i = 0; i < bits.size(); ++i) differ += bits[i] != a.at(name)[i];
        EXPECT_EQ(differ, 0u) << actual << ", channel " << name << ": " << differ << " pixels differ from "
                              << expected;
    }
    EXPECT_EQ(a.size(), e.size()) << actual << " has other channels";
}

#ifdef HT_BINARY
// `hairtrace render` of a small lit strand at depth 3 (100 fibres of 10 segments, 32 x 24): quick,
// and every estimator stage takes part (first-hit splits, light samples, the light threshold).
inline const std::string kSmallStrandRender = std::string(HT_BINARY) +
                                              " render 'builtin:strand?hairs=100&segments=10' --width 32 --height 24 "
                                              "--max-depth 3 --seed 4 --quiet";

// An estimator option's command-line default: `render` (a command without -o) as it is and with
// `explicit_default` added gives the same image, with `other` another one, and every one of `bad`
// exits 2 (a usage error).  Images go to d.
inline void expect_option_default(const TempDir& d, const std::string& render, const std::string& explicit_default,
                                  const std::string& other, const std::vector<std::string>& bad) {
    const auto rendered = [&](const std::string& options, const std::string& name) {
        return run(render + options + " -o " + (d / name) + " 2>/dev/null");
    };
    ASSERT_EQ(rendered("", "default.exr"), 0);
    ASSERT_EQ(rendered(" " + explicit_default, "explicit.exr"), 0);
    EXPECT_EQ(image(d / "default.exr"), image(d / "explicit.exr")) << explicit_default;
    ASSERT_EQ(rendered(" " + other, "other.exr"), 0);
    EXPECT_NE(image(d / "default.exr"), image(d / "other.exr")) << other;
    for (const std::string& b : bad) EXPECT_EQ(rendered(" " + b, "x.exr"), 2) << b;
}

// `render` (8 samples, a command without -o) in chunks of 2 gives the same bits on one thread, on
// two devices and as two render-farm parts merged.  Images go to d; the chunked one is c2.exr.
inline void expect_same_bits_in_chunks_threads_devices_and_parts(const TempDir& d, const std::string& render) {
    ASSERT_EQ(run(render + " --chunk 2 -o " + (d / "c2.exr")), 0);
    ASSERT_EQ(run("POCL_MAX_PTHREAD_COUNT=1 " + render + " --chunk 2 -o " + (d / "c2t1.exr")), 0);
    EXPECT_EQ(image(d / "c2.exr"), image(d / "c2t1.exr")) << "one thread";
    ASSERT_EQ(run("POCL_DEVICES='pthread basic' " + render + " --chunk 2 --device 0,1 -o " + (d / "c2d2.exr")), 0);
    EXPECT_EQ(image(d / "c2.exr"), image(d / "c2d2.exr")) << "two devices";
    ASSERT_EQ(run(render + " --chunk 2 --sample-range 0:6 -o " + (d / "p0.exr")), 0);
    ASSERT_EQ(run(render + " --chunk 2 --sample-range 6:8 -o " + (d / "p1.exr")), 0);
    ASSERT_EQ(run(std::string(HT_BINARY) + " merge " + (d / "p1.exr") + " " + (d / "p0.exr") + " -o " +
                  (d / "merged.exr") + " --quiet"),
              0);
    EXPECT_EQ(image(d / "c2.exr"), image(d / "merged.exr")) << "two parts merged";
}
#endif

}  // namespace clitest
