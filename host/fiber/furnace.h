// Deterministic white-furnace quadrature of the fibre models: directional albedo
// a(wo, h) = integral over the sphere of value(wo, wi, h) dwi.
#pragma once

#include "kernels/types.h"

namespace ht {

// One (wo, h), one colour channel.  Composite 4-point Gauss-Legendre in theta_i (panel width <= half the
// narrowest longitudinal lobe width) x midpoint rule in phi_i (periodic; spacing <= a quarter of the
// narrowest azimuthal feature).  refine > 1 multiplies both resolutions (convergence checks).
double furnace_albedo_at(const HtMaterial& m, double wo_x, double wo_y, double wo_z, double h, int channel,
                         double refine = 1.0);

// theta_o in degrees (wo = (sin, 0, cos): phi_o = pi/2 as in the renderer), averaged over h with an
// nh-point Gauss-Legendre rule on [-1, 1].
double furnace_albedo(const HtMaterial& m, double theta_o_deg, int nh, int channel);

// Gauss-Legendre nodes/weights on [-1, 1].
void gauss_legendre(int n, double* x, double* w);

}  // namespace ht
