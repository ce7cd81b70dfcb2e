// Kernel argument bundles: a struct of buffers and values that several kernels take in one order,
// with a for_each_arg(bundle, f) beside it calling f(name, value) for each argument in the kernels'
// order (render/stage_args.h's bundles, bvh/path_grid_buffers.h's).  The names and order are
// declared once there; these two templates set a bundle's arguments and list its names (which
// tests/render/stage_args_test.cpp compares with the compiled kernels').
#pragma once

#include <CL/opencl.hpp>

#include <string>
#include <vector>

namespace ht {

// Sets a bundle from argument index a on; returns the next free index.
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
