#include "scene/gltf_texture.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "scene/scene_error.h"
#include "scene/texture_image.h"

namespace ht {

namespace {

std::string image_label(const tinygltf::Image& image, int index) {
    if (!image.name.empty()) return str_cat("image ", index, " \"", image.name, "\"");
    if (!image.uri.empty() && image.uri.compare(0, 5, "data:") != 0)
        return str_cat("image ", index, " \"", image.uri, "\"");
    return str_cat("image ", index);
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// URIs are percent-encoded (RFC 3986): "my%20floor.png" names "my floor.png".
std::string percent_decode(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex_digit(uri[i + 1]) >= 0 && hex_digit(uri[i + 2]) >= 0) {
            out += char(hex_digit(uri[i + 1]) * 16 + hex_digit(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

TextureWrap wrap_mode(int gl, const std::string& file, int sampler, const char* axis) {
    switch (gl) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return TextureWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::MirroredRepeat;
        default:
            scene_fail(file, "sampler ", sampler, ": ", axis, " ", gl,
                       " is not REPEAT (10497), CLAMP_TO_EDGE (33071) or MIRRORED_REPEAT (33648)");
    }
}

}  // namespace

bool keep_gltf_image_bytes(tinygltf::Image* image, int, std::string*, std::string*, int, int,
                           const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

GltfTextureReader::GltfTextureReader(const tinygltf::Model& model, const std::string& file,
                                     const std::string& directory, const LoadOptions& opt,
                                     std::vector<Texture>& textures)
    : model_(model), file_(file), directory_(directory), opt_(opt), textures_(textures) {}

int32_t GltfTextureReader::base_color_texture(const tinygltf::Material& material, int index) {
    const tinygltf::TextureInfo& info = material.pbrMetallicRoughness.baseColorTexture;
    if (info.index < 0) return -1;
    const std::string where = str_cat("material ", index, " baseColorTexture");
    if (static_cast<size_t>(info.index) >= model_.textures.size())
        scene_fail(file_, where, ": texture ", info.index, " does not exist (the file has ",
                   model_.textures.size(), " textures)");
    if (info.texCoord != 0)
        scene_fail(file_, where, ": texCoord ", info.texCoord,
                   " is not supported (only TEXCOORD_0 is read)");
    if (info.extensions.count("KHR_texture_transform")) ++ignored_transforms_;
    const auto it = decoded_.find(info.index);
    if (it != decoded_.end()) return it->second;
    Texture t = decode(info.index, where);
    const int32_t scene_index = static_cast<int32_t>(textures_.size());
    textures_.push_back(std::move(t));
    decoded_[info.index] = scene_index;
    return scene_index;
}

Texture GltfTextureReader::decode(int texture_index, const std::string& where) {
    const tinygltf::Texture& gt = model_.textures[texture_index];
    if (gt.source < 0 || static_cast<size_t>(gt.source) >= model_.images.size())
        scene_fail(file_, where, ": texture ", texture_index, " has no valid source image (",
                   gt.source, "; the file has ", model_.images.size(), " images)");
    Texture t;
    if (gt.sampler >= 0) {
        if (static_cast<size_t>(gt.sampler) >= model_.samplers.size())
            scene_fail(file_, where, ": texture ", texture_index, " names sampler ", gt.sampler,
                       ", which does not exist");
        const tinygltf::Sampler& s = model_.samplers[gt.sampler];
        t.wrap_s = wrap_mode(s.wrapS, file_, gt.sampler, "wrapS");
        t.wrap_t = wrap_mode(s.wrapT, file_, gt.sampler, "wrapT");
    }
    const tinygltf::Image& image = model_.images[gt.source];
    const std::string what = image_label(image, gt.source);
    if (!image.mimeType.empty() && image.mimeType != "image/png" && image.mimeType != "image/jpeg")
        scene_fail(file_, what, ": mimeType \"", image.mimeType,
                   "\" is not supported (image/png and image/jpeg are)");
    const std::vector<unsigned char> bytes = image_bytes(gt.source, what);
    // Texels are 4 bytes; all textures together stay within the limit and well inside 32-bit
    // device offsets (2^31 texels = 8 GiB).
    const uint64_t limit = std::min<uint64_t>(opt_.max_bytes / 4, uint64_t(1) << 31);
    const uint64_t left = limit > texel_total_ ? limit - texel_total_ : 0;
    DecodedImage d = decode_texture_image(bytes, sniff_image_format(bytes.data(), bytes.size()),
                                          left, file_, what);
    texel_total_ += d.texels.size();
    t.name = what;
    t.width = d.width;
    t.height = d.height;
    t.texels = std::move(d.texels);
    return t;
}

std::vector<unsigned char> GltfTextureReader::image_bytes(int index, const std::string& what) const {
    const tinygltf::Image& image = model_.images[index];
    if (image.bufferView >= 0) {
        if (static_cast<size_t>(image.bufferView) >= model_.bufferViews.size())
            scene_fail(file_, what, ": bufferView ", image.bufferView, " does not exist");
        const tinygltf::BufferView& view = model_.bufferViews[image.bufferView];
        if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model_.buffers.size())
            scene_fail(file_, what, ": bufferView ", image.bufferView, " refers to missing buffer ",
                       view.buffer);
        const std::vector<unsigned char>& data = model_.buffers[view.buffer].data;
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
            scene_fail(file_, what, ": bufferView ", image.bufferView, " (bytes ", view.byteOffset,
                       " + ", view.byteLength, ") exceeds buffer ", view.buffer, " (", data.size(),
                       " bytes)");
        return std::vector<unsigned char>(data.begin() + view.byteOffset,
                                          data.begin() + view.byteOffset + view.byteLength);
    }
    if (!image.image.empty()) return image.image;  // a data: URI, decoded by tinygltf
    if (image.uri.empty()) scene_fail(file_, what, ": has neither a uri nor a bufferView");
    if (image.uri.compare(0, 5, "data:") == 0)
        scene_fail(file_, what, ": data URI \"", image.uri.substr(0, std::min<size_t>(40, image.uri.find(','))),
                   "...\" is not a base64 PNG or JPEG");
    const std::string name = percent_decode(image.uri);
    const std::string path = !name.empty() && name[0] == '/' ? name : directory_ + "/" + name;
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        scene_fail(file_, what, ": cannot open the image file ", path, " (it does not exist)");
    // A directory, FIFO or device would open and then fail oddly or block: refuse them up front.
    if (!std::filesystem::is_regular_file(status))
        scene_fail(file_, what, ": the image file ", path, " is not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) scene_fail(file_, what, ": cannot open the image file ", path);
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    // A file larger than the limit is refused unread.
    if (size <= 0) scene_fail(file_, what, ": the image file ", path, " is empty");
    if (static_cast<uint64_t>(size) > opt_.max_bytes)
        scene_fail(file_, what, ": the image file ", path, " (", size, " bytes) exceeds the memory limit");
    std::vector<unsigned char> bytes(static_cast<size_t>(size));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), size);
    if (in.gcount() != size) scene_fail(file_, what, ": read error in ", path);
    return bytes;
}

}  // namespace ht
