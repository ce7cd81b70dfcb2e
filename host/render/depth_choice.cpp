#include "render/depth_choice.h"

#include "fiber/afs_quadrature.h"
#include "fiber/material.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ht {

DepthChoice choose_max_depth(const Scene& scene) {
    DepthChoice best;
    best.why = "no material transmits light forward";
    double worst_tt = -1;
    std::string worst_name;
    for (const HairMaterialDesc& d : scene.materials) {
        double tt;
        if (d.model == "kajiya") {
            // Kajiya-Kay has no transmission; its diffuse albedo stands in for the forward share.
            tt = std::max({d.kd[0], d.kd[1], d.kd[2]});
        } else {
            HtMaterial m = make_kernel_material(d);  // validated sigma_a (from melanin or colour too)
            tt = 0;
            for (int c = 0; c < 3; ++c) tt = std::max(tt, afs_reference(m.eta, m.sigma_a[c], 0.0).TT);
        }
        if (tt > worst_tt) worst_tt = tt, worst_name = d.name;
    }
    if (worst_tt <= 0) return best;
    int depth = 1;
    double share = worst_tt;
    while (share >= kDepthThreshold && depth < kMaxAutoDepth) {
        ++depth;
        share *= worst_tt;
    }
    best.depth = depth;
    char line[256];
    std::snprintf(line, sizeof line,
                  "max depth %d: AFS_TT^avg(theta=0) = %.3f for material '%s' (most transmissive channel); "
                  "%.3f^%d = %.3f < %.2f%s",
                  depth, worst_tt, worst_name.c_str(), worst_tt, depth, share, kDepthThreshold,
                  depth == kMaxAutoDepth ? " (capped)" : "");
    best.why = line;
    return best;
}

}  // namespace ht
