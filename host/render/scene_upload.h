// Scene description -> the kernels' layouts (camera, lights, materials, texture headers).
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <vector>

namespace ht {

HtCamera make_kernel_camera(const Camera& cam, int width, int height);
std::vector<HtLight> make_kernel_lights(const std::vector<Light>& lights);
std::vector<HtMaterial> make_kernel_materials(const std::vector<HairMaterialDesc>& materials);
// One header per texture; texture i's texels follow texture i-1's in the shared texel buffer,
// so the renderer copies each texture's texels to the device at its header's offset (no
// concatenated copy on the host).
std::vector<HtTexture> make_kernel_textures(const std::vector<Texture>& textures);
// Texels of all textures together (the shared buffer's size in uint32).
uint64_t total_texels(const std::vector<Texture>& textures);

}  // namespace ht
