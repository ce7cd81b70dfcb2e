#include "scene/texture_image.h"

#include "core/image_files.h"

#include <array>
#include <cstring>

#include "scene/scene_error.h"

namespace ht {

ImageFormat sniff_image_format(const unsigned char* bytes, size_t size) {
    static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    if (size >= 8 && std::memcmp(bytes, kPng, 8) == 0) return ImageFormat::Png;
    if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) return ImageFormat::Jpeg;
    return ImageFormat::Unknown;
}

namespace {

uint32_t be32(const unsigned char* p) { return uint32_t(p[0]) << 24 | p[1] << 16 | p[2] << 8 | p[3]; }

// CRC-32 (ISO 3309) as PNG chunks use it.
uint32_t crc32(const unsigned char* p, size_t n) {
    static const auto table = [] {
        std::array<uint32_t, 256> t{};
        for (uint32_t i = 0; i < 256; ++i) {
            uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
            t[i] = c;
        }
        return t;
    }();
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

// Walks the PNG's chunks (length, type, data, CRC) up to IEND before libpng sees them.  libpng
// reports a truncated or corrupt stream by longjmp out of OpenImageIO 2.4's read callback, which
// skips C++ destructors there and leaks (found by fuzz_gltf); a file whose chunk structure is
// whole and whose CRCs match never takes that path.  It also gives a precise message.
void check_png_chunks(const std::vector<unsigned char>& b, const std::string& file,
                      const std::string& what) {
    size_t at = 8;
    bool first = true, idat = false;
    for (;;) {
        if (b.size() - at < 12)
            scene_fail(file, what, ": PNG is truncated at byte ", at, " (no IEND chunk)");
        const uint32_t length = be32(&b[at]);
        if (length > b.size() - at - 12)
            scene_fail(file, what, ": PNG chunk at byte ", at, " claims ", length,
                       " bytes, more than the image holds");
        const unsigned char* type = &b[at + 4];
        if (crc32(type, 4 + size_t(length)) != be32(type + 4 + length))
            scene_fail(file, what, ": PNG chunk \"", std::string(type, type + 4), "\" at byte ", at,
                       " fails its CRC check (corrupt image)");
        if (first && (std::memcmp(type, "IHDR", 4) != 0 || length != 13))
            scene_fail(file, what, ": PNG does not start with an IHDR chunk");
        first = false;
        if (std::memcmp(type, "IDAT", 4) == 0) idat = true;
        if (std::memcmp(type, "IEND", 4) == 0) break;
        at += 12 + size_t(length);
    }
    if (!idat) scene_fail(file, what, ": PNG has no image data (IDAT chunk)");
}

}  // namespace

DecodedImage decode_texture_image(const std::vector<unsigned char>& bytes, ImageFormat format,
                                  uint64_t max_texels, const std::string& file,
                                  const std::string& what) {
    if (format == ImageFormat::Unknown)
        scene_fail(file, what, ": not a PNG or JPEG image (", bytes.size(), " bytes)");
    if (format == ImageFormat::Png) check_png_chunks(bytes, file, what);
    const char* format_name = format == ImageFormat::Png ? "png" : "jpeg";
    // Limits are checked on the header, before any pixel is allocated.
    auto accept = [&](const ImageFileSpec& spec) {
        if (spec.width <= 0 || spec.height <= 0)
            scene_fail(file, what, ": image has no pixels (", spec.width, " x ", spec.height, ")");
        const uint64_t w = uint64_t(spec.width), h = uint64_t(spec.height);
        if (w > kMaxTextureSide || h > kMaxTextureSide)
            scene_fail(file, what, ": image of ", w, " x ", h, " pixels is larger than ",
                       kMaxTextureSide, " on a side");
        if (w * h > max_texels)
            scene_fail(file, what, ": image of ", w, " x ", h, " pixels (", w * h * 4,
                       " bytes as texels) exceeds the memory limit for textures (--max-memory)");
        if (spec.channels < 1 || spec.channels > 4)
            scene_fail(file, what, ": image has ", spec.channels, " channels (1 to 4 are supported)");
        return true;
    };
    // The 8-bit pixels live only while they are repacked: at most 4 more bytes a texel, for one
    // image at a time, on top of what the limit above counts.
    ImageFileSpec spec;
    std::vector<unsigned char> pixels;
    const ImageFileResult decoded = image_files::decode(bytes.data(), bytes.size(), format_name, accept, &spec, &pixels);
    if (decoded.status == ImageFileStatus::OpenFailed)
        scene_fail(file, what, ": cannot decode the ", format == ImageFormat::Png ? "PNG" : "JPEG",
                   " image: ", one_line(decoded.error.empty() ? std::string("unknown error") : decoded.error));
    if (!decoded.ok())
        scene_fail(file, what, ": cannot decode the image: ",
                   one_line(decoded.error.empty() ? std::string("unknown error") : decoded.error));
    const uint64_t w = uint64_t(spec.width), h = uint64_t(spec.height);
    const int channels = spec.channels;
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
