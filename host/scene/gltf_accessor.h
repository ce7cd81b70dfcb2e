// Reading glTF accessors with every offset, stride and count checked against the bufferView and
// buffer they point into (tinygltf parses the JSON but does not check these), so a lying file
// gives a SceneError instead of an out-of-bounds read.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/tinygltf_config.h"

namespace ht {

// `what` names the accessor's role in messages, e.g. "mesh 0 primitive 1 POSITION".
std::vector<Vec3f> read_float_vec3_accessor(const tinygltf::Model& model, int accessor,
                                            const std::string& file, const std::string& what);
std::vector<float> read_float_scalar_accessor(const tinygltf::Model& model, int accessor,
                                              const std::string& file, const std::string& what);
// TEXCOORD_n: VEC2 of FLOAT, or of normalized UNSIGNED_BYTE / UNSIGNED_SHORT (divided by 255 /
// 65535 as the glTF spec defines); values are returned as stored (finiteness is the caller's).
std::vector<std::array<float, 2>> read_texcoord_accessor(const tinygltf::Model& model, int accessor,
                                                        const std::string& file,
                                                        const std::string& what);
// Unsigned byte / short / int indices, each checked to be < vertex_count.
std::vector<uint32_t> read_index_accessor(const tinygltf::Model& model, int accessor,
                                          size_t vertex_count, const std::string& file,
                                          const std::string& what);

}  // namespace ht
