#include "scene/gltf_material.h"

#include <functional>
#include <map>

#include "scene/scene_error.h"

namespace ht {

namespace {

std::string material_name(const tinygltf::Material& m, int index) {
    return m.name.empty() ? str_cat("material ", index)
                          : str_cat("material ", index, " \"", m.name, "\"");
}

enum class Kind { Number, Rgb, String };

bool has_kind(const tinygltf::Value& v, Kind kind) {
    switch (kind) {
        case Kind::Number: return v.IsNumber();
        case Kind::String: return v.IsString();
        case Kind::Rgb:
            if (!v.IsArray() || v.ArrayLen() != 3) return false;
            for (int i = 0; i < 3; ++i)
                if (!v.Get(i).IsNumber()) return false;
            return true;
    }
    return false;
}

const char* kind_name(Kind kind) {
    switch (kind) {
        case Kind::Number: return "a number";
        case Kind::String: return "a string";
        case Kind::Rgb: return "an array of 3 numbers";
    }
    return "";
}

float number(const tinygltf::Value& v) { return static_cast<float>(v.GetNumberAsDouble()); }

Vec3f rgb(const tinygltf::Value& v) {
    return {number(v.Get(0)), number(v.Get(1)), number(v.Get(2))};
}

// One recognised extras key: its JSON kind and where the (type-checked) value goes.
struct Field {
    Kind kind;
    std::function<void(const tinygltf::Value&)> set;
};

}  // namespace

HairMaterialDesc hair_material_from_gltf(const tinygltf::Material& material, int index,
                                         const std::string& file,
                                         std::set<std::string>& unknown_keys) {
    HairMaterialDesc d;
    d.name = material.name.empty() ? str_cat("material", index) : material.name;
    const std::string where = material_name(material, index);

    auto num = [](float& field) {
        return Field{Kind::Number, [&field](const tinygltf::Value& v) { field = number(v); }};
    };
    auto colour = [](Vec3f& field, bool* stated) {
        return Field{Kind::Rgb, [&field, stated](const tinygltf::Value& v) {
                         field = rgb(v);
                         if (stated) *stated = true;
                     }};
    };
    const std::map<std::string, Field> fields = {
        {"model", {Kind::String,
                   [&](const tinygltf::Value& v) {
                       const std::string& m = v.Get<std::string>();
                       if (m != "kajiya" && m != "marschner" && m != "zinke" && m != "chiang")
                           scene_fail(file, where, ": unknown hair model \"", m,
                                      "\" (known: kajiya, marschner, zinke, chiang)");
                       d.model = m;
                   }}},
        {"sigma_a", colour(d.sigma_a, &d.has_sigma_a)},
        {"eumelanin", {Kind::Number,
                       [&](const tinygltf::Value& v) { d.eumelanin = number(v), d.has_melanin = true; }}},
        {"pheomelanin", {Kind::Number,
                         [&](const tinygltf::Value& v) { d.pheomelanin = number(v), d.has_melanin = true; }}},
        {"color", colour(d.color, &d.has_color)},
        {"eta", num(d.eta)},
        {"beta_m", num(d.beta_m)},
        {"beta_n", num(d.beta_n)},
        {"alpha_deg", num(d.alpha_deg)},
        {"alpha_r_deg", num(d.alpha_r_deg)},
        {"beta_r_deg", num(d.beta_r_deg)},
        {"caustic_wc_deg", num(d.caustic_wc_deg)},
        {"caustic_kg", num(d.caustic_kg)},
        {"caustic_deta", num(d.caustic_deta)},
        {"caustic_dhm", num(d.caustic_dhm)},
        {"eccentricity", num(d.eccentricity)},
        {"kd", colour(d.kd, nullptr)},
        {"ks", colour(d.ks, nullptr)},
        {"ks_exponent", num(d.ks_exponent)},
        // Geometry rather than appearance: read by gltf_material_radius().
        {"radius", {Kind::Number, [](const tinygltf::Value&) {}}},
    };

    const tinygltf::Value& extras = material.extras;
    if (extras.IsObject()) {
        for (const std::string& key : extras.Keys()) {
            const auto it = fields.find(key);
            if (it == fields.end()) {
                unknown_keys.insert(key);
                continue;
            }
            const tinygltf::Value& value = extras.Get(key);
            if (!has_kind(value, it->second.kind))
                scene_fail(file, where, ": extras.", key, " must be ", kind_name(it->second.kind));
            it->second.set(value);
        }
    } else if (extras.Type() != tinygltf::NULL_TYPE) {
        scene_fail(file, where, ": extras must be an object");
    }

    // A plain glTF material (e.g. from a DCC exporter) still says what colour the hair is.
    const std::vector<double>& base = material.pbrMetallicRoughness.baseColorFactor;
    const bool white_base = base.size() < 3 || (base[0] == 1.0 && base[1] == 1.0 && base[2] == 1.0);
    if (!d.has_sigma_a && !d.has_melanin && !d.has_color && !white_base) {
        d.color = {static_cast<float>(base[0]), static_cast<float>(base[1]), static_cast<float>(base[2])};
        d.has_color = true;
    }
    return d;
}

std::optional<float> gltf_material_radius(const tinygltf::Material& material, int index,
                                          const std::string& file) {
    const tinygltf::Value& extras = material.extras;
    if (!extras.IsObject() || !extras.Has("radius")) return std::nullopt;
    const tinygltf::Value& v = extras.Get("radius");
    if (!v.IsNumber())
        scene_fail(file, material_name(material, index), ": extras.radius must be a number");
    return number(v);
}

}  // namespace ht
