// Base colour texture images (PNG, JPEG) decoded from memory through OpenImageIO into the
// Texture layout (8-bit sRGB rgb, one uint32 a texel).  tinygltf's own image decoding stays
// compiled out (tinygltf_config.h): one image library for the whole program, and the image's
// size is checked against the memory limit from its header before a pixel is decoded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

enum class ImageFormat { Unknown, Png, Jpeg };

// From the first bytes (the signature), not from a file name or a mimeType that may lie.
ImageFormat sniff_image_format(const unsigned char* bytes, size_t size);

// Images wider or taller than this are refused whatever the memory limit: texel indices are
// computed in 32-bit integers on the device, and a float texture coordinate cannot address a
// texel of a larger image anyway.
constexpr uint32_t kMaxTextureSide = 65536;

struct DecodedImage {
    uint32_t width = 0, height = 0;
    std::vector<uint32_t> texels;  // r | g << 8 | b << 16, row 0 at the top
};

// Throws SceneError "<file>: <what>: <problem>" for an undecodable image, a side of 0 or above
// kMaxTextureSide, or more than max_texels texels (checked before decoding).  Grey images are
// replicated to rgb; alpha is dropped (not premultiplied into the colour).  16-bit images are
// rounded to 8 bits.
DecodedImage decode_texture_image(const std::vector<unsigned char>& bytes, ImageFormat format,
                                  uint64_t max_texels, const std::string& file,
                                  const std::string& what);

}  // namespace ht
