#include "render/features.h"

#include "bvh/device_geometry.h"
#include "cl/device.h"
#include "kernels/types.h"

namespace ht {

namespace {
const char* kModelNames[4] = {"kajiya", "marschner", "zinke", "chiang"};

int model_index(const std::string& name) {
    for (int i = 0; i < 4; ++i)
        if (name == kModelNames[i]) return i;
    return -1;
}
}  // namespace

KernelFeatures scene_features(const Scene& scene, uint32_t fiber_field, bool indirect_afs) {
    KernelFeatures f;
    f.indirect_afs = indirect_afs;
    for (const Mesh& m : scene.meshes) f.meshes = f.meshes || m.triangle_count() > 0;
    for (const Light& l : scene.lights) {
        switch (l.type) {
        case LightType::Point: f.light_point = true; break;
        case LightType::Spot: f.light_spot = true; break;
        case LightType::Directional: f.light_directional = true; break;
        case LightType::Sphere: f.light_sphere = true; break;
        }
    }
    if (scene.materials.empty()) f.model[model_index(HairMaterialDesc{}.model)] = true;
    for (const auto& m : scene.materials) {
        int i = model_index(m.model);
        if (i >= 0) f.model[i] = true;
    }
    if (fiber_field != HT_FIELD_MATERIAL && (f.model[HT_MODEL_MARSCHNER] || f.model[HT_MODEL_ZINKE])) {
        f.model[HT_MODEL_MARSCHNER] = fiber_field != HT_FIELD_NEAR;
        f.model[HT_MODEL_ZINKE] = fiber_field != HT_FIELD_FAR;
    }
    return f;
}

std::string kernel_build_options(const Scene& scene, uint32_t fiber_field, bool indirect_afs,
                                 const GeometryPaging& paging) {
    KernelFeatures f = scene_features(scene, fiber_field, indirect_afs);
    f.paging = paging;
    std::string o = base_kernel_options();
    auto def = [&](const char* name, bool on) { o += std::string(" -D") + name + "=" + (on ? "1" : "0"); };
    def("HT_FEATURE_LIGHT_POINT", f.light_point);
    def("HT_FEATURE_LIGHT_SPOT", f.light_spot);
    def("HT_FEATURE_LIGHT_DIRECTIONAL", f.light_directional);
    def("HT_FEATURE_LIGHT_SPHERE", f.light_sphere);
    def("HT_FEATURE_MODEL_KAJIYA", f.model[HT_MODEL_KAJIYA]);
    def("HT_FEATURE_MODEL_MARSCHNER", f.model[HT_MODEL_MARSCHNER]);
    def("HT_FEATURE_MODEL_ZINKE", f.model[HT_MODEL_ZINKE]);
    def("HT_FEATURE_MODEL_CHIANG", f.model[HT_MODEL_CHIANG]);
    def("HT_FEATURE_INDIRECT_AFS", f.indirect_afs);
    def("HT_FEATURE_MESHES", f.meshes);
    o += geometry_page_options(f.paging);
    return o;
}

std::vector<std::string> describe_features(const KernelFeatures& f) {
    std::vector<std::string> out;
    auto add = [&](const char* what, bool on) { out.push_back(std::string(what) + (on ? ": compiled in" : ": compiled out")); };
    add("point lights", f.light_point);
    add("spot lights", f.light_spot);
    add("directional lights", f.light_directional);
    add("sphere lights", f.light_sphere);
    for (int i = 0; i < 4; ++i) add((std::string("model ") + kModelNames[i]).c_str(), f.model[i]);
    add("translucent AFS shadow rays", f.indirect_afs);
    add("triangle meshes", f.meshes);
    out.push_back(f.paging.pages > 1 ? "geometry: " + std::to_string(f.paging.pages) + " buffers per array of " +
                                           format_bytes(f.paging.page_bytes()) + " (paged: larger than one allocation)"
                                     : std::string("geometry: one buffer per array"));
    return out;
}

}  // namespace ht
