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
    bool textures = false;                          // base colour textures on those surfaces
    // Lobes of the Marschner-family and Chiang models (kernels/fiber/lobes.h): out only when
    // negligible for every material (lobe_bounds); lobe_why says which material kept it or why.
    bool lobe_tt = true, lobe_trt = true;
    std::string lobe_why[2];
    GeometryPaging paging;                          // geometry in several buffers per array
};

// Which features to compile in: what the scene needs (default), everything (A/B, debugging), or
// the scene's features with every fibre lobe kept (isolates the lobe choice).
enum class FeatureMode { Scene, All, AllLobes };

// A lobe is compiled out when its energy bound stays below this fraction of the material's R
// energy (AFS_R^avg at theta = 0, the smallest over theta) for every material (features.cpp).
constexpr double kLobeThreshold = 1e-3;

// Upper bounds, over every direction and offset h, of the energy each lobe sends out of a fibre
// hit (integral of the lobe over wi: W_p(h) for zinke, at most A_p + glint for marschner, A_p for
// chiang), for the material's most transmissive channel; r_ref = AFS_R^avg(eta, theta = 0).
// Kajiya: all 0.
struct LobeBounds {
    double bound[3] = {0, 0, 0};  // R (unused), TT, TRT (+ glint; chiang: + residual)
    double r_ref = 0;
};
LobeBounds lobe_bounds(const HairMaterialDesc& d);

// fiber_field (HT_FIELD_*): anything but "the material's model" may swap marschner and zinke.
KernelFeatures scene_features(const Scene& scene, uint32_t fiber_field = 0, bool indirect_afs = false,
                              FeatureMode mode = FeatureMode::Scene);

// "-cl-std=CL1.2 ... -DHT_FEATURE_..=1": the options the render program is built with.
// f.paging: how upload_geometry cut the scene's arrays (it depends on the device, not the scene).
std::string kernel_build_options(const KernelFeatures& f);
// The same for the features scene_features chooses (unpaged geometry).
std::string kernel_build_options(const Scene& scene, uint32_t fiber_field = 0, bool indirect_afs = false,
                                 FeatureMode mode = FeatureMode::Scene);

// One line per chosen feature, for --verbose.
std::vector<std::string> describe_features(const KernelFeatures& f);

}  // namespace ht
