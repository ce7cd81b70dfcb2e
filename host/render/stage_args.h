// The host side of the stage kernels' argument bundles (kernels/stages/stage_args.h): one struct
// per bundle, the names in the kernels' order declared once here, and one template that sets any
// bundle (tests/render/stage_args_test.cpp compares the names with the compiled kernels').
#pragma once

#include "kernels/types.h"

#include <CL/opencl.hpp>

#include <string>
#include <vector>

namespace ht {

// HT_SCENE_PARAMS: the scene's shading data on one device.
struct SceneBuffers {
    cl::Buffer textures;
    cl_uint texture_count = 0;
    cl::Buffer texels, strand_material, materials, lights;
    cl_uint light_count = 0;
    HtEnvironment environment{};
    cl::Buffer env_texels, env_marginal, env_conditional;
};

// Calls f(name, value) for each argument of the bundle, in the kernels' order.
template <typename F>
void for_each_arg(const SceneBuffers& s, F&& f) {
    f("textures", s.textures);
    f("texture_count", s.texture_count);
    f("texels", s.texels);
    f("strand_material", s.strand_material);
    f("materials", s.materials);
    f("lights", s.lights);
    f("light_count", s.light_count);
    f("env", s.environment);
    f("env_texels", s.env_texels);
    f("env_marginal", s.env_marginal);
    f("env_conditional", s.env_conditional);
}

// HT_SHADE_QUEUE_PARAMS: one bounce's queues.
struct ShadeQueue {
    cl::Buffer rays, hits, ray_path;
    cl_uint count = 0;
    cl::Buffer paths, shadow_rays, shadow_contrib, stage_rays, stage_path, counters;
};

template <typename F>
void for_each_arg(const ShadeQueue& q, F&& f) {
    f("rays", q.rays);
    f("hits", q.hits);
    f("ray_path", q.ray_path);
    f("count", q.count);
    f("paths", q.paths);
    f("shadow_rays", q.shadow_rays);
    f("shadow_contrib", q.shadow_contrib);
    f("stage_rays", q.stage_rays);
    f("stage_path", q.stage_path);
    f("counters", q.counters);
}

// HT_PATH_GRID_PARAMS: the path rays' grid (render/path_grid.h) on the device, for the stages that
// walk it (features[PATH_GRID]).
struct PathGridBuffers {
    cl::Buffer cells, entries;
    HtPathGrid grid{};
};

template <typename F>
void for_each_arg(const PathGridBuffers& g, F&& f) {
    f("grid_cells", g.cells);
    f("grid_entries", g.entries);
    f("grid", g.grid);
}

// Sets a bundle (any struct above) from argument index a on; returns the next free index.
template <typename Bundle>
cl_uint set_bundle_args(cl::Kernel& k, cl_uint a, const Bundle& b) {
    for_each_arg(b, [&](const char*, const auto& value) { k.setArg(a++, value); });
    return a;
}

// A bundle's argument names, in order.
template <typename Bundle>
std::vector<std::string> bundle_arg_names() {
    std::vector<std::string> names;
    for_each_arg(Bundle{}, [&](const char* name, const auto&) { names.push_back(name); });
    return names;
}

}  // namespace ht
