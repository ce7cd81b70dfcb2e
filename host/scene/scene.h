// In-memory scene: what every loader produces and everything downstream consumes.
#pragma once

#include "core/errors.h"

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ht {

using Vec3f = std::array<float, 3>;

// A bad scene file or scene description.  what() is one line naming the file and the problem.
// Hair strands: strand s owns points [first_point[s], first_point[s+1]).
struct Strands {
    std::vector<Vec3f> points;
    std::vector<float> radius;          // per point, > 0
    std::vector<uint32_t> first_point;  // size strand_count + 1
    std::vector<uint32_t> material;     // per strand, index into Scene::materials

    size_t strand_count() const { return first_point.empty() ? 0 : first_point.size() - 1; }
    size_t point_count() const { return points.size(); }
    size_t segment_count() const;  // sum over strands of (points - 1)
};

// Diffuse (Lambertian) surface material of a triangle mesh: albedo = albedo x the base colour
// texture (decoded to linear) at the hit's TEXCOORD_0 when texture >= 0.
struct SurfaceMaterialDesc {
    std::string name = "surface";
    Vec3f albedo{0.8f, 0.8f, 0.8f};  // glTF baseColorFactor rgb, each in [0, 1]
    int32_t texture = -1;            // index into Scene::textures, -1: none
};

enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };

// A decoded base colour texture: the image's 8-bit sRGB values, one uint32 per texel
// (r | g << 8 | b << 16, alpha dropped), row 0 = the top of the image = glTF v 0.  Kept encoded
// (not linear float) to use a quarter of the memory; kernels/surface/texture.h decodes.
struct Texture {
    std::string name;  // for messages and --verbose, e.g. "image 0 \"checker.png\""
    uint32_t width = 0, height = 0;
    TextureWrap wrap_s = TextureWrap::Repeat, wrap_t = TextureWrap::Repeat;
    std::vector<uint32_t> texels;  // width * height
};

// A triangle mesh in world space (node transforms applied by the loader).  Triangle k is
// positions[indices[3k + 0..2]], counter-clockwise front face (glTF).  normals and uvs are
// per vertex, empty when the file has none (the geometric normal is used then).
struct Mesh {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    std::vector<Vec3f> normals;                  // optional, unit length
    std::vector<std::array<float, 2>> uvs;       // optional TEXCOORD_0, finite
    uint32_t material = 0;                       // index into Scene::surface_materials

    size_t triangle_count() const { return indices.size() / 3; }
};

struct Camera {
    Vec3f eye{0, 0, 10};
    Vec3f target{0, 0, 0};
    Vec3f up{0, 1, 0};
    float yfov_deg = 30.0f;
    bool has_aspect = false;
    float aspect = 1.0f;  // width / height if the scene states it
};

enum class LightType { Point, Spot, Directional, Sphere };
struct Light {
    LightType type = LightType::Point;
    Vec3f position{0, 0, 0};
    Vec3f direction{0, -1, 0};  // direction light travels
    Vec3f color{1, 1, 1};
    float intensity = 1.0f;     // W/sr (point/spot), lux-like irradiance (directional)
    float radius = 0.0f;        // sphere lights
    float inner_cone_deg = 0.0f, outer_cone_deg = 45.0f;
};

// Hair material as the user states it.  Validation and conversion to the kernel layout
// (HtMaterial) happen in one place: host/fiber/material.h.
struct HairMaterialDesc {
    std::string name = "hair";
    std::string model = "marschner";  // kajiya | marschner | zinke | chiang
    // absorption: sigma_a per unit radius, or melanin concentrations, or a target colour
    bool has_sigma_a = false;
    Vec3f sigma_a{0.1f, 0.1f, 0.1f};
    bool has_melanin = false;
    float eumelanin = 0.0f, pheomelanin = 0.0f;
    bool has_color = false;
    Vec3f color{0.8f, 0.6f, 0.4f};
    // Absorption from sigma_a alone, melanin and colour dropped (--sigma-a).
    void set_sigma_a(const Vec3f& s) {
        has_sigma_a = true;
        has_melanin = has_color = false;
        sigma_a = s;
    }
    float eta = 1.55f;
    float beta_m = 0.3f, beta_n = 0.3f, alpha_deg = 2.0f;
    // Marschner / Zinke parameters (degrees)
    float alpha_r_deg = -7.5f, beta_r_deg = 7.5f;
    float caustic_wc_deg = 15.0f, caustic_kg = 2.5f, caustic_deta = 0.3f, caustic_dhm = 0.5f;
    float eccentricity = 1.0f;
    // Kajiya-Kay
    Vec3f kd{0.6f, 0.45f, 0.3f};
    Vec3f ks{0.3f, 0.3f, 0.3f};
    float ks_exponent = 40.0f;
};

// Light arriving from infinitely far away: a lat-long HDR map (EXR/HDR, +y up) scaled by
// `intensity`, or, with no map, the uniform radiance `color * intensity`.
struct Environment {
    std::string map_path;
    Vec3f color{0, 0, 0};
    float intensity = 1.0f;
    bool enabled() const { return !map_path.empty() || color[0] > 0 || color[1] > 0 || color[2] > 0; }
};

struct Scene {
    std::string source;  // file name or builtin:NAME, for messages and metadata
    Strands strands;
    std::vector<HairMaterialDesc> materials;  // at least one
    std::vector<Mesh> meshes;                          // triangle surfaces (head, scalp, floor)
    std::vector<SurfaceMaterialDesc> surface_materials;  // indexed by Mesh::material
    std::vector<Texture> textures;                     // indexed by SurfaceMaterialDesc::texture
    bool has_camera = false;
    Camera camera;
    std::vector<Light> lights;
    Environment environment;
    std::vector<std::string> warnings;  // repairs made while loading (counted, one line each)
};

struct LoadOptions {
    bool thickness_is_diameter = false;  // .hair: thickness is the radius unless stated
    float default_radius = 0.0f;         // > 0 overrides a file's missing radius
    // Refuse scenes whose strand arrays, or whose textures together, would need more memory
    // than this (checked against the counts and image sizes a file states, before anything is
    // allocated or decoded).
    uint64_t max_bytes = uint64_t(16) << 30;
    // glTF: which camera of the file to use (index into its cameras); -1: the first one met.
    int camera_index = -1;
};

// Dispatch on the extension or the builtin: prefix.  Throws SceneError.
Scene load_scene(const std::string& path, const LoadOptions& opt = {});

// Individual loaders (throw SceneError).
Scene load_hair_file(const std::string& path, const LoadOptions& opt);
Scene load_usc_data(const std::string& path, const LoadOptions& opt);
Scene load_gltf(const std::string& path, const LoadOptions& opt);
Scene load_ply_file(const std::string& path, const LoadOptions& opt);
Scene load_obj_file(const std::string& path, const LoadOptions& opt);
Scene load_pbrt_file(const std::string& path, const LoadOptions& opt);
// Built-in procedural scenes: "strand" (the paper's Fig. 5 blond lock, 2,500 x 100 segments),
// "ball" (curly hair ball, 10,000 x 30) and "slab" (a planar layer of straight hairs, 8,000 x 20),
// optionally with parameters after '?':
//   hairs=N      number of strands (default 2500 / 10000 / 8000)
//   segments=N   segments per strand (default 100 / 30 / 20)
//   seed=N       RNG seed (default 20040001 / 20040002 / 20080001)
//   radius=R     fibre radius (default 0.1)
// e.g. "strand?hairs=100&segments=10".  Deterministic: same spec, same bytes.
Scene make_builtin(const std::string& spec, const LoadOptions& opt = {});

// Writes strands as a Cem Yuksel .hair file (segments + points + thickness arrays, thickness =
// radius).  Throws SceneError (unwritable file, strand longer than 65,536 points).
void save_hair_file(const std::string& path, const Scene& scene);
// The Embree anchor's scene content hash of these strands (anchors/embree/README.md "Scenes", and
// the scene hash of its .rays files): FNV-1a 64 over the arrays save_hair_file writes (segments
// per strand as uint16, points, thickness = radius), so it equals the anchor's for a .hair file
// loaded unchanged.  0 when the strands do not fit the format.
uint64_t hair_file_hash(const Strands& s);

// The hair material of files that state none (.hair, .data, .ply, .obj, pbrt, glTF without one,
// the built-ins): golden blond, the `blond` preset's melanin (scene/hair_presets.h), Marschner
// model.
HairMaterialDesc blond_hair_material();

// FNV-1a 64 over the strand arrays (first_point, points, radius, material): equal hashes mean
// equal geometry, bit for bit.
uint64_t strands_content_hash(const Strands& s);

// Axis-aligned bounds of all points inflated by their radius.
struct Bounds {
    Vec3f lo{0, 0, 0}, hi{0, 0, 0};
};
Bounds scene_bounds(const Scene& s);

// What the user says about the view (host/scene/default_view.cpp); unset fields come from the
// scene's own camera, or from the automatic framing when the scene has none.
struct ViewOptions {
    std::optional<Vec3f> up_axis;  // the model's up (+-x, +-y, +-z); unset: detect_up_axis
    std::optional<Vec3f> look_from, look_at, up;
    std::optional<float> yfov_deg;
};

// The model's up direction, a signed unit axis, from its strands' roots and tips (the rule is
// written out in host/scene/default_view.cpp).
Vec3f detect_up_axis(const Strands& strands);

// Gives the scene a camera when it has none (a 3/4 front view from the side of the model's up
// axis, fitted to the hair), applies the view options to it, and adds the key, rim and fill
// light rig when the scene has no light and no environment.
void ensure_camera_and_light(Scene& s, const ViewOptions& view = {});

}  // namespace ht
