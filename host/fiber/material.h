// HairMaterialDesc (user-facing, degrees, melanin/colour) -> HtMaterial (kernel layout, radians,
// sigma_a, derived quantities).  The only place where hair parameters are validated.
#pragma once

#include <array>
#include <string>

#include "scene/scene.h"
#include "kernels/types.h"

namespace ht {

// Validates every parameter of `d` and converts it.  Throws SceneError("material 'NAME': PARAM = X
// is outside [LO, HI]" or similar) on the first bad parameter; never clamps silently.
HtMaterial make_kernel_material(const HairMaterialDesc& d);

// Model name <-> HT_MODEL_* (throws SceneError for an unknown name).
uint32_t model_from_name(const std::string& name);
const char* model_name(uint32_t model);

// Chiang/pbrt roughness mappings (docs/MODEL.md §11).
double chiang_v_from_beta_m(double beta_m);   // (0.726 b + 0.812 b^2 + 3.7 b^20)^2
double chiang_s_from_beta_n(double beta_n);   // sqrt(pi/8) (0.265 b + 1.194 b^2 + 5.372 b^22)
// sigma_a from melanin concentrations (pbrt coefficients) and from a target colour (Chiang 2016).
std::array<double, 3> sigma_a_from_melanin(double eumelanin, double pheomelanin);
std::array<double, 3> sigma_a_from_color(const std::array<double, 3>& color, double beta_n);
// Kajiya-Kay specular normaliser 1 / (2 pi int_{-pi/2}^{pi/2} cos^{p+1}).
double kajiya_ks_norm(double exponent);

}  // namespace ht
