#include "fiber/query_json.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>

#include "fiber/material.h"

namespace ht {

namespace {

using nlohmann::json;

double jnum(const json& j, const char* key) {
    const json& v = j.at(key);
    if (!v.is_number()) throw std::runtime_error(std::string("\"") + key + "\" must be a number");
    return v.get<double>();
}
Vec3f jvec3(const json& j, const char* key, bool allow_scalar) {
    const json& v = j.at(key);
    if (allow_scalar && v.is_number()) {
        float x = v.get<float>();
        return {x, x, x};
    }
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        throw std::runtime_error(std::string("\"") + key + "\" must be an array of 3 numbers");
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}
real3 jdir(const json& j, const char* key) {
    if (!j.contains(key)) throw std::runtime_error(std::string("missing \"") + key + "\"");
    const json& v = j.at(key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        throw std::runtime_error(std::string("\"") + key + "\" must be an array of 3 numbers");
    double x = v[0].get<double>(), y = v[1].get<double>(), z = v[2].get<double>();
    double l = std::sqrt(x * x + y * y + z * z);
    if (!(std::fabs(l - 1.0) <= 1e-3))
        throw std::runtime_error(std::string("\"") + key + "\" must be a unit vector (length " + std::to_string(l) + ")");
    return make_real3(x / l, y / l, z / l);
}

HairMaterialDesc desc_from_json(const json& j, bool sample) {
    static const char* known[] = {"model", "wo", "wi", "h", "u", "eta", "sigma_a", "eumelanin", "pheomelanin",
                                  "color", "beta_m", "beta_n", "alpha_deg", "alpha_r_deg", "beta_r_deg",
                                  "caustic_wc_deg", "caustic_kg", "caustic_deta", "caustic_dhm", "eccentricity",
                                  "kd", "ks", "ks_exponent", "name"};
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const char* k : known) ok = ok || it.key() == k;
        if (!ok) throw std::runtime_error("unknown key \"" + it.key() + "\"");
    }
    HairMaterialDesc d;
    d.name = "query";
    if (!j.contains("model") || !j["model"].is_string()) throw std::runtime_error("missing \"model\" (string)");
    d.model = j["model"].get<std::string>();
    if (j.contains("sigma_a")) { d.has_sigma_a = true; d.sigma_a = jvec3(j, "sigma_a", true); }
    if (j.contains("eumelanin") || j.contains("pheomelanin")) {
        d.has_melanin = true;
        if (j.contains("eumelanin")) d.eumelanin = (float)jnum(j, "eumelanin");
        if (j.contains("pheomelanin")) d.pheomelanin = (float)jnum(j, "pheomelanin");
    }
    if (j.contains("color")) { d.has_color = true; d.color = jvec3(j, "color", true); }
    struct { const char* k; float* p; } nums[] = {
        {"eta", &d.eta}, {"beta_m", &d.beta_m}, {"beta_n", &d.beta_n}, {"alpha_deg", &d.alpha_deg},
        {"alpha_r_deg", &d.alpha_r_deg}, {"beta_r_deg", &d.beta_r_deg}, {"caustic_wc_deg", &d.caustic_wc_deg},
        {"caustic_kg", &d.caustic_kg}, {"caustic_deta", &d.caustic_deta}, {"caustic_dhm", &d.caustic_dhm},
        {"eccentricity", &d.eccentricity}, {"ks_exponent", &d.ks_exponent}};
    for (auto& n : nums)
        if (j.contains(n.k)) *n.p = (float)jnum(j, n.k);
    if (j.contains("kd")) d.kd = jvec3(j, "kd", true);
    if (j.contains("ks")) d.ks = jvec3(j, "ks", true);
    return d;
}

}  // namespace

FiberJsonQuery parse_fiber_query(const std::string& line, bool sample) {
    FiberJsonQuery r;
    try {
        json j = json::parse(line);
        if (!j.is_object()) throw std::runtime_error("a query must be a JSON object");
        r.m = make_kernel_material(desc_from_json(j, sample));
        real3 wo = jdir(j, "wo");
        r.wo = wo;
        r.q.wo[0] = (float)wo.x; r.q.wo[1] = (float)wo.y; r.q.wo[2] = (float)wo.z;
        if (!sample) {
            real3 wi = jdir(j, "wi");
            r.wi = wi;
            r.q.wi[0] = (float)wi.x; r.q.wi[1] = (float)wi.y; r.q.wi[2] = (float)wi.z;
        }
        double h = j.contains("h") ? jnum(j, "h") : 0.0;
        if (!(h >= -1.0 && h <= 1.0)) throw std::runtime_error("\"h\" = " + std::to_string(h) + " is outside [-1, 1]");
        r.h = h;
        r.q.h = (float)h;
        if (sample) {
            if (!j.contains("u") || !j["u"].is_array() || j["u"].size() != 4)
                throw std::runtime_error("\"u\" must be an array of 4 numbers in [0, 1)");
            float* us[4] = {&r.q.u0, &r.q.u1, &r.q.u2, &r.q.u3};
            for (int k = 0; k < 4; ++k) {
                if (!j["u"][k].is_number()) throw std::runtime_error("\"u\" must be an array of 4 numbers in [0, 1)");
                double u = j["u"][k].get<double>();
                if (!(u >= 0.0 && u < 1.0)) throw std::runtime_error("\"u\"[" + std::to_string(k) + "] is outside [0, 1)");
                r.u[k] = u;
                *us[k] = (float)u;
            }
        }
        r.valid = true;
    } catch (const json::exception& e) {
        r.error = std::string("bad JSON: ") + e.what();
    } catch (const std::exception& e) {
        r.error = e.what();
    }
    return r;
}


}  // namespace ht
