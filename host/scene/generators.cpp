// Built-in procedural scenes, deterministic (see rng.h), with their camera, light and material.
//
//   builtin:strand  the paper's Fig. 5 subject: one long blond lock hanging along -y from
//                   y = +50, hairs 90..100 units long, roots uniform in a 20 x 7 ellipse that
//                   fans out to 1.6x towards the tips, a coherent wave in x (wavelength 30,
//                   amplitude 2.4..3.6, phase jitter +-0.25 rad), a weaker wave in z and small
//                   per-hair wiggles.  2,500 hairs x 100 segments.  Seen from +z, lit from the
//                   upper front right.
//   builtin:ball    curly hair ball: roots uniform on a sphere of radius 20 (the sphere is not
//                   geometry); each hair a helix (curl radius 1.5..2.5, 2.5..3.5 turns, random
//                   handedness) around an axis tilted randomly from the surface normal, axial
//                   length 19.2..28.8, the curl growing in over the first 15 %.
//                   10,000 hairs x 30 segments.
//   builtin:slab    a planar layer of straight, parallel hairs hanging along -y: roots uniform
//                   over x in [-20, 20], z in [-10, 0], length 40; 8,000 hairs x 20 segments,
//                   about 32 fibres across its depth.  Seen straight on from +z (the middle
//                   20 x 20, away from the edges), lit by a distant light 30 degrees off that
//                   axis: the geometry where multiple scattering is one-dimensional, as dual
//                   scattering pictures it (docs/MODEL.md §13).
//
// All use fibre radius 0.1 (1/1000 of the ~100-unit scene) and blond_hair_material().
// Parameters: "NAME?hairs=N&segments=N&seed=N&radius=R" (documented at make_builtin in scene.h).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <glm/glm.hpp>
#include <map>

#include "core/constants.h"
#include "scene/hygiene.h"
#include "scene/rng.h"
#include "scene/scene_error.h"

namespace ht {

namespace {


struct BuiltinParams {
    uint64_t hairs = 0;
    uint64_t segments = 0;
    uint64_t seed = 0;
    float radius = 0.1f;
};

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

glm::dvec3 random_unit_vector(Pcg32& rng) {
    const double z = rng.uniform(-1.0, 1.0);  // uniform z = uniform area on the sphere
    const double phi = 2.0 * kPi * rng.uniform();
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {rho * std::cos(phi), rho * std::sin(phi), z};
}

Vec3f to_vec3f(const glm::dvec3& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

uint64_t parse_uint(const std::string& spec, const std::string& key, const std::string& text,
                    uint64_t lo, uint64_t hi) {
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (text.empty() || text[0] == '-' || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        scene_fail("builtin:" + spec, key, " must be an integer in ", lo, "..", hi, " (got '",
                   text, "')");
    return v;
}

float parse_radius(const std::string& spec, const std::string& text) {
    char* end = nullptr;
    const float v = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0f))
        scene_fail("builtin:" + spec, "radius must be a positive number (got '", text, "')");
    return v;
}

// Splits "NAME?k=v&k=v" and fills params over the defaults.
std::string parse_spec(const std::string& spec, BuiltinParams& params) {
    const size_t q = spec.find('?');
    const std::string name = spec.substr(0, q);
    if (name == "strand") {
        params.hairs = 2500, params.segments = 100, params.seed = 20040001;
    } else if (name == "ball") {
        params.hairs = 10000, params.segments = 30, params.seed = 20040002;
    } else if (name == "slab") {
        params.hairs = 8000, params.segments = 20, params.seed = 20080001;
    } else {
        scene_fail("builtin:" + spec, "unknown builtin scene '", name, "' (known: strand, ball, slab)");
    }
    if (q == std::string::npos) return name;
    std::string rest = spec.substr(q + 1);
    size_t pos = 0;
    while (pos <= rest.size()) {
        const size_t amp = std::min(rest.find('&', pos), rest.size());
        const std::string item = rest.substr(pos, amp - pos);
        pos = amp + 1;
        if (item.empty()) continue;
        const size_t eq = item.find('=');
        if (eq == std::string::npos)
            scene_fail("builtin:" + spec, "parameter '", item, "' is not KEY=VALUE");
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        if (key == "hairs")
            params.hairs = parse_uint(spec, key, value, 1, kMaxScenePoints / 2);
        else if (key == "segments")
            params.segments = parse_uint(spec, key, value, 1, 65535);
        else if (key == "seed")
            params.seed = parse_uint(spec, key, value, 0, ~uint64_t(0));
        else if (key == "radius")
            params.radius = parse_radius(spec, value);
        else
            scene_fail("builtin:" + spec, "unknown parameter '", key,
                       "' (known: hairs, segments, seed, radius)");
    }
    return name;
}

// Fills s with `hairs` strands of `segments + 1` points; shape(rng, points) writes one hair.
template <typename Shape>
void generate(Strands& s, const BuiltinParams& p, Shape shape) {
    const size_t per_strand = p.segments + 1;
    s.points.resize(p.hairs * per_strand);
    s.radius.assign(p.hairs * per_strand, p.radius);
    s.first_point.resize(p.hairs + 1);
    s.material.assign(p.hairs, 0);
    for (uint64_t i = 0; i < p.hairs; ++i) {
        Pcg32 rng(p.seed, i);
        s.first_point[i] = static_cast<uint32_t>(i * per_strand);
        shape(rng, &s.points[i * per_strand]);
    }
    s.first_point[p.hairs] = static_cast<uint32_t>(p.hairs * per_strand);
}

void make_strand(Scene& scene, const BuiltinParams& p) {
    const double top = 50.0, full_length = 100.0, wavelength = 30.0;
    const double root_half_x = 10.0, root_half_z = 3.5, wiggle = 0.3;
    const uint64_t segments = p.segments;
    generate(scene.strands, p, [&](Pcg32& rng, Vec3f* out) {
        // Root uniform in the ellipse (sqrt: uniform in area).
        const double rr = std::sqrt(rng.uniform()), root_angle = 2.0 * kPi * rng.uniform();
        const double x0 = root_half_x * rr * std::cos(root_angle);
        const double z0 = root_half_z * rr * std::sin(root_angle);
        const double length = full_length * rng.uniform(0.9, 1.0);
        // The lock's coherent wave, shared by all hairs up to a small phase and amplitude jitter.
        const double amp_x = rng.uniform(2.4, 3.6), phase_x = rng.uniform(-0.25, 0.25);
        const double amp_z = rng.uniform(0.0, 0.8), phase_z = 2.0 * kPi * rng.uniform();
        // Per-hair wiggles: a few low-frequency periods along the hair.
        const double fx = rng.uniform(2.0, 5.0), px = 2.0 * kPi * rng.uniform();
        const double fz = rng.uniform(2.0, 5.0), pz = 2.0 * kPi * rng.uniform();
        for (uint64_t k = 0; k <= segments; ++k) {
            const double t = double(k) / double(segments);
            const double along = t * length;
            const double fan = 1.0 + 0.6 * t * t;
            const double settle = smoothstep(0.0, 0.1, t);  // roots leave the scalp straight
            const double x = x0 * fan + settle * (amp_x * std::sin(2.0 * kPi * along / wavelength + phase_x) +
                                                  wiggle * std::sin(2.0 * kPi * fx * t + px));
            const double z = z0 * fan + settle * (amp_z * std::sin(2.0 * kPi * along / (1.4 * wavelength) + phase_z) +
                                                  wiggle * std::sin(2.0 * kPi * fz * t + pz));
            out[k] = to_vec3f({x, top - along, z});
        }
    });

    // Like Fig. 5: the whole lock in view from the front, light from the upper front side.
    scene.has_camera = true;
    scene.camera.eye = {0.0f, 0.0f, 200.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.yfov_deg = 30.0f;
    Light key;
    key.type = LightType::Point;
    key.position = {70.0f, 110.0f, 140.0f};
    key.intensity = 70.0f * 70.0f + 110.0f * 110.0f + 140.0f * 140.0f;  // irradiance 1 at origin
    scene.lights.push_back(key);
}

void make_ball(Scene& scene, const BuiltinParams& p) {
    const double sphere_radius = 20.0;
    const uint64_t segments = p.segments;
    generate(scene.strands, p, [&](Pcg32& rng, Vec3f* out) {
        const glm::dvec3 normal = random_unit_vector(rng);
        const glm::dvec3 root = sphere_radius * normal;
        const glm::dvec3 axis = glm::normalize(normal + 0.25 * random_unit_vector(rng));
        const double length = rng.uniform(19.2, 28.8);
        const double curl = rng.uniform(1.5, 2.5), turns = rng.uniform(2.5, 3.5);
        const double phase = 2.0 * kPi * rng.uniform();
        const double handedness = rng.uniform() < 0.5 ? -1.0 : 1.0;
        const glm::dvec3 helper = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 e1 = glm::normalize(glm::cross(helper, axis));
        const glm::dvec3 e2 = glm::cross(axis, e1);
        for (uint64_t k = 0; k <= segments; ++k) {
            const double t = double(k) / double(segments);
            const double angle = phase + handedness * 2.0 * kPi * turns * t;
            const double r = curl * smoothstep(0.0, 0.15, t);
            // Offsets relative to the helix start so that every hair begins at its root.
            const glm::dvec3 p = root + axis * (t * length) +
                                 r * ((std::cos(angle) - std::cos(phase)) * e1 +
                                      (std::sin(angle) - std::sin(phase)) * e2);
            out[k] = to_vec3f(p);
        }
    });

    scene.has_camera = true;
    const glm::dvec3 eye = 195.0 * glm::normalize(glm::dvec3(0.35, 0.45, 1.0));
    scene.camera.eye = to_vec3f(eye);
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.yfov_deg = 30.0f;
    Light key;
    key.type = LightType::Point;
    key.position = {90.0f, 120.0f, 110.0f};
    key.intensity = 90.0f * 90.0f + 120.0f * 120.0f + 110.0f * 110.0f;
    scene.lights.push_back(key);
}

void make_slab(Scene& scene, const BuiltinParams& p) {
    const double half_width = 20.0, depth = 10.0, length = 40.0;
    const uint64_t segments = p.segments;
    generate(scene.strands, p, [&](Pcg32& rng, Vec3f* out) {
        const double x = rng.uniform(-half_width, half_width), z = rng.uniform(-depth, 0.0);
        for (uint64_t k = 0; k <= segments; ++k)
            out[k] = to_vec3f({x, 0.5 * length - length * double(k) / double(segments), z});
    });
    scene.has_camera = true;
    scene.camera.eye = {0.0f, 0.0f, 100.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.yfov_deg = 11.4f;  // 2 atan(10 / 100): the middle 20 x 20 of the front face
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = to_vec3f(glm::normalize(glm::dvec3(-0.5, 0.0, -std::sqrt(0.75))));  // 30 degrees off -z
    sun.intensity = 1.0f;
    scene.lights.push_back(sun);
}

}  // namespace

Scene make_builtin(const std::string& spec, const LoadOptions& opt) {
    BuiltinParams params;
    const std::string name = parse_spec(spec, params);
    const std::string source = "builtin:" + spec;
    check_scene_size(source, str_cat(params.hairs, " hairs x ", params.segments, " segments"),
                     params.hairs, params.hairs * (params.segments + 1), opt);
    Scene scene;
    scene.source = source;
    scene.materials.push_back(blond_hair_material());
    if (name == "strand")
        make_strand(scene, params);
    else if (name == "ball")
        make_ball(scene, params);
    else
        make_slab(scene, params);
    add_hygiene_warnings(scene, source, sanitize_strands(scene.strands, source));
    return scene;
}

}  // namespace ht
