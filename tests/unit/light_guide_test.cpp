// Host (double) checks of light-guided continuations (kernels/integrator/light_guide.h): the guide
// lobe is a density (it integrates to 1 and its samples have the von Mises-Fisher mean cosine),
// a guided sample's pdf is the mixture's density at the direction it returns and its weight the
// fibre's value over that density, and the guided estimate of a fibre's directional albedo equals
// the BCSDF-sampled one: the unbiasedness the renders rely on (tests/render/light_guiding_test.cpp
// checks whole images).
#include <gtest/gtest.h>

#include "fibre_point_util.h"
#include "kernels/integrator/light_guide.h"

#include <cmath>
#include <vector>

namespace {

HtLight light(uint type, double x, double y, double z) {
    HtLight l{};
    l.type = type;
    l.position[0] = float(x), l.position[1] = float(y), l.position[2] = float(z);
    // a directional light travelling down and a little sideways
    const double n = std::sqrt(0.3 * 0.3 + 1.0 + 0.2 * 0.2);
    l.direction[0] = float(0.3 / n), l.direction[1] = float(-1.0 / n), l.direction[2] = float(0.2 / n);
    l.radiance[0] = l.radiance[1] = l.radiance[2] = 5.0f;
    l.cos_outer = float(std::cos(0.4)), l.cos_inner = float(std::cos(0.3));
    return l;
}

// A fibre vertex of a path that has scattered once (fibre_point_util.h).
HtShadingPoint fibre_point(double h, const char* model) { return fibretest::fibre_point(h, model, 0u, 1u); }

// A directional light and a point light off to the side: two guide lobes.
const std::vector<HtLight>& rig() {
    static const std::vector<HtLight> r = {light(HT_LIGHT_DIRECTIONAL, 0, 0, 0), light(HT_LIGHT_POINT, 4, 1, -3)};
    return r;
}

TEST(LightGuide, TheLobeIsADensityWithTheVonMisesFisherMeanCosine) {
    const real3 mu = normalize(make_real3(0.2, -0.5, 0.8));
    // midpoint quadrature in (cos of the angle to mu, azimuth): the density depends on the first only
    double integral = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double c = -1 + 2 * (i + 0.5) / n;
        const double s = std::sqrt(1 - c * c);
        // any direction at that angle: mu rotated in a plane that contains it
        const real3 t = normalize(cross(mu, make_real3(1, 0, 0)));
        integral += ht_vmf_pdf(mu, mu * c + t * s) * HT_TWO_PI * (2.0 / n);
    }
    EXPECT_NEAR(integral, 1.0, 1e-6);
    // E[mu . w] = coth(kappa) - 1 / kappa for samples drawn by ht_vmf_sample, and every sample unit
    const double k = HT_GUIDE_KAPPA;
    double mean = 0;
    const int m = 200000;
    for (int i = 0; i < m; ++i) {
        const real3 w = ht_vmf_sample(mu, (i + 0.5) / m, std::fmod(i * 0.6180339887498949, 1.0));
        ASSERT_NEAR(dot(w, w), 1.0, 1e-12);
        mean += dot(mu, w) / m;
    }
    EXPECT_NEAR(mean, std::cosh(k) / std::sinh(k) - 1 / k, 1e-4);
}

TEST(LightGuide, GuidedSamplesAgreeWithTheMixturesDensity) {
    // With an MIS partner (mixture 1), each sample's pdf is the mixture's density at its direction
    // (what the next-event estimate's MIS uses, ht_guided_pdf) and its weight the value there over
    // that pdf; some samples come from the guide (near a light's direction), most from the BCSDF.
    const real share = 0.3;
    for (const char* model : {"chiang", "zinke", "marschner"})
        for (double h : {-0.7, 0.2}) {
            const HtShadingPoint sp = fibre_point(h, model);
            int sampled = 0, near_light = 0;
            for (uint s = 0; s < 3000; ++s) {
                real3 wi, weight;
                real pdf = 0;
                if (!ht_point_sample_guided(&sp, rig().data(), uint(rig().size()), share, 11u, 5u, s, 1u, 1, &wi, &weight,
                                            &pdf))
                    continue;
                ++sampled;
                real3 value;
                real pdf_bsdf = 0;
                ht_point_eval(&sp, wi, &value, &pdf_bsdf);
                const real mixture = ht_guided_pdf(&sp, rig().data(), uint(rig().size()), share, 1u, wi, pdf_bsdf);
                ASSERT_GT(pdf, 0);
                EXPECT_NEAR(mixture / pdf, 1.0, 1e-9) << model << " h " << h << " sample " << s;
                EXPECT_NEAR(weight.x, value.x / pdf, 1e-9 * std::max(1.0, weight.x)) << model << " sample " << s;
                EXPECT_NEAR(weight.z, value.z / pdf, 1e-9 * std::max(1.0, weight.z)) << model << " sample " << s;
                HtLight d = rig()[0];
                HtLightSample ls;
                ASSERT_TRUE(ht_light_toward(&d, sp.p, &ls));
                near_light += dot(wi, ls.wi) > 0.9;
            }
            EXPECT_GT(sampled, 2900) << model;
            // the guide gives the directional light 15 % of the samples, 63 % of them within 26
            // degrees of it (1 - e^{-kappa (1 - 0.9)} of the lobe's mass): 9.5 %, and the BCSDF's few
            EXPECT_GT(near_light, 0.08 * sampled) << model;
        }
}

TEST(LightGuide, TheGuidedAlbedoEqualsTheBcsdfSampledOne) {
    // The mean weight of a vertex's continuations is its directional albedo, whatever density drew
    // them.  Independent numbers, 400,000 samples each way; the bound is 5 standard errors of the
    // difference (measured: within 1.2 of them for every model and offset here).
    for (const char* model : {"chiang", "zinke"})
        for (double h : {-0.5, 0.4}) {
            const HtShadingPoint sp = fibre_point(h, model);
            const uint n = 400000;
            double sum[2] = {0, 0}, sum2[2] = {0, 0};
            for (uint s = 0; s < n; ++s) {
                real3 wi, w;
                real pdf;
                const real3 zero = make_real3(0, 0, 0);
                const real3 plain = ht_point_sample(&sp, 3u, 9u, s, 2u, 0, &wi, &w, &pdf) ? w : zero;
                const real3 guided = ht_point_sample_guided(&sp, rig().data(), uint(rig().size()), 0.3, 3u, 8u, s, 2u, 0,
                                                            &wi, &w, &pdf)
                                         ? w
                                         : zero;
                sum[0] += plain.y, sum2[0] += plain.y * plain.y;
                sum[1] += guided.y, sum2[1] += guided.y * guided.y;
            }
            double mean[2], var[2];
            for (int k = 0; k < 2; ++k) {
                mean[k] = sum[k] / n;
                var[k] = (sum2[k] / n - mean[k] * mean[k]) / n;
            }
            ASSERT_GT(mean[0], 0.05) << model;
            EXPECT_NEAR(mean[1], mean[0], 5 * std::sqrt(var[0] + var[1]))
                << model << " h " << h << ": guided " << mean[1] << ", BCSDF-sampled " << mean[0];
        }
}

TEST(LightGuide, PerLobeWeightsAreEachLobeAgainstTheGuide) {
    // Without an MIS partner, chiang's guided continuations weigh each lobe against the guide on its
    // own (light_guide.h): recomputed here from the model's lobe values and the sampler's lobe
    // choice, independently of the kernel's per-lobe helpers.  A BCSDF draw's weight is one of the
    // terms, a guided draw's their sum, so the weight must equal either one term or the sum.
    const real share = 0.3;
    for (double h : {-0.7, 0.2}) {
        const HtShadingPoint sp = fibre_point(h, "chiang");
        const HtChiangSetup& c = sp.wo_prep.chiang;
        int as_one = 0, as_sum = 0;
        for (uint s = 0; s < 3000; ++s) {
            real3 wi, weight;
            real pdf = -1;
            if (!ht_point_sample_guided(&sp, rig().data(), uint(rig().size()), share, 11u, 5u, s, 1u, 0, &wi, &weight,
                                        &pdf))
                continue;
            EXPECT_EQ(pdf, 0);
            real3 mu, lobes[4], value;
            real guide;
            ht_guide_lights(rig().data(), uint(rig().size()), sp.p, uint(rig().size()), &mu, wi, &guide);
            ht_chiang_eval_setup(&sp.mat, &c, sp.wo_l, ht_to_fiber_local(wi, sp.fx, sp.fy, sp.fz), lobes, &value, 0);
            double sum = 0, term[4];
            for (int p = 0; p < 4; ++p) {
                // lobe p's value is A_p d_p: its density d_p from the value's green channel
                const double d = c.ap[p].y > 0 ? lobes[p].y / c.ap[p].y : 0;
                term[p] = c.ap_pdf[p] > 0 ? lobes[p].y / (share * guide + (1 - share) * c.ap_pdf[p] * d) : 0;
                sum += term[p];
            }
            const double tol = 1e-9 * std::max(1.0, sum);
            bool one = false;
            for (int p = 0; p < 4; ++p) one = one || std::fabs(weight.y - term[p]) <= tol;
            as_one += one;
            as_sum += std::fabs(weight.y - sum) <= tol;
            ASSERT_TRUE(one || std::fabs(weight.y - sum) <= tol) << "h " << h << " sample " << s << " weight " << weight.y;
        }
        // a share of about 0.3 comes from the guide
        EXPECT_GT(as_sum, 600) << h;
        EXPECT_GT(as_one, 1800) << h;
    }
}

TEST(LightGuide, NothingGuidesWithoutALightThatReachesTheVertexNorPastTheFirstVertices) {
    // no lights, a spot whose cone misses the vertex, and a light that reaches it but at a vertex
    // past the guided ones: the BCSDF's own sample, bit for bit
    const HtShadingPoint sp = fibre_point(0.3, "chiang");
    const HtLight spot = light(HT_LIGHT_SPOT, 6, 5, 0), sun = light(HT_LIGHT_DIRECTIONAL, 0, 0, 0);
    struct Case {
        const HtLight* lights;
        uint count, bounce;
    };
    for (const Case c : {Case{&spot, 0u, 1u}, Case{&spot, 1u, 1u}, Case{&sun, 1u, HT_GUIDE_VERTICES}})
        for (uint s = 0; s < 200; ++s) {
            real3 wa, wb, ga, gb;
            real pa, pb;
            const int a = ht_point_sample(&sp, 4u, 2u, s, c.bounce, 0, &wa, &ga, &pa);
            const int b = ht_point_sample_guided(&sp, c.lights, c.count, 0.5, 4u, 2u, s, c.bounce, 0, &wb, &gb, &pb);
            ASSERT_EQ(a, b);
            if (!a) continue;
            EXPECT_EQ(wa.x, wb.x);
            EXPECT_EQ(ga.y, gb.y);
            EXPECT_EQ(pa, pb);
        }
}

}  // namespace
