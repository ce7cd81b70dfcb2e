// Scene description -> the kernels' layouts (camera, lights, materials).
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <vector>

namespace ht {

HtCamera make_kernel_camera(const Camera& cam, int width, int height);
std::vector<HtLight> make_kernel_lights(const std::vector<Light>& lights);
std::vector<HtMaterial> make_kernel_materials(const std::vector<HairMaterialDesc>& materials);

}  // namespace ht
