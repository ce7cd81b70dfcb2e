#include "render/features.h"

#include "bvh/device_geometry.h"
#include "cl/device.h"
#include "fiber/afs_quadrature.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace ht {

namespace {
const char* kModelNames[4] = {"kajiya", "marschner", "zinke", "chiang"};

struct FeatureNames {
    const char* define;
    const char* meaning;
};
const FeatureNames kFeatureNames[kFeatureCount] = {
#define HT_FEATURE_NAMES(name, meaning) {"HT_FEATURE_" #name, meaning},
    HT_FEATURE_SWITCHES(HT_FEATURE_NAMES)
#undef HT_FEATURE_NAMES
};

int model_index(const std::string& name) {
    for (int i = 0; i < 4; ++i)
        if (name == kModelNames[i]) return i;
    return -1;
}
}  // namespace

// Why these bounds hold (docs/MODEL.md §4, §6-7):
//  * Every TT/TRT term carries the chord transmittance T(h, theta)^p (p internal chords; the TRT
//    glint T(h_c)^2), and the chord 2 cos gamma_t / cos theta_t >= l_min = 2 sqrt(1 - 1/eta^2)
//    because eta' >= eta (so sin gamma_t = h/eta' <= 1/eta) and cos theta_t <= 1.  Hence, pointwise
//    in (h, theta), term(sigma_a) <= exp(-p sigma_min l_min) term(sigma_a = 0), with sigma_min the
//    smallest channel: the chords that shrink toward |h| -> 1 and grazing angles are all covered.
//  * The absorption-free factor G_p (Fresnel; for marschner's TRT also the glint) does not depend
//    on sigma_a; it is maximised numerically with the kernels' own ht_zinke_w (zinke's W_p) and
//    ht_marschner_ap on a 181 (theta_d) x 401 (h) grid and doubled: these are smooth functions of
//    (theta, h), so the grid maximum is within a few percent of the true one and the factor 2 is a
//    wide margin.  For marschner the lobe energy is the h-average of A_p (<= max A_p) plus, for
//    TRT, the glint's 2 t k_G A(h_c) dh (its caustic removal only lowers it), all included in G_p.
//    Taking the max of W_p and A_p keeps the bound valid whichever weight zinke uses (A_p S'_p
//    before main's 830c9cf, A_p after).
//  * Chiang's lobes are normalised (M_p and N_p integrate to 1), so the energy of lobe p is A_p:
//    TT <= T_max, TRT <= (4/27) T_max^2 (max of F (1 - F)^2 is 4/27), residual
//    A_TRT F T/(1 - F T) <= (4/27) T_max^3 / (1 - T_max).
//  * Eccentric fibres (a < 1): marschner's TRT uses eta*(phi_h) in [min(e1, e2), max(e1, e2)]
//    (linear in cos 2 phi_h), which may be below eta.  Bounded without the grid: F (1 - F)^2 <=
//    4/27 for every index and the glint adds at most 2 k_G (4/27) dh_M, with the chord bound at the
//    smallest eta*: (4/27)(1 + 2 k_G dh_M) exp(-2 sigma_min l_min(eta*_min)).
const char* feature_define(Feature f) { return kFeatureNames[size_t(f)].define; }
const char* feature_meaning(Feature f) { return kFeatureNames[size_t(f)].meaning; }

Feature model_feature(uint32_t m) {
    static_assert(uint32_t(Feature::MODEL_MARSCHNER) - uint32_t(Feature::MODEL_KAJIYA) == HT_MODEL_MARSCHNER &&
                      uint32_t(Feature::MODEL_ZINKE) - uint32_t(Feature::MODEL_KAJIYA) == HT_MODEL_ZINKE &&
                      uint32_t(Feature::MODEL_CHIANG) - uint32_t(Feature::MODEL_KAJIYA) == HT_MODEL_CHIANG,
                  "the model switches follow HT_MODEL_* order");
    return Feature(uint32_t(Feature::MODEL_KAJIYA) + m);
}

KernelFeatures::KernelFeatures() {
    for (bool& b : on) b = false;
    (*this)[Feature::LOBE_TT] = (*this)[Feature::LOBE_TRT] = true;
}

LobeBounds lobe_bounds(const HairMaterialDesc& d) {
    LobeBounds b;
    if (d.model == "kajiya") return b;
    const HtMaterial m = make_kernel_material(d);
    const double eta = m.eta;
    const double sigma_min = std::min({double(m.sigma_a[0]), double(m.sigma_a[1]), double(m.sigma_a[2])});
    const double l_min = 2.0 * std::sqrt(std::max(0.0, 1.0 - 1.0 / (eta * eta)));
    const double t_max = std::exp(-sigma_min * l_min);
    b.r_ref = afs_reference(eta, 0.0, 0.0).R;
    b.bound[0] = std::numeric_limits<double>::infinity();
    if (d.model == "chiang") {
        b.bound[1] = t_max;
        b.bound[2] = 4.0 / 27.0 * t_max * t_max * (1.0 + t_max / std::max(1.0 - t_max, 1e-300));
        return b;
    }
    HtMaterial clear = m;  // G_p: the same material without absorption
    for (int c = 0; c < 4; ++c) clear.sigma_a[c] = 0.0f;
    double g[3] = {0, 0, 0}, glint = 0;
    const int nt = 181, nh = 401;
    for (int i = 0; i < nt; ++i) {
        const double theta = (HT_HALF_PI - 1e-4) * i / (nt - 1);
        const double sd = std::sin(theta), cd = std::cos(theta);
        for (int j = 0; j < nh; ++j) {
            const double h = double(j) / (nh - 1);
            real3 w[3];
            real phis[3];
            ht_zinke_w(&clear, h, sd, cd, w, phis);
            for (int p = 1; p < 3; ++p) {
                const real3 a = ht_marschner_ap(&clear, p, h, eta, sd, cd);
                g[p] = std::max({g[p], w[p].x, w[p].y, w[p].z, a.x, a.y, a.z});
            }
        }
        // marschner's glint energy: integral over phi of t k_G A(h_c) dh (g_c(+) + g_c(-))
        real phi_c, dh, t, hc;
        ht_marschner_caustic(&clear, ht_inv_eta_prime(eta, sd, cd), &phi_c, &dh, &t, &hc);
        const real3 ac = ht_marschner_ap(&clear, 2, hc, eta, sd, cd);
        glint = std::max(glint, 2.0 * t * clear.caustic_kg * dh * std::max({ac.x, ac.y, ac.z}));
    }
    b.bound[1] = 2.0 * g[1] * t_max;
    b.bound[2] = 2.0 * (g[2] + glint) * t_max * t_max;
    if (m.eccentricity < 1.0f) {
        const double eta_lo = std::min({eta, double(ht_marschner_eta_star(&m, 1.0)), double(ht_marschner_eta_star(&m, -1.0))});
        const double t_ecc = std::exp(-sigma_min * 2.0 * std::sqrt(std::max(0.0, 1.0 - 1.0 / (eta_lo * eta_lo))));
        b.bound[2] = std::max(b.bound[2], 4.0 / 27.0 * (1.0 + 2.0 * m.caustic_kg * m.caustic_dhm) * t_ecc * t_ecc);
    }
    return b;
}

KernelFeatures scene_features(const Scene& scene, uint32_t fiber_field, bool indirect_afs, FeatureMode mode) {
    KernelFeatures f;
    f[Feature::INDIRECT_AFS] = indirect_afs;
    for (const Mesh& m : scene.meshes) {
        if (m.triangle_count() == 0) continue;
        f[Feature::MESHES] = true;
        // build_geometry textures exactly these triangles (a textured material and coordinates).
        const bool textured = m.material < scene.surface_materials.size() &&
                              scene.surface_materials[m.material].texture >= 0 && !m.uvs.empty();
        f[Feature::TEXTURES] = f[Feature::TEXTURES] || textured;
    }
    for (const Light& l : scene.lights) {
        switch (l.type) {
        case LightType::Point: break;  // the code all positional lights share
        case LightType::Spot: f[Feature::LIGHT_SPOT] = true; break;
        case LightType::Directional: f[Feature::LIGHT_DIRECTIONAL] = true; break;
        case LightType::Sphere: f[Feature::LIGHT_SPHERE] = true; break;
        }
    }
    if (scene.materials.empty()) f[model_feature(uint32_t(model_index(HairMaterialDesc{}.model)))] = true;
    for (const auto& m : scene.materials) {
        int i = model_index(m.model);
        if (i >= 0) f[model_feature(uint32_t(i))] = true;
    }
    if (fiber_field != HT_FIELD_MATERIAL && (f[Feature::MODEL_MARSCHNER] || f[Feature::MODEL_ZINKE])) {
        f[Feature::MODEL_MARSCHNER] = fiber_field != HT_FIELD_NEAR;
        f[Feature::MODEL_ZINKE] = fiber_field != HT_FIELD_FAR;
    }
    // Lobes: in unless negligible for every material that uses them.  The bound covers marschner
    // and zinke alike, so --fiber-field (which swaps the two) cannot change the choice; --model
    // has already been applied to scene.materials.
    std::vector<HairMaterialDesc> mats = scene.materials;
    if (mats.empty()) mats.push_back(HairMaterialDesc{});
    bool any = false;
    f[Feature::LOBE_TT] = f[Feature::LOBE_TRT] = false;
    for (const HairMaterialDesc& d : mats) {
        if (d.model == "kajiya") continue;
        any = true;
        const LobeBounds b = lobe_bounds(d);
        for (int k = 0; k < 2; ++k) {
            bool& on = f[k == 0 ? Feature::LOBE_TT : Feature::LOBE_TRT];
            const double limit = kLobeThreshold * b.r_ref;
            char line[200];
            std::snprintf(line, sizeof line, "material '%s' (%s): bound %.3g %s %.0e x AFS_R^avg(0) = %.3g",
                          d.name.c_str(), d.model.c_str(), b.bound[k + 1], b.bound[k + 1] < limit ? "<" : ">=",
                          kLobeThreshold, limit);
            if (!(b.bound[k + 1] < limit)) {
                if (!on) f.lobe_why[k] = line;  // the first material that keeps it
                on = true;
            } else if (f.lobe_why[k].empty()) {
                f.lobe_why[k] = line;
            }
        }
    }
    if (!any) f[Feature::LOBE_TT] = f[Feature::LOBE_TRT] = true;  // only kajiya: the flags change nothing
    if (mode == FeatureMode::All || mode == FeatureMode::AllLobes) {
        f[Feature::LOBE_TT] = f[Feature::LOBE_TRT] = true;
        f.lobe_why[0] = f.lobe_why[1] = "forced in (--features)";
    }
    if (mode == FeatureMode::All) {
        const bool afs = f[Feature::INDIRECT_AFS];  // a stage the settings ask for, not a scene feature
        for (bool& on : f.on) on = true;
        f[Feature::INDIRECT_AFS] = afs;
        f[Feature::INDIRECT_DUAL] = false;  // settings too: prepare_scene sets them
        f[Feature::AOVS] = false;
    }
    return f;
}

std::string kernel_build_options(const Scene& scene, uint32_t fiber_field, bool indirect_afs, FeatureMode mode) {
    return kernel_build_options(scene_features(scene, fiber_field, indirect_afs, mode));
}

std::string kernel_build_options(const KernelFeatures& f) {
    std::string o = base_kernel_options();
    for (size_t i = 0; i < kFeatureCount; ++i)
        o += std::string(" -D") + kFeatureNames[i].define + "=" + (f.on[i] ? "1" : "0");
    o += geometry_page_options(f.paging);
    return o;
}

std::string estimator_build_options(float clamp_indirect, float regularize_deg, float light_threshold,
                                    bool spawn_offset_pbrt, bool sampler_sobol, bool light_pick_importance,
                                    float light_guiding, bool light_vertices) {
    auto float_define = [](const char* name, double v) {
        char def[80];
        std::snprintf(def, sizeof def, " -D%s=%.9ef", name, v);
        return std::string(def);
    };
    std::string o;
    if (clamp_indirect > 0) o += float_define("HT_CLAMP_INDIRECT", clamp_indirect);
    if (regularize_deg > 0) o += float_define("HT_REGULARIZE_WIDTH", regularize_deg * HT_PI / 180.0);
    if (light_threshold > 0) o += float_define("HT_LIGHT_THRESHOLD", light_threshold);
    if (spawn_offset_pbrt) o += " -DHT_SPAWN_PBRT=1";
    if (sampler_sobol) o += " -DHT_SAMPLER_SOBOL=1";
    if (light_pick_importance) o += " -DHT_LIGHT_PICK_IMPORTANCE=1";
    if (light_guiding > 0) o += float_define("HT_LIGHT_GUIDE", light_guiding);
    if (light_vertices) o += " -DHT_LIGHT_VERTICES=1";
    return o;
}

std::vector<std::string> describe_features(const KernelFeatures& f) {
    std::vector<std::string> out;
    for (size_t i = 0; i < kFeatureCount; ++i) {
        out.push_back(std::string(kFeatureNames[i].meaning) + (f.on[i] ? ": compiled in" : ": compiled out"));
        const Feature id = Feature(i);
        if (id == Feature::LOBE_TT || id == Feature::LOBE_TRT) {
            const std::string& why = f.lobe_why[id == Feature::LOBE_TT ? 0 : 1];
            if (!why.empty()) out.back() += " (" + why + ")";
        }
    }
    out.push_back(f.paging.pages > 1 ? "geometry: " + std::to_string(f.paging.pages) + " buffers per array of " +
                                           format_bytes(f.paging.page_bytes()) + " (paged: larger than one allocation)"
                                     : std::string("geometry: one buffer per array"));
    return out;
}

}  // namespace ht
