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

int model_index(const std::string& name) {
    for (int i = 0; i < 4; ++i)
        if (name == kModelNames[i]) return i;
    return -1;
}
}  // namespace

// Why these bounds hold (MODEL_NOTES §4, §6-7):
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
    f.indirect_afs = indirect_afs;
    for (const Mesh& m : scene.meshes) {
        if (m.triangle_count() == 0) continue;
        f.meshes = true;
        // build_geometry textures exactly these triangles (a textured material and coordinates).
        const bool textured = m.material < scene.surface_materials.size() &&
                              scene.surface_materials[m.material].texture >= 0 && !m.uvs.empty();
        f.textures = f.textures || textured;
    }
    for (const Light& l : scene.lights) {
        switch (l.type) {
        case LightType::Point: f.light_point = true; break;
        case LightType::Spot: f.light_spot = true; break;
        case LightType::Directional: f.light_directional = true; break;
        case LightType::Sphere: f.light_sphere = true; break;
        }
    }
    if (scene.materials.empty()) f.model[model_index(HairMaterialDesc{}.model)] = true;
    for (const auto& m : scene.materials) {
        int i = model_index(m.model);
        if (i >= 0) f.model[i] = true;
    }
    if (fiber_field != HT_FIELD_MATERIAL && (f.model[HT_MODEL_MARSCHNER] || f.model[HT_MODEL_ZINKE])) {
        f.model[HT_MODEL_MARSCHNER] = fiber_field != HT_FIELD_NEAR;
        f.model[HT_MODEL_ZINKE] = fiber_field != HT_FIELD_FAR;
    }
    // Lobes: in unless negligible for every material that uses them.  The bound covers marschner
    // and zinke alike, so --fiber-field (which swaps the two) cannot change the choice; --model
    // has already been applied to scene.materials.
    std::vector<HairMaterialDesc> mats = scene.materials;
    if (mats.empty()) mats.push_back(HairMaterialDesc{});
    bool any = false;
    f.lobe_tt = f.lobe_trt = false;
    for (const HairMaterialDesc& d : mats) {
        if (d.model == "kajiya") continue;
        any = true;
        const LobeBounds b = lobe_bounds(d);
        for (int k = 0; k < 2; ++k) {
            bool& on = k == 0 ? f.lobe_tt : f.lobe_trt;
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
    if (!any) f.lobe_tt = f.lobe_trt = true;  // only kajiya: the flags change nothing, keep the default
    if (mode == FeatureMode::All || mode == FeatureMode::AllLobes) {
        f.lobe_tt = f.lobe_trt = true;
        f.lobe_why[0] = f.lobe_why[1] = "forced in (--features)";
    }
    if (mode == FeatureMode::All) {
        f.light_point = f.light_spot = f.light_directional = f.light_sphere = true;
        for (bool& m : f.model) m = true;
        f.meshes = f.textures = true;
    }
    return f;
}

std::string kernel_build_options(const Scene& scene, uint32_t fiber_field, bool indirect_afs, FeatureMode mode) {
    return kernel_build_options(scene_features(scene, fiber_field, indirect_afs, mode));
}

std::string kernel_build_options(const KernelFeatures& f) {
    std::string o = base_kernel_options();
    auto def = [&](const char* name, bool on) { o += std::string(" -D") + name + "=" + (on ? "1" : "0"); };
    def("HT_FEATURE_LIGHT_POINT", f.light_point);
    def("HT_FEATURE_LIGHT_SPOT", f.light_spot);
    def("HT_FEATURE_LIGHT_DIRECTIONAL", f.light_directional);
    def("HT_FEATURE_LIGHT_SPHERE", f.light_sphere);
    def("HT_FEATURE_MODEL_KAJIYA", f.model[HT_MODEL_KAJIYA]);
    def("HT_FEATURE_MODEL_MARSCHNER", f.model[HT_MODEL_MARSCHNER]);
    def("HT_FEATURE_MODEL_ZINKE", f.model[HT_MODEL_ZINKE]);
    def("HT_FEATURE_MODEL_CHIANG", f.model[HT_MODEL_CHIANG]);
    def("HT_FEATURE_INDIRECT_AFS", f.indirect_afs);
    def("HT_FEATURE_MESHES", f.meshes);
    def("HT_FEATURE_TEXTURES", f.textures);
    def("HT_FEATURE_LOBE_TT", f.lobe_tt);
    def("HT_FEATURE_LOBE_TRT", f.lobe_trt);
    o += geometry_page_options(f.paging);
    return o;
}

std::vector<std::string> describe_features(const KernelFeatures& f) {
    std::vector<std::string> out;
    auto add = [&](const char* what, bool on) { out.push_back(std::string(what) + (on ? ": compiled in" : ": compiled out")); };
    add("point lights", f.light_point);
    add("spot lights", f.light_spot);
    add("directional lights", f.light_directional);
    add("sphere lights", f.light_sphere);
    for (int i = 0; i < 4; ++i) add((std::string("model ") + kModelNames[i]).c_str(), f.model[i]);
    add("translucent AFS shadow rays", f.indirect_afs);
    add("triangle meshes", f.meshes);
    add("base colour textures", f.textures);
    const char* lobe[2] = {"lobe TT", "lobe TRT (chiang: + TRRT+)"};
    for (int k = 0; k < 2; ++k) {
        add(lobe[k], k == 0 ? f.lobe_tt : f.lobe_trt);
        if (!f.lobe_why[k].empty()) out.back() += " (" + f.lobe_why[k] + ")";
    }
    out.push_back(f.paging.pages > 1 ? "geometry: " + std::to_string(f.paging.pages) + " buffers per array of " +
                                           format_bytes(f.paging.page_bytes()) + " (paged: larger than one allocation)"
                                     : std::string("geometry: one buffer per array"));
    return out;
}

}  // namespace ht
