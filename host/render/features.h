// What a scene needs from the kernels, as build options: features the scene lacks are compiled
// out, so the shading kernel carries no code for lights, models or lobes it never uses.
#pragma once

#include "render/memory_plan.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

struct KernelFeatures {
    bool light_point = false, light_spot = false, light_directional = false, light_sphere = false;
    bool model[4] = {false, false, false, false};  // indexed by HT_MODEL_*
    bool indirect_afs = false;                      // translucent AFS shadow rays (--indirect afs)
    bool meshes = false;                            // triangle surfaces in the BVH and in shade
    GeometryPaging paging;                          // geometry in several buffers per array
};

// fiber_field (HT_FIELD_*): anything but "the material's model" may swap marschner and zinke.
KernelFeatures scene_features(const Scene& scene, uint32_t fiber_field = 0, bool indirect_afs = false);

// "-cl-std=CL1.2 ... -DHT_FEATURE_..=1": the options the render program is built with.
// paging: how upload_geometry cut the scene's arrays (it depends on the device, not the scene).
std::string kernel_build_options(const Scene& scene, uint32_t fiber_field = 0, bool indirect_afs = false,
                                 const GeometryPaging& paging = {});

// One line per chosen feature, for --verbose.
std::vector<std::string> describe_features(const KernelFeatures& f);

}  // namespace ht
