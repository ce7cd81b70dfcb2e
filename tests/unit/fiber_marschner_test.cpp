// Marschner 2003 far field and Zinke 2004 near field: geometry, roots, caustics, energy, reciprocity.
#include <gtest/gtest.h>

#include <cmath>

#include "fiber_test_util.h"

using namespace ht;

TEST(FiberMarschner, RootsSolvePhiExactly) {
    // Every returned root satisfies Phi(p, h) = phi (mod 2 pi) to 1e-10; TRT below the caustic has 3 roots.
    for (double inv_ep : {1 / 1.55, 1 / 1.9, 1 / 2.2, 0.1})
        for (int p = 0; p < 3; ++p)
            for (double phi = -3.1; phi < 3.15; phi += 0.05) {
                double hs[3];
                double cs[3];
                int n = ht_phi_roots(p, phi, inv_ep, hs, cs);
                for (int k = 0; k < n; ++k) {
                    double g = std::asin(hs[k]);
                    double d = ht_wrap_pi(ht_phi_gamma(p, g, inv_ep) - phi);
                    EXPECT_NEAR(d, 0.0, 1e-10) << p << " " << phi << " " << inv_ep;
                }
                if (p == 0) {
                    EXPECT_EQ(n, 1);  // R: always exactly one root
                }
            }
    double hs[3];
    double cs[3];
    EXPECT_EQ(ht_phi_roots(2, 0.2, 1 / 1.55, hs, cs), 3);
    EXPECT_EQ(ht_phi_roots(2, 0.5, 1 / 1.55, hs, cs), 0);  // beyond the caustic phi_c = 0.3249 and 4c - pi
}

TEST(FiberMarschner, CausticConstantsMatchNotes) {
    // docs/MODEL.md §3: eta' = 1.55 (theta_d = 0): h_c = 0.729726, phi_c = 0.32491 rad (1e-5).
    HtMaterial m = make_kernel_material(fibertest::white("marschner", 0.3, 0.3));
    double phi_c, dh, t, hc;
    ht_marschner_caustic(&m, 1 / 1.55, &phi_c, &dh, &t, &hc);
    EXPECT_NEAR(hc, 0.729726, 1e-6);
    EXPECT_NEAR(phi_c, 0.32491, 1e-5);
    EXPECT_EQ(t, 1.0);
    // Delta h_M = 0.5 is active at theta = 0 (2 sqrt(2 w_c/|Phi''|) = 0.78 > 0.5)
    EXPECT_NEAR(dh, 0.5, 1e-12);
    // fade: eta' = 2.15 is half-way through delta eta' = 0.3 -> t = 0.5
    ht_marschner_caustic(&m, 1 / 2.15, &phi_c, &dh, &t, &hc);
    EXPECT_NEAR(t, 0.5, 1e-6);  // delta eta' stored as float
}

TEST(FiberMarschner, NRClosedForm) {
    // N_R(phi) = F(gamma = -phi/2) cos(phi/2) / 4 at theta_d = 0.
    HtMaterial m = make_kernel_material(fibertest::white("marschner", 0.3, 0.3));
    for (double phi = -3.0; phi <= 3.0; phi += 0.25) {
        real3 n;
        real dens;
        ht_marschner_np_raw(&m, 0, phi, m.eta, 0.0, 1.0, &n, &dens);
        double f = ht_fresnel_dielectric(std::cos(phi / 2), m.eta);
        EXPECT_NEAR(n.x, f * std::cos(phi / 2) / 4, 1e-12);
        EXPECT_NEAR(dens, std::cos(phi / 2) / 4, 1e-12);
    }
}

TEST(FiberMarschner, AzimuthalNormalisationIsEnergyFraction) {
    // integral N_p dphi = 1/2 integral_{-1}^{1} A_p dh (docs/MODEL.md §5), p = R, TT (caustic-free), 1e-4.
    HairMaterialDesc d = fibertest::white("marschner", 0.3, 0.3);
    d.has_sigma_a = true;
    d.sigma_a = {0.3f, 0.3f, 0.3f};
    HtMaterial m = make_kernel_material(d);
    for (int p = 0; p < 2; ++p) {
        double s = 0, a = 0;
        int n = 200000;
        for (int i = 0; i < n; ++i) {
            double phi = -HT_PI + (i + 0.5) * 2 * HT_PI / n;
            real3 v;
            real dens;
            ht_marschner_np_raw(&m, p, phi, m.eta, 0.0, 1.0, &v, &dens);
            s += v.x * 2 * HT_PI / n;
            double h = -1 + (i + 0.5) * 2.0 / n;
            a += 0.5 * ht_marschner_ap(&m, p, h, m.eta, 0.0, 1.0).x * 2.0 / n;
        }
        EXPECT_NEAR(s, a, 1e-4) << p;
    }
}

TEST(FiberMarschner, ReciprocalAndBoundedEnergyWithoutGlints) {
    // S = value / (cos theta_i / 2) is symmetric in (wi, wo) (theta_h symmetric, |theta_d| and phi -> -phi);
    // kajiya's diffuse term likewise for value / cos theta_i (its classic specular term cos^p(theta_i+theta_o)
    // is a lighting term, not BRDF x cos, and is not reciprocal: ks = 0 here).  1e-9 relative.
    HairMaterialDesc d;
    d.model = "marschner";
    d.eccentricity = 1.0f;
    HtMaterial m = make_kernel_material(d);
    d.model = "kajiya";
    d.ks = {0.f, 0.f, 0.f};
    HtMaterial k = make_kernel_material(d);
    uint64_t st = 17;
    for (int i = 0; i < 500; ++i) {
        real3 a = fibertest::rand_dir(st), b = fibertest::rand_dir(st), v1, v2;
        real p1, p2;
        for (const HtMaterial* mm : {&m, &k}) {
            ht_bcsdf_eval(mm, a, b, 0.3, &v1, &p1);
            ht_bcsdf_eval(mm, b, a, 0.3, &v2, &p2);
            double ca = std::sqrt(1 - a.x * a.x), cb = std::sqrt(1 - b.x * b.x);
            if (ca < 1e-3 || cb < 1e-3) continue;
            EXPECT_NEAR(v1.x / cb, v2.x / ca, 1e-9 * (v1.x / cb) + 1e-14);
        }
    }
    // energy <= 1 for a white fibre once the (non-energy-conserving) glint is off; 1e-3 quadrature slack
    HairMaterialDesc w = fibertest::white("marschner", 0.3, 0.3);
    w.caustic_kg = 0.0f;
    HtMaterial mw = make_kernel_material(w);
    for (double th : {0.0, 30.0, 60.0, 85.0}) EXPECT_LE(fibertest::albedo(mw, th, 1), 1.001) << th;
}

namespace {
// A_R + A_TT + A_TRT of a smooth circle at theta = 0 (docs/MODEL.md §4), written out independently:
// unpolarised Fresnel from Snell's law, chord absorption exp(-2 sigma_a cos gamma_t) per pass.
double attenuation_sum_theta0(double h, double eta, double sigma_a) {
    double ci = std::sqrt(1 - h * h), st = h / eta, ct = std::sqrt(1 - st * st);
    double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
    double f = 0.5 * (rs * rs + rp * rp), t = std::exp(-2 * sigma_a * ct);
    return f + (1 - f) * (1 - f) * t * (1 + f * t);
}
HtMaterial zinke_theta0_material(float sigma_a) {
    // narrow, untilted longitudinal lobes: theta_d stays ~0 inside them (see the tolerances below)
    HairMaterialDesc d;
    d.model = "zinke";
    d.has_sigma_a = true;
    d.sigma_a = {sigma_a, sigma_a, sigma_a};
    d.alpha_r_deg = 0.0f;
    d.beta_r_deg = 5.0f;
    return make_kernel_material(d);
}
}  // namespace

TEST(FiberZinke, AlbedoAtEachOffsetIsTheAttenuationOfThatOffset) {
    // Near field: the light leaving at offset h is A_p(h) of the one path through h (radiance is
    // conserved along a refracted ray), so integral value dwi = sum_p A_p(h) at every h, up to the
    // longitudinal factor (cos theta_i / cos^2 theta_d / 2 over the Gaussian: 1 - O(beta^2)) and
    // theta_d != 0 inside the lobe: 2 % with beta_R = 5 deg (beta_TRT = 10 deg).  Beyond |h| = 0.95 the
    // Fresnel factor at cos theta_d cos gamma_i changes fast across the lobe (2.5 % at h = 0.99); the
    // energy bound there is checked by WhiteFibreNeverReflectsMoreThanItReceives.
    HtMaterial m = zinke_theta0_material(0.1f);
    for (double h : {-0.95, -0.6, 0.0, 0.3, 0.7, 0.9, 0.95}) {
        double a = fibertest::albedo_at(m, fibertest::wo_at(0), h);
        EXPECT_NEAR(a, attenuation_sum_theta0(h, 1.55, 0.1), 0.02 * a) << "h = " << h;
    }
}

TEST(FiberZinke, HAverageIsTheFarFieldEnergy) {
    // The near field averaged over the fibre width must give the far field's energy
    // int N_p dphi = 1/2 int A_p dh (Marschner's N_p = sum over roots A_p / |2 dPhi/dh|); the paper's
    // S'-weighted AFS sum differs (R: pi/8-weighted, 0.30x) and is not what a pixel integrates.
    HtMaterial m = zinke_theta0_material(0.1f);
    double ref = 0;
    const int n = 2000;  // midpoint rule on a smooth integrand: error ~1e-7
    for (int i = 0; i < n; ++i) ref += attenuation_sum_theta0(-1 + (i + 0.5) * 2.0 / n, 1.55, 0.1) / n;
    double a = fibertest::albedo(m, 0.0, 24);
    EXPECT_NEAR(a, ref, 0.02 * a);
    AfsValues v = afs_reference(1.55, 0.1, 0.0);
    EXPECT_GT(std::fabs(a - (v.R + v.TT + v.TRT_glint)), 0.05 * a) << "the S'-weighted sum is a different quantity";
}

TEST(FiberZinke, WhiteFibreNeverReflectsMoreThanItReceives) {
    // sigma_a = 0: sum_p A_p(h) <= 1 at every h (the rest leaves as TRRT+, not modelled), so the albedo
    // at any single offset stays <= 1 up to the longitudinal normalisation (1 + O(beta^2): 1.5 % slack).
    HairMaterialDesc d = fibertest::white("zinke", 0.3, 0.3);
    HtMaterial m = make_kernel_material(d);
    for (double th : {0.0, 30.0, 60.0, 80.0})
        for (double h : {-0.999, -0.5, 0.0, 0.5, 0.8, 0.95, 0.999}) {
            double a = fibertest::albedo_at(m, fibertest::wo_at(th), h);
            EXPECT_LE(a, 1.015) << "theta " << th << " h " << h;
            EXPECT_GE(a, 0.0);
        }
}

TEST(FiberMarschner, CubicApproximationIsOnlyAStart) {
    // docs/MODEL.md §3: the cubic's TRT stationary point sits at h = 0.7108, phi = 20.49 deg versus the exact
    // 0.7297 / 18.62 deg (eta' = 1.55): its roots are close to, not equal to, the exact ones (TT within
    // 0.05 rad here), and ht_phi_roots polishes them to 1e-10 (RootsSolvePhiExactly).
    const double inv_ep = 1 / 1.55;
    for (double phi = 2.0; phi < 4.2; phi += 0.1) {
        double g[3];
        ASSERT_EQ(ht_phi_cubic_roots(1, phi, inv_ep, g), 1);
        double hs[3], cs[3];
        ASSERT_EQ(ht_phi_roots(1, phi, inv_ep, hs, cs), 1);
        EXPECT_NEAR(g[0], std::asin(hs[0]), 0.05) << phi;
        EXPECT_GT(std::fabs(ht_wrap_pi(ht_phi_gamma(1, g[0], inv_ep) - phi)), 0.0);
    }
    // stationary point of the cubic: d/dgamma = 0 at gamma^2 = (6pc/pi - 2) pi^3 / (24 p c)
    double c = std::asin(inv_ep), p = 2;
    double gs = std::sqrt((6 * p * c / HT_PI - 2) * HT_PI * HT_PI * HT_PI / (24 * p * c));
    EXPECT_NEAR(std::sin(gs), 0.7108, 2e-4);
    double phis = (6 * p * c / HT_PI - 2) * gs - 8 * p * c / (HT_PI * HT_PI * HT_PI) * gs * gs * gs;
    EXPECT_NEAR(phis * 180 / HT_PI, 20.49, 0.01);
}

TEST(FiberMarschner, ExponentPartsAreTheFunctions) {
    // zinke's eval multiplies factor * exp(exponent) forms to pay one exp per product: each must be
    // its function.  The wrapped Gaussian against an independent sum over 201 images (truncation
    // far below 1e-300 for sigma <= 3), the Gaussian and M_p against their closed forms; relative
    // 1e-12 (double rounding of a few operations and of exp at |exponent| <= ~700).
    for (double sigma : {1e-3, 0.05, 0.2, 1.0, 1.59, 1.61, 3.0}) {
        for (double x = -10.0; x <= 10.0; x += 0.0625) {
            for (double xx : {x, 3.14159265358979, -3.14159265358979, 3.1415926536, -3.1415926536}) {
                double truth = 0;
                for (int k = -100; k <= 100; ++k) {
                    const double d = xx + 2 * 3.14159265358979323846 * k;
                    truth += std::exp(-0.5 * d * d / (sigma * sigma)) / (sigma * std::sqrt(2 * 3.14159265358979323846));
                }
                double e;
                const double f = ht_wrapped_gaussian_parts(xx, sigma, &e);
                EXPECT_LE(e, 0.0);
                EXPECT_NEAR(f * std::exp(e), truth, 1e-12 * truth + 1e-300) << sigma << " " << xx;
                const double g = ht_gaussian_parts(xx, sigma, &e);
                const double gt = std::exp(-0.5 * xx * xx / (sigma * sigma)) / (sigma * std::sqrt(2 * 3.14159265358979323846));
                EXPECT_NEAR(g * std::exp(e), gt, 1e-12 * gt + 1e-300);
            }
        }
    }
    // M_p against d'Eon's closed form exp(-sin ti sin to / v) I0(cos ti cos to / v) / (2 v sinh(1/v)),
    // for the v where it does not overflow
    for (double v : {0.05, 0.2, 0.5, 4.0})
        for (double ti = -1.5; ti <= 1.5; ti += 0.1)
            for (double to = -1.5; to <= 1.5; to += 0.3) {
                const double ci = std::cos(ti), si = std::sin(ti), co = std::cos(to), so = std::sin(to);
                double e;
                const double f = ht_mp_n_parts(ci, si, co, so, v, ht_mp_log_norm(v), &e);
                const double truth = std::exp(-si * so / v) * std::cyl_bessel_i(0.0, ci * co / v) / (2 * v * std::sinh(1 / v));
                EXPECT_NEAR(f * std::exp(e), truth, 1e-12 * truth + 1e-300) << v << " " << ti << " " << to;
            }
}
