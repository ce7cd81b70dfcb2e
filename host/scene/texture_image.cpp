#include "scene/texture_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>

#include "scene/scene_error.h"

namespace ht {

ImageFormat sniff_image_format(const unsigned char* bytes, size_t size) {
    static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    if (size >= 8 && std::memcmp(bytes, kPng, 8) == 0) return ImageFormat::Png;
    if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) return ImageFormat::Jpeg;
    return ImageFormat::Unknown;
}

DecodedImage decode_texture_image(const std::vector<unsigned char>& bytes, ImageFormat format,
                                  uint64_t max_texels, const std::string& file,
                                  const std::string& what) {
    if (format == ImageFormat::Unknown)
        scene_fail(file, what, ": not a PNG or JPEG image (", bytes.size(), " bytes)");
    // OIIO reads through the proxy, never from the disk, and only with the plugin named here:
    // no other of OIIO's many readers ever sees the bytes.
    const char* format_name = format == ImageFormat::Png ? "png" : "jpeg";
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    auto in = OIIO::ImageInput::create(format_name, false, nullptr, &proxy);
    OIIO::ImageSpec config, opened;
    void* proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
    // The PNG reader premultiplies colour by alpha unless told not to; alpha is not coverage here.
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (!in || !in->open("texture", opened, config)) {
        std::string err = in ? in->geterror() : OIIO::geterror();
        scene_fail(file, what, ": cannot decode the ", format == ImageFormat::Png ? "PNG" : "JPEG",
                   " image: ", one_line(err.empty() ? std::string("unknown error") : err));
    }
    const OIIO::ImageSpec spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1)
        scene_fail(file, what, ": image has no pixels (", spec.width, " x ", spec.height, ")");
    const uint64_t w = uint64_t(spec.width), h = uint64_t(spec.height);
    if (w > kMaxTextureSide || h > kMaxTextureSide)
        scene_fail(file, what, ": image of ", w, " x ", h, " pixels is larger than ",
                   kMaxTextureSide, " on a side");
    if (w * h > max_texels)
        scene_fail(file, what, ": image of ", w, " x ", h, " pixels (", w * h * 4,
                   " bytes as texels) exceeds the memory limit for textures (--max-memory)");
    const int channels = spec.nchannels;
    if (channels < 1 || channels > 4)
        scene_fail(file, what, ": image has ", channels, " channels (1 to 4 are supported)");
    std::vector<unsigned char> pixels(w * h * size_t(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data())) {
        std::string err = in->geterror();
        scene_fail(file, what, ": cannot decode the image: ",
                   one_line(err.empty() ? std::string("unknown error") : err));
    }
    in->close();
    DecodedImage out;
    out.width = uint32_t(w);
    out.height = uint32_t(h);
    out.texels.resize(w * h);
    for (size_t i = 0; i < out.texels.size(); ++i) {
        const unsigned char* p = &pixels[i * size_t(channels)];
        // 1-2 channels: grey (+ alpha); 3-4: rgb (+ alpha).  Alpha is dropped either way.
        const uint32_t r = p[0], g = channels >= 3 ? p[1] : p[0], b = channels >= 3 ? p[2] : p[0];
        out.texels[i] = r | g << 8 | b << 16;
    }
    return out;
}

}  // namespace ht
