// Dual scattering tables (Zinke, Yuksel, Weber, Hauber 2008; docs/MODEL.md §13): the per-fibre
// forward/backward averages and the local back-scattering closed forms of one material, in double
// from the portable fibre functions (kernels/fiber/dual.h), and their float table for the kernels.
#pragma once

#include "kernels/types.h"

#include <vector>

namespace ht {

// One inclination theta_i, per colour channel.
struct DualValues {
    double a_f[3] = {}, a_b[3] = {};          // forward / backward attenuation (energy fractions)
    double alpha_f[3] = {}, alpha_b[3] = {};  // energy-weighted lobe shifts (theta_h, radians)
    double beta_f2[3] = {}, beta_b2[3] = {};  // energy-weighted lobe variances (theta_h, rad^2)
    double A_b[3] = {}, delta_b[3] = {}, sigma_b2[3] = {};  // local back-scattering
};

// h-quadrature resolution of the partition: midpoint rule in u = asin h with `nodes` nodes (the
// indicator [|Phi| > pi/2] makes the integrand discontinuous, so the error is O(1/nodes)).
constexpr int kDualQuadratureNodes = 2048;

DualValues dual_values(const HtMaterial& m, double theta_i, int nodes = kDualQuadratureNodes);

// The local back-scattering closed forms (the paper's geometric series in a_f, a_b) for one
// channel; fills A_b, delta_b, sigma_b2 of channel c from the a/alpha/beta of channel c.
void dual_back_scattering(DualValues& v, int c);

// N^G_p(theta_i, phi) of lobe p (kernels/fiber/dual.h), one channel.
double dual_ng(const HtMaterial& m, int p, double theta_i, double phi, int channel, int nodes = 512);

// HT_DUAL_MATERIAL_ROWS float4 rows for one material (kernels/fiber/dual.h's layout).
std::vector<float> dual_table(const HtMaterial& m);

}  // namespace ht
