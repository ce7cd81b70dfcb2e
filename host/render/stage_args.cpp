#include "render/stage_args.h"

namespace ht {

namespace {
struct ArgSetter {
    cl::Kernel& k;
    cl_uint a;
    template <typename T>
    void operator()(const char*, const T& value) { k.setArg(a++, value); }
};
struct NameList {
    std::vector<std::string> names;
    template <typename T>
    void operator()(const char* name, const T&) { names.push_back(name); }
};
}  // namespace

cl_uint set_scene_args(cl::Kernel& k, cl_uint a, const SceneBuffers& s) {
    ArgSetter set{k, a};
    for_each_scene_arg(s, set);
    return set.a;
}

cl_uint set_shade_queue_args(cl::Kernel& k, cl_uint a, const ShadeQueue& q) {
    ArgSetter set{k, a};
    for_each_shade_queue_arg(q, set);
    return set.a;
}

std::vector<std::string> scene_arg_names() {
    NameList n;
    for_each_scene_arg(SceneBuffers{}, n);
    return n.names;
}

std::vector<std::string> shade_queue_arg_names() {
    NameList n;
    for_each_shade_queue_arg(ShadeQueue{}, n);
    return n.names;
}

}  // namespace ht
