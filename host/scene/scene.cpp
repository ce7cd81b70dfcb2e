// Scene-level operations: loader dispatch, bounds, hashing.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "core/constants.h"
#include "core/hash.h"
#include "scene/hair_presets.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

std::string lower_extension(const std::string& path) {
    const size_t slash = path.find_last_of("/\\");
    const size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// Invariants everything downstream relies on; a loader that breaks them has a bug.
void check_scene_invariants(const Scene& s) {
    if (s.strands.strand_count() == 0)
        scene_fail(s.source, "the scene holds no hair strands");
    if (s.materials.empty()) scene_fail(s.source, "the scene has no hair material");
    for (uint32_t m : s.strands.material)
        if (m >= s.materials.size())
            scene_fail(s.source, "a strand refers to material ", m, " of ", s.materials.size());
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        const Mesh& m = s.meshes[i];
        if (m.indices.size() % 3 != 0)
            scene_fail(s.source, "mesh ", i, ": ", m.indices.size(), " indices is not whole triangles");
        if (m.material >= s.surface_materials.size())
            scene_fail(s.source, "mesh ", i, " refers to surface material ", m.material, " of ",
                       s.surface_materials.size());
        if (!m.normals.empty() && m.normals.size() != m.positions.size())
            scene_fail(s.source, "mesh ", i, ": ", m.normals.size(), " normals for ",
                       m.positions.size(), " positions");
        for (uint32_t v : m.indices)
            if (v >= m.positions.size())
                scene_fail(s.source, "mesh ", i, ": index ", v, " out of range (", m.positions.size(),
                           " positions)");
        if (!m.uvs.empty() && m.uvs.size() != m.positions.size())
            scene_fail(s.source, "mesh ", i, ": ", m.uvs.size(), " texture coordinates for ",
                       m.positions.size(), " positions");
    }
    for (size_t i = 0; i < s.surface_materials.size(); ++i) {
        const int32_t t = s.surface_materials[i].texture;
        if (t >= 0 && static_cast<size_t>(t) >= s.textures.size())
            scene_fail(s.source, "surface material ", i, " refers to texture ", t, " of ", s.textures.size());
    }
    for (size_t i = 0; i < s.textures.size(); ++i) {
        const Texture& t = s.textures[i];
        if (t.width == 0 || t.height == 0 || t.texels.size() != uint64_t(t.width) * t.height)
            scene_fail(s.source, "texture ", i, " is ", t.width, " x ", t.height, " but holds ",
                       t.texels.size(), " texels");
    }
    // Camera and lights feed ray generation and light sampling directly: one non-finite value
    // would turn the whole image into NaN, so refuse it here for every loader (found by fuzzing).
    auto finite3 = [](const Vec3f& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
    if (s.has_camera) {
        const Camera& c = s.camera;
        if (!finite3(c.eye) || !finite3(c.target) || !finite3(c.up))
            scene_fail(s.source, "camera position, target or up vector is not finite");
        if (!(c.yfov_deg > 0.0f && c.yfov_deg < 180.0f))
            scene_fail(s.source, "camera vertical field of view ", c.yfov_deg, " is outside (0, 180) degrees");
        if (c.has_aspect && !(std::isfinite(c.aspect) && c.aspect > 0.0f))
            scene_fail(s.source, "camera aspect ratio ", c.aspect, " is not a positive finite number");
    }
    for (size_t i = 0; i < s.lights.size(); ++i) {
        const Light& l = s.lights[i];
        if (!finite3(l.position) || !finite3(l.direction) || !finite3(l.color))
            scene_fail(s.source, "light ", i, ": position, direction or colour is not finite");
        if (!(std::isfinite(l.intensity) && l.intensity >= 0.0f))
            scene_fail(s.source, "light ", i, ": intensity ", l.intensity, " is not a finite number >= 0");
        if (!(std::isfinite(l.radius) && l.radius >= 0.0f))
            scene_fail(s.source, "light ", i, ": radius ", l.radius, " is not a finite number >= 0");
        if (!(std::isfinite(l.inner_cone_deg) && std::isfinite(l.outer_cone_deg)))
            scene_fail(s.source, "light ", i, ": spot cone angles are not finite");
    }
}

}  // namespace

size_t Strands::segment_count() const {
    // Every strand has at least one point, so (points - strands) counts the segments.
    return strand_count() == 0 ? 0 : point_count() - strand_count();
}

Scene load_scene(const std::string& path, const LoadOptions& opt) {
    static const std::string kBuiltin = "builtin:";
    Scene scene;
    if (path.compare(0, kBuiltin.size(), kBuiltin) == 0) {
        scene = make_builtin(path.substr(kBuiltin.size()), opt);
    } else {
        const std::string ext = lower_extension(path);
        if (ext == ".hair")
            scene = load_hair_file(path, opt);
        else if (ext == ".data")
            scene = load_usc_data(path, opt);
        else if (ext == ".gltf" || ext == ".glb")
            scene = load_gltf(path, opt);
        else if (ext == ".ply")
            scene = load_ply_file(path, opt);
        else if (ext == ".obj")
            scene = load_obj_file(path, opt);
        else if (ext == ".pbrt" || ext == ".gz")
            scene = load_pbrt_file(path, opt);
        else
            scene_fail(path, "unknown scene type '", ext.empty() ? std::string("(none)") : ext,
                       "' (known: .hair, .data, .gltf, .glb, .ply, .obj, .pbrt, .pbrt.gz, builtin:strand, builtin:ball)");
    }
    scene.source = path;
    check_scene_invariants(scene);
    return scene;
}

HairMaterialDesc blond_hair_material() {
    // The melanin of real blond hair, as the shipped scenes have it: golden, where a sigma_a of
    // half that absorption (0.06, 0.10, 0.20) rendered a nearly grey light blond.
    const HairPreset& blond = *find_hair_preset("blond");
    HairMaterialDesc m;
    m.name = "blond";
    m.model = "marschner";
    m.has_melanin = true;
    m.eumelanin = blond.eumelanin;
    m.pheomelanin = blond.pheomelanin;
    m.eta = 1.55f;
    return m;
}

Bounds scene_bounds(const Scene& s) {
    const Strands& st = s.strands;
    if (st.points.empty()) return {};
    Bounds b;
    const float inf = std::numeric_limits<float>::infinity();
    b.lo = {inf, inf, inf};
    b.hi = {-inf, -inf, -inf};
    for (size_t i = 0; i < st.points.size(); ++i) {
        const float r = i < st.radius.size() ? st.radius[i] : 0.0f;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], st.points[i][a] - r);
            b.hi[a] = std::max(b.hi[a], st.points[i][a] + r);
        }
    }
    return b;
}

uint64_t strands_content_hash(const Strands& s) {
    uint64_t h = fnv1a(s.first_point);
    h = fnv1a(s.points, h);
    h = fnv1a(s.radius, h);
    return fnv1a(s.material, h);
}

}  // namespace ht
