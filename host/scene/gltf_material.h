// Hair material parameters stored in a glTF material's `extras` object, e.g.
//
//   "materials": [{ "name": "blond", "extras": {
//       "model": "marschner", "sigma_a": [0.06, 0.10, 0.20], "eta": 1.55,
//       "alpha_r_deg": -7.5, "beta_r_deg": 7.5, "radius": 0.1 } }]
//
// Keys are the HairMaterialDesc field names: model (kajiya | marschner | zinke | chiang),
// sigma_a [r,g,b], eumelanin, pheomelanin, color [r,g,b], eta, beta_m, beta_n, alpha_deg,
// alpha_r_deg, beta_r_deg, caustic_wc_deg, caustic_kg, caustic_deta, caustic_dhm, eccentricity,
// kd [r,g,b], ks [r,g,b], ks_exponent; plus "radius", the default fibre radius for primitives
// without a _RADIUS attribute.  When extras state no absorption (sigma_a, melanin or color) and
// the material's pbrMetallicRoughness.baseColorFactor is not the default white, its rgb is used
// as the target hair colour.  Values are only type-checked here; ranges are validated with the
// rest of the material in host/fiber/material.h.
#pragma once

#include <optional>
#include <set>
#include <string>

#include "scene/scene.h"
#include "scene/tinygltf_config.h"

namespace ht {

// Throws SceneError for a wrongly typed value or an unknown model; names of unknown keys are
// added to unknown_keys (typos should not pass silently, but also not stop a render).
HairMaterialDesc hair_material_from_gltf(const tinygltf::Material& material, int index,
                                         const std::string& file,
                                         std::set<std::string>& unknown_keys);

// The material's extras.radius if present (checked to be a number; its sign is checked later by
// the hygiene rule like every radius).
std::optional<float> gltf_material_radius(const tinygltf::Material& material, int index, const std::string& file);

}  // namespace ht
