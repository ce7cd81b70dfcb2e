#include "fiber/material.h"

#include "core/constants.h"

#include "kernels/fiber/longitudinal.h"
#include "kernels/fiber/marschner.h"

#include <cmath>
#include <sstream>

namespace ht {


namespace {

[[noreturn]] void fail(const HairMaterialDesc& d, const std::string& what) {
    throw SceneError("material '" + d.name + "': " + what);
}
void check(const HairMaterialDesc& d, const char* param, double x, double lo, double hi) {
    // Desc fields are float: compare against the float-rounded bounds so that e.g. 0.01f passes [0.01, 1].
    if (!(x >= (double)(float)lo && x <= (double)(float)hi)) {
        std::ostringstream s;
        s << param << " = " << x << " is outside the allowed range [" << lo << ", " << hi << "]";
        fail(d, s.str());
    }
}
void check3(const HairMaterialDesc& d, const char* param, const Vec3f& v, double lo, double hi) {
    static const char* c[3] = {"[0]", "[1]", "[2]"};
    for (int i = 0; i < 3; ++i) check(d, (std::string(param) + c[i]).c_str(), v[i], lo, hi);
}
}  // namespace

uint32_t model_from_name(const std::string& n) {
    if (n == "kajiya") return HT_MODEL_KAJIYA;
    if (n == "marschner") return HT_MODEL_MARSCHNER;
    if (n == "zinke") return HT_MODEL_ZINKE;
    if (n == "chiang") return HT_MODEL_CHIANG;
    throw SceneError("unknown hair model '" + n + "' (allowed: kajiya, marschner, zinke, chiang)");
}
const char* model_name(uint32_t m) {
    switch (m) {
    case HT_MODEL_KAJIYA: return "kajiya";
    case HT_MODEL_MARSCHNER: return "marschner";
    case HT_MODEL_ZINKE: return "zinke";
    case HT_MODEL_CHIANG: return "chiang";
    default: return "unknown";
    }
}

double chiang_v_from_beta_m(double b) {
    double t = 0.726 * b + 0.812 * b * b + 3.7 * std::pow(b, 20);
    return t * t;
}
double chiang_s_from_beta_n(double b) {
    return std::sqrt(kPi / 8.0) * (0.265 * b + 1.194 * b * b + 5.372 * std::pow(b, 22));
}
std::array<double, 3> sigma_a_from_melanin(double ce, double cp) {
    const double eu[3] = {0.419, 0.697, 1.37}, ph[3] = {0.187, 0.4, 1.05};
    return {ce * eu[0] + cp * ph[0], ce * eu[1] + cp * ph[1], ce * eu[2] + cp * ph[2]};
}
std::array<double, 3> sigma_a_from_color(const std::array<double, 3>& c, double b) {
    double D = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b * b * b + 5.574 * std::pow(b, 4) + 0.245 * std::pow(b, 5);
    std::array<double, 3> s{};
    for (int i = 0; i < 3; ++i) {
        double r = std::log(c[i]) / D;
        s[i] = r * r;
    }
    return s;
}
double kajiya_ks_norm(double p) {
    // int_{-pi/2}^{pi/2} cos^{q} = sqrt(pi) Gamma((q+1)/2) / Gamma(q/2 + 1), q = p + 1
    double q = p + 1.0;
    double integral = std::sqrt(kPi) * std::exp(std::lgamma(0.5 * (q + 1.0)) - std::lgamma(0.5 * q + 1.0));
    return 1.0 / (2.0 * kPi * integral);
}

HtMaterial make_kernel_material(const HairMaterialDesc& d) {
    HtMaterial m{};
    m.model = model_from_name(d.model);
    // ---- absorption: exactly one source (sigma_a is the default when none is stated)
    int sources = (d.has_sigma_a ? 1 : 0) + (d.has_melanin ? 1 : 0) + (d.has_color ? 1 : 0);
    if (sources > 1) fail(d, "give only one of sigma_a, eumelanin/pheomelanin, color");
    check(d, "beta_n", d.beta_n, 0.01, 1.0);
    check(d, "beta_m", d.beta_m, 0.01, 1.0);
    std::array<double, 3> sa{d.sigma_a[0], d.sigma_a[1], d.sigma_a[2]};
    if (d.has_melanin) {
        check(d, "eumelanin", d.eumelanin, 0.0, 50.0);
        check(d, "pheomelanin", d.pheomelanin, 0.0, 50.0);
        sa = sigma_a_from_melanin(d.eumelanin, d.pheomelanin);
    } else if (d.has_color) {
        check3(d, "color", d.color, 1e-5, 1.0);
        sa = sigma_a_from_color({d.color[0], d.color[1], d.color[2]}, d.beta_n);
    } else {
        check3(d, "sigma_a", d.sigma_a, 0.0, 100.0);
    }
    for (int i = 0; i < 3; ++i) m.sigma_a[i] = (float)sa[i];
    check(d, "eta", d.eta, 1.0001, 3.0);
    m.eta = d.eta;
    m.beta_m = d.beta_m;
    m.beta_n = d.beta_n;
    check(d, "alpha_deg", d.alpha_deg, -15.0, 15.0);
    m.alpha = (float)(d.alpha_deg * kRadiansPerDegree);
    // ---- chiang derived
    double v = chiang_v_from_beta_m(d.beta_m);
    m.v[0] = (float)v;
    m.v[1] = (float)(0.25 * v);
    m.v[2] = (float)(4.0 * v);
    m.v[3] = (float)(4.0 * v);
    for (int i = 0; i < 4; ++i) m.mp_c[i] = (float)ht_mp_log_norm(m.v[i]);
    double s = chiang_s_from_beta_n(d.beta_n);
    m.s = (float)s;
    m.azim_sigma = (float)(kPi * s / std::sqrt(3.0));  // std of a logistic with scale s
    double a = d.alpha_deg * kRadiansPerDegree;
    const double k[3] = {1.0, 2.0, 4.0};
    for (int i = 0; i < 3; ++i) {
        m.sin_tilt[i] = (float)std::sin(k[i] * a);
        m.cos_tilt[i] = (float)std::cos(k[i] * a);
    }
    m.cos_tilt[3] = 1.0f;
    // ---- Marschner / Zinke (Marschner 2003 Table 1 relations)
    check(d, "alpha_r_deg", d.alpha_r_deg, -20.0, 20.0);
    check(d, "beta_r_deg", d.beta_r_deg, 0.5, 45.0);
    m.alpha_r = (float)(d.alpha_r_deg * kRadiansPerDegree);
    m.alpha_tt = (float)(-0.5 * d.alpha_r_deg * kRadiansPerDegree);
    m.alpha_trt = (float)(-1.5 * d.alpha_r_deg * kRadiansPerDegree);
    m.beta_r = (float)(d.beta_r_deg * kRadiansPerDegree);
    m.beta_tt = (float)(0.5 * d.beta_r_deg * kRadiansPerDegree);
    m.beta_trt = (float)(2.0 * d.beta_r_deg * kRadiansPerDegree);
    ht_mz_prepare_material(&m);
    check(d, "caustic_wc_deg", d.caustic_wc_deg, 1.0, 45.0);
    check(d, "caustic_kg", d.caustic_kg, 0.0, 10.0);
    check(d, "caustic_deta", d.caustic_deta, 0.01, 1.0);
    check(d, "caustic_dhm", d.caustic_dhm, 0.0, 1.0);
    check(d, "eccentricity", d.eccentricity, 0.5, 1.0);
    m.caustic_wc = (float)(d.caustic_wc_deg * kRadiansPerDegree);
    m.caustic_kg = d.caustic_kg;
    m.caustic_deta = d.caustic_deta;
    m.caustic_dhm = d.caustic_dhm;
    m.eccentricity = d.eccentricity;
    // ---- Kajiya-Kay
    check3(d, "kd", d.kd, 0.0, 1.0);
    check3(d, "ks", d.ks, 0.0, 1.0);
    for (int i = 0; i < 3; ++i)
        if (d.kd[i] + d.ks[i] > 1.0f + 1e-6f)
            fail(d, "kd[" + std::to_string(i) + "] + ks[" + std::to_string(i) +
                        "] exceeds 1 (the Kajiya-Kay albedo would exceed 1)");
    check(d, "ks_exponent", d.ks_exponent, 1.0, 10000.0);
    for (int i = 0; i < 3; ++i) {
        m.kd[i] = d.kd[i];
        m.ks[i] = d.ks[i];
    }
    m.ks_exponent = d.ks_exponent;
    m.ks_norm = (float)kajiya_ks_norm(d.ks_exponent);
    return m;
}

}  // namespace ht
