// Which fibre lobes the render program keeps (host/render/features.cpp): the bound of each lobe's
// energy against kLobeThreshold x the material's R energy, for every material of the scene.
#include <gtest/gtest.h>

#include "fiber/afs_quadrature.h"
#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"
#include "render/features.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace ht;

namespace {
HairMaterialDesc hair(const std::string& model, Vec3f sigma_a) {
    HairMaterialDesc d;
    d.model = model;
    d.has_sigma_a = true;
    d.sigma_a = sigma_a;
    return d;
}
Scene with(std::initializer_list<HairMaterialDesc> mats) {
    Scene s;
    for (auto& m : mats) s.materials.push_back(m);
    return s;
}
const Vec3f kBlond{0.06f, 0.10f, 0.20f}, kBlack{8.0f, 10.0f, 12.0f};
}  // namespace

TEST(FeaturesLobes, BlondKeepsEveryLobeForEveryModel) {
    for (const char* model : {"marschner", "zinke", "chiang"}) {
        KernelFeatures f = scene_features(with({hair(model, kBlond)}));
        EXPECT_TRUE(f[Feature::LOBE_TT] && f[Feature::LOBE_TRT]) << model;
    }
}

TEST(FeaturesLobes, VeryDarkHairDropsTTAndTRT) {
    for (const char* model : {"marschner", "zinke", "chiang"}) {
        for (uint32_t field : {HT_FIELD_MATERIAL, HT_FIELD_NEAR, HT_FIELD_FAR, HT_FIELD_AUTO}) {
            KernelFeatures f = scene_features(with({hair(model, kBlack)}), field);
            EXPECT_FALSE(f[Feature::LOBE_TT]) << model;
            EXPECT_FALSE(f[Feature::LOBE_TRT]) << model;
        }
        std::string opts = kernel_build_options(with({hair(model, kBlack)}));
        EXPECT_NE(opts.find("-DHT_FEATURE_LOBE_TT=0"), std::string::npos);
        EXPECT_NE(opts.find("-DHT_FEATURE_LOBE_TRT=0"), std::string::npos);
        // forced in for A/B comparisons
        for (FeatureMode mode : {FeatureMode::All, FeatureMode::AllLobes}) {
            KernelFeatures f = scene_features(with({hair(model, kBlack)}), 0, false, mode);
            EXPECT_TRUE(f[Feature::LOBE_TT] && f[Feature::LOBE_TRT]);
        }
    }
}

TEST(FeaturesLobes, OneMaterialThatNeedsALobeKeepsIt) {
    KernelFeatures f = scene_features(with({hair("zinke", kBlack), hair("marschner", kBlond)}));
    EXPECT_TRUE(f[Feature::LOBE_TT] && f[Feature::LOBE_TRT]);
    // realistic black hair (eumelanin 8, pbrt's conversion: sigma_a ~ 3.4, 5.6, 11 per radius):
    // the red channel still transmits through the thin chords near |h| = 1, so TT stays
    HairMaterialDesc d;
    d.model = "zinke";
    d.has_melanin = true;
    d.eumelanin = 8;
    EXPECT_TRUE(scene_features(with({d}))[Feature::LOBE_TT]);
    // kajiya has no such lobes: it neither keeps nor drops them
    f = scene_features(with({hair("zinke", kBlack), hair("kajiya", kBlond)}));
    EXPECT_FALSE(f[Feature::LOBE_TT] || f[Feature::LOBE_TRT]);
    f = scene_features(with({hair("kajiya", kBlond)}));
    EXPECT_TRUE(f[Feature::LOBE_TT] && f[Feature::LOBE_TRT]);  // nothing to decide: the default
    // eccentric fibres: marschner's TRT uses eta* (here down to 1.24), bounded separately
    HairMaterialDesc e = hair("marschner", kBlack);
    e.eccentricity = 0.85f;
    f = scene_features(with({e}));
    EXPECT_FALSE(f[Feature::LOBE_TT] || f[Feature::LOBE_TRT]);
    e.sigma_a = kBlond;
    f = scene_features(with({e}));
    EXPECT_TRUE(f[Feature::LOBE_TT] && f[Feature::LOBE_TRT]);
}

TEST(FeaturesLobes, EccentricTRTBoundHoldsForEveryEtaStar) {
    // marschner's TRT with eta*(phi_h): A_TRT at every eta* in range, plus the glint energy
    for (Vec3f sa : {kBlond, Vec3f{2.0f, 3.0f, 4.0f}, kBlack}) {
        HairMaterialDesc d = hair("marschner", sa);
        d.eccentricity = 0.8f;
        const LobeBounds b = lobe_bounds(d);
        const HtMaterial m = make_kernel_material(d);
        double worst = 0;
        for (int k = 0; k <= 20; ++k) {
            const double eta_s = ht_marschner_eta_star(&m, -1.0 + k / 10.0);
            for (int i = 0; i <= 90; ++i) {
                const double theta = std::min(i * 0.999, 89.99) * HT_PI / 180;
                for (int j = 0; j <= 200; ++j) {
                    const real3 a = ht_marschner_ap(&m, 2, j / 200.0, eta_s, std::sin(theta), std::cos(theta));
                    worst = std::max({worst, a.x, a.y, a.z});
                }
            }
        }
        EXPECT_LE(worst * (1 + 2 * m.caustic_kg * m.caustic_dhm), b.bound[2]) << sa[0];
    }
}

TEST(FeaturesLobes, BoundHoldsOnADenseSampleOfTheModels) {
    // The bound must dominate the lobe's energy W_p(h) (zinke) and A_p(h) (marschner, chiang) at
    // every (theta, h), including grazing angles and |h| -> 1 where the chords are shortest.
    // Sampled on a grid offset from the bound's own grid (and at |h| = 1, theta = 89.99 deg).
    for (Vec3f sa : {kBlond, Vec3f{1.0f, 2.0f, 3.0f}, kBlack}) {
        for (float eta : {1.3f, 1.55f, 2.0f}) {
            HairMaterialDesc d = hair("zinke", sa);
            d.eta = eta;
            const LobeBounds b = lobe_bounds(d);
            const HtMaterial m = make_kernel_material(d);
            double worst[3] = {0, 0, 0};
            for (int i = 0; i <= 300; ++i) {
                const double theta = std::min(i * 0.3013, 89.99) * HT_PI / 180;
                for (int j = 0; j <= 700; ++j) {
                    const double h = std::min(1.0, j / 700.0 + 0.37e-3);
                    real3 w[3];
                    real phis[3];
                    ht_zinke_w(&m, h, std::sin(theta), std::cos(theta), w, phis);
                    for (int p = 1; p < 3; ++p) {
                        const real3 a = ht_marschner_ap(&m, p, h, m.eta, std::sin(theta), std::cos(theta));
                        worst[p] = std::max({worst[p], w[p].x, w[p].y, w[p].z, a.x, a.y, a.z});
                    }
                }
            }
            EXPECT_LE(worst[1], b.bound[1]) << "eta " << eta << " sigma " << sa[0];
            EXPECT_LE(worst[2], b.bound[2]) << "eta " << eta << " sigma " << sa[0];
            EXPECT_GT(b.r_ref, 0.0);
        }
    }
}
