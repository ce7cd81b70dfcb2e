#include "cli/commands.h"
#include "kernels/types.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ht {

void add_scene_options(ArgParser& p) {
    p.option("--thickness", "radius|diameter", ".hair files: whether the thickness array is the radius or the diameter", "radius");
    p.option("--radius", "R", "default fibre radius for files that store none (.data, glTF without _RADIUS)");
}

LoadOptions scene_load_options(const ArgParser& p) {
    LoadOptions o;
    std::string t = p.get("--thickness");
    if (t != "radius" && t != "diameter") throw UsageError("--thickness must be 'radius' or 'diameter', got '" + t + "'");
    o.thickness_is_diameter = t == "diameter";
    if (p.has("--radius")) o.default_radius = float(p.get_double("--radius", 1e-12, 1e12));
    return o;
}

void apply_model_override(Scene& scene, const std::string& m) {
    if (m != "kajiya" && m != "marschner" && m != "zinke" && m != "chiang")
        throw UsageError("unknown fibre model '" + m + "' (kajiya, marschner, zinke or chiang)");
    for (auto& mat : scene.materials) mat.model = m;
}

uint32_t parse_fiber_field(const std::string& what, const std::string& f) {
    if (f == "material") return HT_FIELD_MATERIAL;
    if (f == "near") return HT_FIELD_NEAR;
    if (f == "far") return HT_FIELD_FAR;
    if (f == "auto") return HT_FIELD_AUTO;
    throw UsageError(what + " must be near, far, auto or material, got '" + f + "'");
}

Vec3f parse_rgb(const std::string& opt, const std::string& s) {
    Vec3f v{};
    std::stringstream ss(s);
    std::string item;
    int n = 0;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (n == 3 || item.empty() || *end || !std::isfinite(d)) throw UsageError(opt + " expects r,g,b numbers, got '" + s + "'");
        v[n++] = float(d);
    }
    if (n == 1) v[1] = v[2] = v[0];
    else if (n != 3) throw UsageError(opt + " expects r,g,b numbers, got '" + s + "'");
    return v;
}

}  // namespace ht
