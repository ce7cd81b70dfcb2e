// What a scene needs from the kernels, as build options: features the scene lacks are compiled
// out, so the shading kernel carries no code for lights, models or lobes it never uses.
#pragma once

#include "kernels/features.h"
#include "render/memory_plan.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// The kernels' feature switches, one per entry of HT_FEATURE_SWITCHES (kernels/features.h).
enum class Feature {
#define HT_FEATURE_ENUM(name, meaning) name,
    HT_FEATURE_SWITCHES(HT_FEATURE_ENUM)
#undef HT_FEATURE_ENUM
    Count
};
constexpr size_t kFeatureCount = size_t(Feature::Count);

// "HT_FEATURE_LIGHT_SPOT", and what it switches ("spot lights").
const char* feature_define(Feature f);
const char* feature_meaning(Feature f);
// The switch of fibre model HT_MODEL_* m.
Feature model_feature(uint32_t m);

struct KernelFeatures {
    // Everything out but the lobes, which are out only when negligible for every material
    // (lobe_bounds); lobe_why says which material kept each of TT and TRT, or why not.
    KernelFeatures();
    bool on[kFeatureCount];
    bool& operator[](Feature f) { return on[size_t(f)]; }
    bool operator[](Feature f) const { return on[size_t(f)]; }
    std::string lobe_why[2];
    GeometryPaging paging;  // geometry in several buffers per array
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

// The estimator's value defines (kernels/features.h): --clamp-indirect C (0: off), --regularize
// DEG (0: off), --light-threshold T (0: off), --spawn-offset pbrt, --sampler sobol, --light-pick
// importance (for a scene with 2..HT_LIGHT_PICK_MAX lights), --light-guiding F (0: off, and off for
// a scene without lights), --light-vertices (on or off); "" when everything is off.
std::string estimator_build_options(float clamp_indirect, float regularize_deg, float light_threshold,
                                    bool spawn_offset_pbrt, bool sampler_sobol, bool light_pick_importance = false,
                                    float light_guiding = 0.0f, bool light_vertices = false);

// One line per chosen feature, for --verbose.
std::vector<std::string> describe_features(const KernelFeatures& f);

}  // namespace ht
