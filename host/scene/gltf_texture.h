// glTF base colour textures: material.pbrMetallicRoughness.baseColorTexture -> texture ->
// sampler + image -> a decoded Scene::textures entry.  Images come from a file named by a
// relative URI, a base64 data: URI, or a bufferView (GLB); PNG and JPEG, decoded by
// texture_image.h.  Every index, offset and size is checked, each problem a SceneError naming
// the glTF file, the material or image and what is wrong.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/tinygltf_config.h"

namespace ht {

// tinygltf LoadImageData callback: keeps a data: URI image's decoded bytes in Image::image
// (tinygltf drops the URI text) and nothing else: bufferView images are read later with the
// bounds checks tinygltf does not make, and external files are read only when a surface
// material uses them.
bool keep_gltf_image_bytes(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                           int req_width, int req_height, const unsigned char* bytes, int size,
                           void* user_data);

class GltfTextureReader {
public:
    // directory: the glTF file's folder (relative URIs); textures: where decoded textures go.
    GltfTextureReader(const tinygltf::Model& model, const std::string& file,
                      const std::string& directory, const LoadOptions& opt,
                      std::vector<Texture>& textures);

    // The Scene::textures index of material `index`'s base colour texture, -1 without one.
    // Decodes each glTF texture once.  Throws SceneError.
    int32_t base_color_texture(const tinygltf::Material& material, int index);

    // KHR_texture_transform on base colour textures (ignored: coordinates are used as stored).
    size_t ignored_transforms() const { return ignored_transforms_; }

private:
    std::vector<unsigned char> image_bytes(int image, const std::string& what) const;
    Texture decode(int texture, const std::string& what);

    const tinygltf::Model& model_;
    const std::string& file_;
    std::string directory_;
    const LoadOptions& opt_;
    std::vector<Texture>& textures_;
    std::map<int, int32_t> decoded_;  // glTF texture index -> Scene::textures index
    uint64_t texel_total_ = 0;
    size_t ignored_transforms_ = 0;
};

}  // namespace ht
