// Scene description -> the kernels' layouts (camera, lights, materials, texture headers).
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <vector>

namespace ht {

HtCamera make_kernel_camera(const Camera& cam, int width, int height);
std::vector<HtLight> make_kernel_lights(const std::vector<Light>& lights);
std::vector<HtMaterial> make_kernel_materials(const std::vector<HairMaterialDesc>& materials);
// One header per texture; the shared texel buffer holds the sRGB decode table
// (HT_SRGB_TABLE_SIZE entries, kernels/surface/texture.h) and then each texture's texels in
// turn, so the renderer copies each texture to the device at its header's offset (no
// concatenated copy on the host).
std::vector<HtTexture> make_kernel_textures(const std::vector<Texture>& textures);
// The shared buffer's size in uint32: the table and the texels of all textures.
uint64_t texel_buffer_size(const std::vector<Texture>& textures);

}  // namespace ht
