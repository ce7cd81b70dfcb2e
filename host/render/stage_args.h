// The host side of the stage kernels' argument bundles (kernels/stages/stage_args.h): one struct
// per bundle, with the names in the kernels' order declared once beside it, set by
// cl/arg_bundle.h's set_bundle_args (tests/render/stage_args_test.cpp compares the names with the
// compiled kernels').  The path grid's bundle is bvh/path_grid_buffers.h's, which bench's tracer
// sets too.
#pragma once

#include "bvh/path_grid_buffers.h"
#include "cl/arg_bundle.h"
#include "kernels/types.h"

#include <CL/opencl.hpp>

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

}  // namespace ht
