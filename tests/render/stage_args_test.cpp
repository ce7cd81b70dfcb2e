// The argument bundles' host side (host/render/stage_args.h) names the same parameters in the same
// order as the kernels' (kernels/stages/stage_args.h): a parameter added, removed or moved on one
// side only would otherwise shift every argument after it, which OpenCL reports at best as a size
// mismatch and at worst not at all (two buffers swapped).
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/features.h"
#include "render/stage_args.h"

#include <string>
#include <vector>

namespace {

std::vector<std::string> kernel_arg_names(const cl::Kernel& k) {
    std::vector<std::string> names;
    const cl_uint n = k.getInfo<CL_KERNEL_NUM_ARGS>();
    for (cl_uint i = 0; i < n; ++i) names.push_back(k.getArgInfo<CL_KERNEL_ARG_NAME>(i));
    return names;
}

TEST(StageArgs, ShadeTakesGeometrySceneQueueAndBounceInTheHostsOrder) {
    ht::ClContext cl;
    const std::string options = ht::kernel_build_options(ht::KernelFeatures{}) + " -cl-kernel-arg-info";
    cl::Program prog = cl.build("stages/shade.cl", options);
    std::vector<std::string> expected = {"segs", "points", "tri_shading"};  // unpaged geometry
    for (const std::string& n : ht::bundle_arg_names<ht::SceneBuffers>()) expected.push_back(n);
    for (const std::string& n : ht::bundle_arg_names<ht::ShadeQueue>()) expected.push_back(n);
    expected.push_back("b");
    EXPECT_EQ(kernel_arg_names(cl::Kernel(prog, "shade")), expected);
}

// The stages that walk the path rays' grid take its bundle after their own arguments, as the
// renderer sets it (render/renderer.cpp: the path stage and the shadow stage).
TEST(StageArgs, TheGridWalkingStagesEndWithThePathGridBundle) {
    ht::ClContext cl;
    ht::KernelFeatures features;
    features[ht::Feature::PATH_GRID] = true;
    cl::Program prog = cl.build("stages/trace.cl", ht::kernel_build_options(features) + " -cl-kernel-arg-info");
    const std::vector<std::string> grid = ht::bundle_arg_names<ht::PathGridBuffers>();
    ASSERT_EQ(grid.size(), 3u);
    for (const char* stage : {"intersect_closest_paths", "intersect_shadow"}) {
        const std::vector<std::string> names = kernel_arg_names(cl::Kernel(prog, stage));
        ASSERT_GT(names.size(), grid.size()) << stage;
        EXPECT_EQ(std::vector<std::string>(names.end() - grid.size(), names.end()), grid) << stage;
    }
}

}  // namespace
