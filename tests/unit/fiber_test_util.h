// Shared helpers of the fibre tests (header only: the test globs take *.cpp).
#pragma once

#include "fiber/furnace.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fibertest {

inline ht::HairMaterialDesc white(const std::string& model, double bm, double bn) {
    ht::HairMaterialDesc d;
    d.model = model;
    d.has_sigma_a = true;
    d.sigma_a = {0.f, 0.f, 0.f};
    d.beta_m = (float)bm;
    d.beta_n = (float)bn;
    d.alpha_deg = 0.f;
    d.alpha_r_deg = 0.f;
    return d;
}

inline real3 wo_at(double theta_deg) {
    double t = theta_deg * HT_PI / 180.0;
    return make_real3(std::sin(t), 0.0, std::cos(t));  // renderer convention: phi_o = pi/2
}

inline real3 dir(double theta, double phi) {
    return make_real3(std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi));
}

inline double albedo_at(const HtMaterial& m, real3 wo, double h, int c = 0, double refine = 1.0) {
    return ht::furnace_albedo_at(m, wo.x, wo.y, wo.z, h, c, refine);
}
inline double albedo(const HtMaterial& m, double theta_o_deg, int nh, int c = 0) {
    return ht::furnace_albedo(m, theta_o_deg, nh, c);
}

}  // namespace fibertest
