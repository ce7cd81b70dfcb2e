// Alpha in 8-bit images (host/io/image_io.h write_image): a PNG given the coverage channel A is
// RGBA with straight alpha (0 where nothing covers the pixel, 255 where hair covers it fully) and
// the colour divided by the coverage, so a half-covered edge pixel shows the same colour as a
// covered one; the EXR keeps the premultiplied radiance, a JPEG stays RGB.
#include <gtest/gtest.h>

#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

using namespace ht;

namespace {

// Four pixels of 4 samples each: empty, covered by hair of radiance `hair`, half covered and
// a quarter covered by the same hair (a film's radiance is premultiplied by the coverage).
const float hair[3] = {0.5f, 0.3f, 0.1f};
const std::vector<float> coverage = {0.0f, 1.0f, 0.5f, 0.25f};

Film edge_film() {
    Film f;
    f.width = 4;
    f.height = 1;
    for (float a : coverage) f.rgba.insert(f.rgba.end(), {4 * a * hair[0], 4 * a * hair[1], 4 * a * hair[2], 4.0f});
    return f;
}

struct Pixels {
    int channels = 0;
    std::vector<unsigned char> bytes;
};

// The stored bytes, alpha as written (OpenImageIO would premultiply a PNG's colour on reading).
Pixels read_bytes(const std::string& path) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    EXPECT_TRUE(in) << path;
    if (!in) return {};
    Pixels p;
    p.channels = in->spec().nchannels;
    p.bytes.resize(size_t(in->spec().image_pixels()) * p.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, p.channels, OIIO::TypeDesc::UINT8, p.bytes.data()));
    return p;
}

std::string scratch(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("ht_png_alpha_" + std::to_string(::getpid()) + name)).string();
}

}  // namespace

TEST(PngAlpha, StraightAlphaFromCoverage) {
    const Film film = edge_film();
    const std::vector<ImageChannel> alpha = {{"A", coverage}};
    const std::string rgba = scratch(".png"), rgb = scratch("_rgb.png");
    write_image(rgba, film, {}, 2.0f, ToneMap::Filmic, alpha);
    write_image(rgb, film, {}, 2.0f, ToneMap::Filmic);
    const Pixels p = read_bytes(rgba), plain = read_bytes(rgb);
    std::filesystem::remove(rgba);
    std::filesystem::remove(rgb);
    ASSERT_EQ(p.channels, 4);
    ASSERT_EQ(plain.channels, 3);
    auto at = [&](int pixel, int c) { return int(p.bytes[size_t(pixel) * 4 + c]); };
    EXPECT_EQ(at(0, 3), 0);
    EXPECT_EQ(at(1, 3), 255);
    EXPECT_EQ(at(2, 3), 128);
    EXPECT_EQ(at(3, 3), 64);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(at(0, c), 0) << "nothing to show where nothing covers the pixel";
        EXPECT_EQ(at(1, c), int(plain.bytes[3 + c])) << "a covered pixel keeps the colour of the RGB image";
        EXPECT_EQ(at(2, c), at(1, c)) << "the edge pixel's colour is the hair's, unpremultiplied";
        EXPECT_EQ(at(3, c), at(1, c));
        EXPECT_LT(int(plain.bytes[6 + c]), at(2, c)) << "without alpha the edge is darker";
    }
    EXPECT_GT(at(1, 0), at(1, 2)) << "a warm colour";
}

TEST(PngAlpha, ExrKeepsPremultipliedRadianceAndJpegStaysRgb) {
    const Film film = edge_film();
    const std::vector<ImageChannel> alpha = {{"A", coverage}};
    const std::string exr = scratch(".exr"), jpg = scratch(".jpg");
    write_image(exr, film, {}, 1.0f, ToneMap::Filmic, alpha);
    write_image(jpg, film, {}, 1.0f, ToneMap::Filmic, alpha);
    auto in = OIIO::ImageInput::open(exr);
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().nchannels, 4);
    EXPECT_EQ(in->spec().alpha_channel, 3);
    std::vector<float> v(16);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, v.data()));
    in->close();
    EXPECT_FLOAT_EQ(v[2 * 4 + 0], 0.5f * hair[0]);
    EXPECT_FLOAT_EQ(v[2 * 4 + 3], 0.5f);
    EXPECT_EQ(read_bytes(jpg).channels, 3);
    std::filesystem::remove(exr);
    std::filesystem::remove(jpg);
}
