// A fibre shading point for the host (double) tests of the path-vertex code
// (kernels/integrator/shading_point.h, kernels/integrator/light_guide.h).
#pragma once

#include "fiber/material.h"
#include "kernels/integrator/shading_point.h"

#include <cmath>

namespace fibretest {

inline HtRay ray_towards(real3 o, real3 d) {
    HtRay r;
    r.ox = float(o.x); r.oy = float(o.y); r.oz = float(o.z); r.tmin = 0;
    r.dx = float(d.x); r.dy = float(d.y); r.dz = float(d.z); r.tmax = 1e30f;
    return r;
}

// A fibre along +y through the origin, radius 0.5, sigma_a (0.2, 0.3, 0.5), hit by a ray from +z at
// offset h, as a path with `path_flags` reaches it after `bounce` scatterings.
inline HtShadingPoint fibre_point(double h, const char* model, uint path_flags = HT_PATH_FROM_CAMERA, uint bounce = 0) {
    ht::HairMaterialDesc d;
    d.model = model;
    d.has_sigma_a = true;
    d.sigma_a = {0.2f, 0.3f, 0.5f};
    HtPoint a{}, b{};
    a.y = -1; b.y = 1;
    a.r = b.r = 0.5f;
    const double r = 0.5, x = h * r, z = std::sqrt(r * r - x * x);
    const HtRay ray = ray_towards(make_real3(x, 0, 10), make_real3(0, 0, -1));
    HtHit hit{};
    hit.t = float(10 - z);
    hit.u = 0.5f;
    hit.h = float(h);
    hit.tx = 0; hit.ty = 1; hit.tz = 0;
    hit.radius = float(r);
    HtShadingPoint sp;
    ht_fibre_point(ht::make_kernel_material(d), a, b, &ray, &hit, path_flags, bounce, HT_FIELD_MATERIAL, 0.001, &sp);
    return sp;
}

}  // namespace fibretest
