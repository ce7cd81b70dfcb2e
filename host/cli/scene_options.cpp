#include "cli/commands.h"
#include "kernels/types.h"
#include "scene/hair_presets.h"
#include "render/settings.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ht {

void add_scene_argument(ArgParser& p) {
    p.positional("SCENE",
                 "scene file (.gltf/.glb, .hair, .data, .ply, .obj, .pbrt/.pbrt.gz) or a built-in scene: "
                 "builtin:strand (the paper's blond lock), builtin:ball (a curly hair ball) or builtin:slab (a planar "
                 "layer of straight hairs), each with optional ?hairs=N&segments=N&seed=N&radius=R (docs/CLI.md "
                 "\"Scenes\")");
}

void add_scene_options(ArgParser& p) {
    p.option("--thickness", "radius|diameter", ".hair files: whether the thickness array is the radius or the diameter", "radius");
    p.option("--radius", "R", "default fibre radius for files that store none (.data, glTF without _RADIUS)");
    // View and hair colour (ensure_camera_and_light, hair_color_options).
    p.option("--up-axis", "x|y|z|-x|-y|-z", "the model's up axis for the automatic view (default: detected from where the strands' roots are, see README)");
    p.option("--look-from", "X,Y,Z", "camera position (default: the scene's camera, or a 3/4 front view fitted to the hair)");
    p.option("--look-at", "X,Y,Z", "point the camera looks at");
    p.option("--up", "X,Y,Z", "camera up vector (default: the model's up axis)");
    p.option("--fov", "DEG", "camera vertical field of view in degrees (default: the scene's, or 30)");
    p.option("--camera", "N", "glTF: use the file's camera N (default: the first one)");
    p.option("--hair-preset", "blond|brown|black|red", "every hair material's colour from the melanin of real hair (README table)");
    p.option("--eumelanin", "C", "every hair material's eumelanin concentration (0.3 blond, 1.3 brown, 8 black)");
    p.option("--pheomelanin", "C", "every hair material's pheomelanin concentration (red hair; default 0 or the preset's)");
    p.option("--hair-color", "R,G,B", "every hair material's colour, each in (0, 1], converted to absorption (Chiang 2016)");
}

LoadOptions scene_load_options(const ArgParser& p) {
    LoadOptions o;
    std::string t = p.get("--thickness");
    if (t != "radius" && t != "diameter") throw UsageError("--thickness must be 'radius' or 'diameter', got '" + t + "'");
    o.thickness_is_diameter = t == "diameter";
    if (p.has("--radius")) o.default_radius = float(p.get_double("--radius", 1e-12, 1e12));
    if (p.has("--camera")) o.camera_index = p.get_int("--camera", 0, 1 << 20);
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

float parse_light_guiding(const std::string& what, const std::string& value) {
    return float(parse_auto_off_or_double(what, value, kMinLightGuiding, kMaxLightGuiding, kAutoLightGuiding));
}

namespace {

Vec3f parse_xyz(const ArgParser& p, const std::string& opt) {
    const std::vector<double> v = parse_number_list(opt, p.get(opt), 3, "x,y,z");
    return {float(v[0]), float(v[1]), float(v[2])};
}

}  // namespace

ViewOptions scene_view_options(const ArgParser& p) {
    ViewOptions v;
    if (p.has("--up-axis")) {
        const std::string a = p.get("--up-axis");
        const bool negative = !a.empty() && a[0] == '-';
        const std::string name = a.substr(!a.empty() && (a[0] == '-' || a[0] == '+') ? 1 : 0);
        if (name != "x" && name != "y" && name != "z")
            throw UsageError("--up-axis must be x, y or z (optionally -x, -y, -z), got '" + a + "'");
        Vec3f up{0, 0, 0};
        up[name[0] - 'x'] = negative ? -1.0f : 1.0f;
        v.up_axis = up;
    }
    if (p.has("--look-from")) v.look_from = parse_xyz(p, "--look-from");
    if (p.has("--look-at")) v.look_at = parse_xyz(p, "--look-at");
    if (p.has("--up")) {
        v.up = parse_xyz(p, "--up");
        if ((*v.up)[0] == 0 && (*v.up)[1] == 0 && (*v.up)[2] == 0) throw UsageError("--up must not be the zero vector");
    }
    if (p.has("--fov")) v.yfov_deg = float(p.get_double("--fov", 0.1, 179.0));
    return v;
}

HairColorOverride hair_color_options(const ArgParser& p) {
    HairColorOverride o;
    const bool melanin = p.has("--hair-preset") || p.has("--eumelanin") || p.has("--pheomelanin");
    const int sources = (melanin ? 1 : 0) + (p.has("--hair-color") ? 1 : 0) + (p.has("--sigma-a") ? 1 : 0);
    if (sources > 1)
        throw UsageError("give only one of --hair-preset/--eumelanin/--pheomelanin, --hair-color and --sigma-a");
    if (melanin) {
        o.kind = HairColorOverride::Melanin;
        if (p.has("--hair-preset")) {
            const HairPreset* preset = find_hair_preset(p.get("--hair-preset"));
            if (!preset) {
                std::string known;
                for (const HairPreset& h : hair_presets()) known += (known.empty() ? "" : ", ") + std::string(h.name);
                throw UsageError("unknown --hair-preset '" + p.get("--hair-preset") + "' (known: " + known + ")");
            }
            o.eumelanin = preset->eumelanin, o.pheomelanin = preset->pheomelanin;
        }
        if (p.has("--eumelanin")) o.eumelanin = float(p.get_double("--eumelanin", 0.0, 50.0));
        if (p.has("--pheomelanin")) o.pheomelanin = float(p.get_double("--pheomelanin", 0.0, 50.0));
    } else if (p.has("--hair-color")) {
        const std::vector<double> c = parse_number_list("--hair-color", p.get("--hair-color"), 3, "r,g,b");
        for (double x : c)
            if (!(x > 0.0 && x <= 1.0)) throw UsageError("--hair-color components must be in (0, 1], got '" + p.get("--hair-color") + "'");
        o.kind = HairColorOverride::Color;
        o.color = {float(c[0]), float(c[1]), float(c[2])};
    }
    return o;
}

void apply_hair_color(const HairColorOverride& o, Scene& scene) {
    for (HairMaterialDesc& m : scene.materials) {
        if (o.kind == HairColorOverride::Melanin) {
            m.has_sigma_a = m.has_color = false;
            m.has_melanin = true;
            m.eumelanin = o.eumelanin, m.pheomelanin = o.pheomelanin;
        } else if (o.kind == HairColorOverride::Color) {
            m.has_sigma_a = m.has_melanin = false;
            m.has_color = true;
            m.color = o.color;
        }
    }
}

Vec3f parse_rgb(const std::string& opt, const std::string& s) {
    if (s.find(',') == std::string::npos) {
        const double grey = parse_number_list(opt, s, 1, "r,g,b")[0];
        return {float(grey), float(grey), float(grey)};
    }
    const std::vector<double> v = parse_number_list(opt, s, 3, "r,g,b");
    return {float(v[0]), float(v[1]), float(v[2])};
}


}  // namespace ht
