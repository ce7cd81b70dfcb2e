// Environment light tables for the kernels: radiance texels and the CDFs that importance-sample
// them (kernels/environment.h).
#pragma once

#include "kernels/types.h"
#include "scene/scene.h"

#include <vector>

namespace ht {

struct EnvironmentTables {
    HtEnvironment header{};
    std::vector<float> texels;       // 4 floats per pixel
    std::vector<float> marginal;     // height + 1
    std::vector<float> conditional;  // height * (width + 1)
};

// Loads env.map_path through OpenImageIO when set (throws SceneError naming the file on
// failure or on negative / non-finite texels).  A disabled environment gives enabled = 0.
EnvironmentTables build_environment(const Environment& env);

// The tables for an rgb lat-long image (3 floats per pixel, row 0 at the zenith).
EnvironmentTables build_environment_from_rgb(int width, int height, const std::vector<float>& rgb,
                                             float intensity, const std::string& name);

}  // namespace ht
