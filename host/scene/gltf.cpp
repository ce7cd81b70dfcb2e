// glTF 2.0 scenes (.gltf / .glb) through tinygltf.
//
// What is read, walking the node hierarchy of the default scene (node transforms, given as a
// matrix or as translation/rotation/scale, are applied):
//   * hair: mesh primitives of mode LINES (1) or LINE_STRIP (3).  POSITION (float VEC3) plus an
//     optional per-vertex `_RADIUS` (float SCALAR) attribute in object units, scaled by the
//     node's uniform scale; without it the material's extras.radius (also scaled), else
//     LoadOptions::default_radius, else 1/1000 of the extent of all hair (as for USC .data).
//     LINE_STRIP: one primitive = one strand.  LINES: consecutive segments that share an
//     endpoint (same index or identical position, end of one == start of the next) are chained
//     into one strand.  Hair material: the primitive's material with hair parameters in its
//     extras (gltf_material.h); no material = blond_hair_material().
//   * the first camera met, or camera LoadOptions::camera_index when set (perspective: yfov,
//     aspectRatio); it looks along -Z of its node with +Y up.  Further and orthographic cameras
//     are ignored with a warning.
//   * KHR_lights_punctual point, spot (inner/outer cone) and directional lights: colour and
//     intensity as stated (range is ignored); position = node origin, direction = node -Z.
//   * surfaces: TRIANGLES (4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6) primitives, indexed or
//     not, become Scene::meshes in world space: POSITION, optional NORMAL (transformed with the
//     inverse transpose), optional TEXCOORD_0 (float or normalized unsigned byte / short), a
//     diffuse SurfaceMaterialDesc from pbrMetallicRoughness.baseColorFactor (rgb; no material =
//     grey 0.8) times its baseColorTexture (gltf_texture.h: texCoord 0 only, PNG / JPEG from a
//     file, a data: URI or a bufferView, sampler wrap modes; decoded only for materials that
//     triangles use).  Non-finite positions or texture coordinates are a SceneError; degenerate
//     (zero-area) triangles are dropped with a counted warning; a textured material on a
//     primitive without TEXCOORD_0 uses its factor alone (counted in a warning).
//   * point and line-loop primitives are ignored, counted in a warning.
//   * `"hairtrace_builtin": "strand"` (any make_builtin spec, e.g. "ball?hairs=500") in the
//     scene's or the asset's extras adds that built-in hair; `"hairtrace_material"` (a material
//     index or name) gives it a glTF material, otherwise it keeps its own.  The built-in's camera
//     and light are used only when the file has none.
//   * `"hairtrace_hair": {"uri": "straight.hair", "material": 0}` in a node's extras loads that
//     hair file (any format load_scene reads but glTF; the uri relative to this file's folder),
//     transformed by the node's world transform (radii by its uniform scale, as for LINES), with
//     the glTF material given by index or name, else the file's own.  Schema and errors in
//     scenes/README.md; an example is scenes/straight_on_floor.gltf.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <map>
#include <set>

#include "scene/binary_file.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_material.h"
#include "scene/gltf_texture.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

Vec3f to_vec3f(const glm::dvec3& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

std::string directory_of(const std::string& path) {
    const size_t slash = path.find_last_of("/\\");
    return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

// JSON nested deeper than this is refused before parsing: tinygltf and nlohmann::json recurse
// once per level, and a few ten thousand levels overflow the stack (found by fuzzing).  Real
// glTF files nest a dozen levels.
constexpr int kMaxJsonDepth = 256;

void check_json_depth(const char* text, size_t n, const std::string& path) {
    int depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < n; ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                scene_fail(path, "JSON is nested more than ", kMaxJsonDepth, " levels deep");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

// Reads a .glb after checking its container header against the file, so a truncated file is
// reported as such rather than as whatever tinygltf makes of the remains.
void load_glb(tinygltf::TinyGLTF& loader, tinygltf::Model& model, const std::string& path,
              std::string& err, std::string& warn) {
    std::ifstream in(path, std::ios::binary);
    if (!in) scene_fail(path, "cannot open");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) scene_fail(path, "cannot determine the file size");
    if (size < 20) scene_fail(path, "the file holds ", size, " bytes, too few for a GLB header");
    if (static_cast<uint64_t>(size) >= (uint64_t(1) << 32))
        scene_fail(path, "GLB files of 4 GiB or more are not supported");
    std::vector<unsigned char> bytes(static_cast<size_t>(size));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), size);
    if (in.gcount() != size) scene_fail(path, "read error");
    uint32_t header[5];
    std::memcpy(header, bytes.data(), sizeof header);
    if (std::memcmp(bytes.data(), "glTF", 4) != 0) scene_fail(path, "not a GLB file (bad magic)");
    if (header[1] != 2) scene_fail(path, "GLB version ", header[1], " (only 2 is supported)");
    if (header[2] != static_cast<uint64_t>(size))
        scene_fail(path, "GLB header says ", header[2], " bytes but the file holds ", size);
    if (uint64_t(header[3]) + 20 > static_cast<uint64_t>(size))
        scene_fail(path, "GLB JSON chunk of ", header[3], " bytes exceeds the file (", size,
                   " bytes)");
    check_json_depth(reinterpret_cast<const char*>(bytes.data()) + 20, header[3], path);
    if (!loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                     static_cast<unsigned int>(size), directory_of(path)))
        scene_fail(path, "glTF parse error: ", err.empty() ? std::string("unknown") : err);
}

struct StrandLabel {
    size_t first_strand;  // first strand (in Strands order) this label covers
    std::string text;     // e.g. "mesh 0 \"hair\" primitive 1"
};

class GltfSceneBuilder {
public:
    GltfSceneBuilder(const std::string& file, const tinygltf::Model& model, const LoadOptions& opt)
        : file_(file), model_(model), opt_(opt),
          textures_(model, file, directory_of(file), opt, scene_.textures) {
        scene_.source = file;
    }

    Scene build() {
        for (int root : root_nodes()) visit(root, glm::dmat4(1.0));
        add_builtin();
        fill_missing_radii();
        finish_warnings();
        if (scene_.strands.strand_count() == 0)
            scene_fail(file_, "no hair: the file holds no LINES or LINE_STRIP primitives",
                       triangle_primitives_ > 0
                           ? str_cat(" (only ", triangle_primitives_,
                                     " triangle primitives; a scene needs hair)")
                           : std::string());
        auto namer = [this](size_t strand) {
            auto it = std::upper_bound(labels_.begin(), labels_.end(), strand,
                                       [](size_t s, const StrandLabel& l) { return s < l.first_strand; });
            const StrandLabel& label = *std::prev(it);
            return str_cat(label.text, " strand ", strand - label.first_strand);
        };
        add_hygiene_warnings(scene_, file_, sanitize_strands(scene_.strands, file_, namer));
        return std::move(scene_);
    }

private:
    std::vector<int> root_nodes() const {
        const int node_count = static_cast<int>(model_.nodes.size());
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (s >= static_cast<int>(model_.scenes.size()))
                scene_fail(file_, "default scene ", s, " does not exist");
            roots = model_.scenes[s].nodes;
        } else {
            // No scenes: every node that is nobody's child is a root.
            std::vector<bool> is_child(node_count, false);
            for (const tinygltf::Node& n : model_.nodes)
                for (int c : n.children)
                    if (c >= 0 && c < node_count) is_child[c] = true;
            for (int i = 0; i < node_count; ++i)
                if (!is_child[i]) roots.push_back(i);
        }
        return roots;
    }

    const tinygltf::Value* scene_extras_value(const char* key) const {
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            const tinygltf::Value& e = model_.scenes[s].extras;
            if (e.IsObject() && e.Has(key)) return &e.Get(key);
        }
        const tinygltf::Value& a = model_.asset.extras;
        if (a.IsObject() && a.Has(key)) return &a.Get(key);
        return nullptr;
    }

    glm::dmat4 local_transform(const tinygltf::Node& n, int index) const {
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16) scene_fail(file_, "node ", index, ": matrix needs 16 numbers");
            return glm::make_mat4(n.matrix.data());  // both glTF and GLM are column-major
        }
        glm::dmat4 m(1.0);
        if (!n.translation.empty()) {
            if (n.translation.size() != 3)
                scene_fail(file_, "node ", index, ": translation needs 3 numbers");
            m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
        }
        if (!n.rotation.empty()) {
            if (n.rotation.size() != 4)
                scene_fail(file_, "node ", index, ": rotation needs 4 numbers");
            // glTF stores (x, y, z, w); glm::dquat's constructor takes w first.
            const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
            if (!(glm::length(q) > 0.0)) scene_fail(file_, "node ", index, ": zero rotation quaternion");
            m = m * glm::mat4_cast(glm::normalize(q));
        }
        if (!n.scale.empty()) {
            if (n.scale.size() != 3) scene_fail(file_, "node ", index, ": scale needs 3 numbers");
            m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
        }
        return m;
    }

    // Depth-first over the node tree with an explicit stack: a hostile file may chain nodes
    // deeper than the call stack allows.
    void visit(int root, const glm::dmat4& root_parent) {
        std::vector<std::pair<int, glm::dmat4>> todo{{root, root_parent}};
        while (!todo.empty()) {
            const auto [index, parent] = todo.back();
            todo.pop_back();
            if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
                scene_fail(file_, "node ", index, " does not exist");
            if (visited_.size() < model_.nodes.size()) visited_.resize(model_.nodes.size(), false);
            // glTF node hierarchies are strict trees; a second visit means a cycle or shared child.
            if (visited_[index])
                scene_fail(file_, "node ", index, " is reached twice (node hierarchy is not a tree)");
            visited_[index] = true;
            const tinygltf::Node& node = model_.nodes[index];
            const glm::dmat4 world = parent * local_transform(node, index);
            for (int i = 0; i < 16; ++i)
                if (!std::isfinite(glm::value_ptr(world)[i]))
                    scene_fail(file_, "node ", index, ": transform is not finite");
            if (node.camera >= 0) add_camera(node.camera, world, index);
            const auto light_ext = node.extensions.find("KHR_lights_punctual");
            if (light_ext != node.extensions.end()) add_light(light_ext->second, world, index);
            if (node.mesh >= 0) add_mesh(node.mesh, world, index);
            if (node.extras.IsObject() && node.extras.Has("hairtrace_hair"))
                add_hair_file(node.extras.Get("hairtrace_hair"), world, index);
            // reversed, so children are visited in file order
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) todo.push_back({*c, world});
        }
    }

    void add_camera(int index, const glm::dmat4& world, int node) {
        if (static_cast<size_t>(index) >= model_.cameras.size())
            scene_fail(file_, "node ", node, ": camera ", index, " does not exist");
        const tinygltf::Camera& c = model_.cameras[index];
        if (opt_.camera_index >= 0 && index != opt_.camera_index) {
            ++ignored_cameras_;
            return;
        }
        if (c.type != "perspective") {
            if (index == opt_.camera_index) scene_fail(file_, "camera ", index, " is ", c.type, ", not perspective");
            ++ignored_cameras_;
            return;
        }
        if (scene_.has_camera) {
            ++ignored_cameras_;
            return;
        }
        const glm::dvec3 eye(world[3]);
        const glm::dmat3 basis(world);
        const glm::dvec3 forward = basis * glm::dvec3(0, 0, -1), up = basis * glm::dvec3(0, 1, 0);
        if (!(glm::length(forward) > 0.0) || !(glm::length(up) > 0.0) ||
            !(glm::length(glm::cross(forward, up)) > 0.0))
            scene_fail(file_, "node ", node, ": camera transform is degenerate");
        if (!(c.perspective.yfov > 0.0) || !(c.perspective.yfov < 3.14159))
            scene_fail(file_, "camera ", index, ": yfov ", c.perspective.yfov,
                       " is not in (0, pi) radians");
        Camera& cam = scene_.camera;
        cam.eye = to_vec3f(eye);
        // Only the direction matters: the target is one unit in front of the eye.
        cam.target = to_vec3f(eye + glm::normalize(forward));
        cam.up = to_vec3f(glm::normalize(up));
        cam.yfov_deg = static_cast<float>(c.perspective.yfov * kRadToDeg);
        cam.has_aspect = c.perspective.aspectRatio > 0.0;
        cam.aspect = cam.has_aspect ? static_cast<float>(c.perspective.aspectRatio) : 1.0f;
        scene_.has_camera = true;
    }

    void add_light(const tinygltf::Value& ext, const glm::dmat4& world, int node) {
        if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsInt())
            scene_fail(file_, "node ", node, ": KHR_lights_punctual needs an integer \"light\"");
        const int index = ext.Get("light").Get<int>();
        if (index < 0 || static_cast<size_t>(index) >= model_.lights.size())
            scene_fail(file_, "node ", node, ": light ", index, " does not exist");
        const tinygltf::Light& l = model_.lights[index];
        Light light;
        if (l.type == "point")
            light.type = LightType::Point;
        else if (l.type == "spot")
            light.type = LightType::Spot;
        else if (l.type == "directional")
            light.type = LightType::Directional;
        else
            scene_fail(file_, "light ", index, ": unknown type \"", l.type, "\"");
        light.position = to_vec3f(glm::dvec3(world[3]));
        const glm::dvec3 dir = glm::dmat3(world) * glm::dvec3(0, 0, -1);
        if (!(glm::length(dir) > 0.0)) scene_fail(file_, "node ", node, ": light transform is degenerate");
        light.direction = to_vec3f(glm::normalize(dir));
        if (!l.color.empty()) {
            if (l.color.size() != 3) scene_fail(file_, "light ", index, ": color needs 3 numbers");
            light.color = to_vec3f({l.color[0], l.color[1], l.color[2]});
        }
        light.intensity = static_cast<float>(l.intensity);
        if (!std::isfinite(light.intensity) || light.intensity < 0.0f)
            scene_fail(file_, "light ", index, ": intensity ", l.intensity, " is not a finite number >= 0");
        if (light.type == LightType::Spot) {
            const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
            if (!(inner >= 0.0 && inner < outer && outer <= 1.5707963268))
                scene_fail(file_, "light ", index, ": spot cone angles need 0 <= inner (", inner,
                           ") < outer (", outer, ") <= pi/2");
            light.inner_cone_deg = static_cast<float>(inner * kRadToDeg);
            light.outer_cone_deg = static_cast<float>(outer * kRadToDeg);
        }
        scene_.lights.push_back(light);
    }

    uint32_t material_index(int gltf_material) {
        if (gltf_material < 0) {
            if (default_material_ < 0) {
                default_material_ = static_cast<int>(scene_.materials.size());
                scene_.materials.push_back(blond_hair_material());
            }
            return static_cast<uint32_t>(default_material_);
        }
        if (static_cast<size_t>(gltf_material) >= model_.materials.size())
            scene_fail(file_, "material ", gltf_material, " does not exist");
        const auto it = material_map_.find(gltf_material);
        if (it != material_map_.end()) return it->second;
        const uint32_t index = static_cast<uint32_t>(scene_.materials.size());
        scene_.materials.push_back(hair_material_from_gltf(model_.materials[gltf_material],
                                                           gltf_material, file_, unknown_keys_));
        material_map_[gltf_material] = index;
        return index;
    }

    void add_mesh(int mesh_index, const glm::dmat4& world, int node) {
        if (static_cast<size_t>(mesh_index) >= model_.meshes.size())
            scene_fail(file_, "node ", node, ": mesh ", mesh_index, " does not exist");
        const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_STRIP) {
                const std::string label =
                    mesh.name.empty() ? str_cat("mesh ", mesh_index, " primitive ", p)
                                      : str_cat("mesh ", mesh_index, " \"", mesh.name, "\" primitive ", p);
                add_hair_primitive(prim, mode, label, world, node);
            } else if (mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
                       mode == TINYGLTF_MODE_TRIANGLE_FAN) {
                ++triangle_primitives_;
                const std::string label =
                    mesh.name.empty() ? str_cat("mesh ", mesh_index, " primitive ", p)
                                      : str_cat("mesh ", mesh_index, " \"", mesh.name, "\" primitive ", p);
                add_triangle_primitive(prim, mode, label, world);
            } else {
                ++other_primitives_;  // POINTS, LINE_LOOP, or an invalid mode
            }
        }
    }

    uint32_t surface_material_index(int gltf_material) {
        if (gltf_material < 0) {
            if (default_surface_material_ < 0) {
                default_surface_material_ = static_cast<int>(scene_.surface_materials.size());
                scene_.surface_materials.push_back(SurfaceMaterialDesc{});
            }
            return static_cast<uint32_t>(default_surface_material_);
        }
        if (static_cast<size_t>(gltf_material) >= model_.materials.size())
            scene_fail(file_, "material ", gltf_material, " does not exist");
        const auto it = surface_material_map_.find(gltf_material);
        if (it != surface_material_map_.end()) return it->second;
        const tinygltf::Material& gm = model_.materials[gltf_material];
        SurfaceMaterialDesc m;
        m.name = gm.name.empty() ? str_cat("material ", gltf_material) : gm.name;
        const std::vector<double>& f = gm.pbrMetallicRoughness.baseColorFactor;
        if (f.size() < 3)
            scene_fail(file_, "material ", gltf_material, ": baseColorFactor needs 4 numbers");
        for (int c = 0; c < 3; ++c) {
            // An albedo above 1 creates energy; refuse it rather than render a glowing surface.
            if (!(f[c] >= 0.0 && f[c] <= 1.0))
                scene_fail(file_, "material ", gltf_material, ": baseColorFactor ", f[c],
                           " is outside [0, 1]");
            m.albedo[c] = static_cast<float>(f[c]);
        }
        m.texture = textures_.base_color_texture(gm, gltf_material);
        const uint32_t index = static_cast<uint32_t>(scene_.surface_materials.size());
        scene_.surface_materials.push_back(m);
        surface_material_map_[gltf_material] = index;
        return index;
    }

    std::vector<Vec3f> read_positions(const tinygltf::Primitive& prim, const std::string& label) const {
        const auto pos_it = prim.attributes.find("POSITION");
        if (pos_it == prim.attributes.end()) scene_fail(file_, label, ": no POSITION attribute");
        return read_float_vec3_accessor(model_, pos_it->second, file_, label + " POSITION");
    }

    // The primitive's vertex sequence: its indices, or 0..n-1 without an index accessor.
    std::vector<uint32_t> vertex_order(const tinygltf::Primitive& prim, size_t vertex_count,
                                       const std::string& label) const {
        if (prim.indices >= 0)
            return read_index_accessor(model_, prim.indices, vertex_count, file_, label + " indices");
        std::vector<uint32_t> order(vertex_count);
        for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>(i);
        return order;
    }

    // A vertex attribute must have one value per POSITION.
    void require_per_vertex(const std::string& label, const char* attribute, size_t values, size_t positions) const {
        if (values != positions)
            scene_fail(file_, label, ": ", attribute, " has ", values, " values for ", positions, " positions");
    }

    void add_triangle_primitive(const tinygltf::Primitive& prim, int mode, const std::string& label,
                                const glm::dmat4& world) {
        const std::vector<Vec3f> positions = read_positions(prim, label);
        std::vector<Vec3f> normals;
        const auto nrm_it = prim.attributes.find("NORMAL");
        if (nrm_it != prim.attributes.end()) {
            normals = read_float_vec3_accessor(model_, nrm_it->second, file_, label + " NORMAL");
            require_per_vertex(label, "NORMAL", normals.size(), positions.size());
        }
        std::vector<std::array<float, 2>> uvs;
        const auto uv_it = prim.attributes.find("TEXCOORD_0");
        if (uv_it != prim.attributes.end()) {
            uvs = read_texcoord_accessor(model_, uv_it->second, file_, label + " TEXCOORD_0");
            require_per_vertex(label, "TEXCOORD_0", uvs.size(), positions.size());
            for (size_t v = 0; v < uvs.size(); ++v)
                if (!(std::isfinite(uvs[v][0]) && std::isfinite(uvs[v][1])))
                    scene_fail(file_, label, ": TEXCOORD_0 of vertex ", v, " is not finite (",
                               uvs[v][0], ", ", uvs[v][1], ")");
        }
        const std::vector<uint32_t> order = vertex_order(prim, positions.size(), label);
        // Strips and fans to a plain triangle list (glTF winding rules, spec §3.7.2.1).
        std::vector<uint32_t> tris;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (order.size() % 3 != 0)
                scene_fail(file_, label, ": TRIANGLES needs a multiple of 3 vertices (got ",
                           order.size(), ")");
            tris = order;
        } else {
            for (size_t i = 2; i < order.size(); ++i) {
                if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
                    tris.insert(tris.end(), {order[0], order[i - 1], order[i]});
                else if (i % 2 == 0)
                    tris.insert(tris.end(), {order[i - 2], order[i - 1], order[i]});
                else
                    tris.insert(tris.end(), {order[i - 1], order[i - 2], order[i]});
            }
        }

        Mesh mesh;
        mesh.material = surface_material_index(prim.material);
        if (scene_.surface_materials[mesh.material].texture >= 0 && uvs.empty())
            ++textured_without_uvs_;
        mesh.uvs = std::move(uvs);
        mesh.positions.reserve(positions.size());
        for (size_t v = 0; v < positions.size(); ++v) {
            const Vec3f& p = positions[v];
            const Vec3f w = to_vec3f(glm::dvec3(world * glm::dvec4(p[0], p[1], p[2], 1.0)));
            if (!(std::isfinite(w[0]) && std::isfinite(w[1]) && std::isfinite(w[2])))
                scene_fail(file_, label, ": vertex ", v, " is not finite");
            mesh.positions.push_back(w);
        }
        if (!normals.empty()) {
            // Normals transform with the inverse transpose (non-uniform scale, mirroring).
            const glm::dmat3 nmat = glm::transpose(glm::inverse(glm::dmat3(world)));
            bool usable = true;
            mesh.normals.reserve(normals.size());
            for (const Vec3f& n : normals) {
                const glm::dvec3 w = nmat * glm::dvec3(n[0], n[1], n[2]);
                const double len = glm::length(w);
                if (!(len > 0.0 && std::isfinite(len))) {
                    usable = false;
                    break;
                }
                mesh.normals.push_back(to_vec3f(w / len));
            }
            if (!usable) {
                // A zero or non-finite normal has no direction to interpolate: fall back to the
                // geometric normal for the whole primitive rather than render a black seam.
                mesh.normals.clear();
                ++bad_normal_primitives_;
            }
        }
        mesh.indices.reserve(tris.size());
        for (size_t t = 0; t + 2 < tris.size(); t += 3) {
            const Vec3f& a = mesh.positions[tris[t]];
            const Vec3f& b = mesh.positions[tris[t + 1]];
            const Vec3f& c = mesh.positions[tris[t + 2]];
            const glm::dvec3 e1(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
            const glm::dvec3 e2(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
            // Zero area (repeated vertices, collinear points): no surface to hit or shade.
            if (!(glm::length(glm::cross(e1, e2)) > 0.0)) {
                ++degenerate_triangles_;
                continue;
            }
            mesh.indices.insert(mesh.indices.end(), {tris[t], tris[t + 1], tris[t + 2]});
        }
        if (!mesh.indices.empty()) scene_.meshes.push_back(std::move(mesh));
    }

    void add_hair_primitive(const tinygltf::Primitive& prim, int mode, const std::string& label,
                            const glm::dmat4& world, int node) {
        const std::vector<Vec3f> positions = read_positions(prim, label);
        std::vector<float> radii;
        const auto rad_it = prim.attributes.find("_RADIUS");
        if (rad_it != prim.attributes.end()) {
            radii = read_float_scalar_accessor(model_, rad_it->second, file_, label + " _RADIUS");
            if (radii.size() != positions.size())
                scene_fail(file_, label, ": _RADIUS has ", radii.size(), " values for ",
                           positions.size(), " positions");
        }
        const std::vector<uint32_t> order = vertex_order(prim, positions.size(), label);
        if (mode == TINYGLTF_MODE_LINE && order.size() % 2 != 0)
            scene_fail(file_, label, ": LINES needs an even number of vertices (got ", order.size(), ")");

        // Radius: per vertex, else material extras.radius, else filled in at the end.
        const glm::dmat3 basis(world);
        const double det = glm::determinant(basis);
        if (!(std::abs(det) > 0.0)) scene_fail(file_, "node ", node, ": transform has zero scale");
        const double scale = std::cbrt(std::abs(det));
        if (!is_uniform_scale(basis, scale)) ++nonuniform_hair_nodes_;
        const uint32_t material = material_index(prim.material);
        std::optional<float> stated_radius;
        if (radii.empty() && prim.material >= 0)
            stated_radius = gltf_material_radius(model_.materials[prim.material], prim.material, file_);

        // Strands as runs of vertex-sequence positions.
        std::vector<std::pair<size_t, size_t>> strands;  // [begin, end) into `chain`
        std::vector<uint32_t> chain;
        if (mode == TINYGLTF_MODE_LINE_STRIP) {
            chain = order;
            strands.push_back({0, chain.size()});
        } else {
            for (size_t i = 0; i + 1 < order.size(); i += 2) {
                const uint32_t a = order[i], b = order[i + 1];
                const bool continues = !strands.empty() &&
                                       (chain.back() == a || positions[chain.back()] == positions[a]);
                if (continues) {
                    chain.push_back(b);
                    strands.back().second = chain.size();
                } else {
                    strands.push_back({chain.size(), chain.size() + 2});
                    chain.push_back(a);
                    chain.push_back(b);
                }
            }
        }

        Strands& s = scene_.strands;
        check_scene_size(file_, str_cat(label, ": with this primitive the scene has"),
                         s.strand_count() + strands.size(), s.point_count() + chain.size(), opt_);
        if (s.first_point.empty()) s.first_point.push_back(0);
        labels_.push_back({s.strand_count(), label});
        const size_t first_new_point = s.points.size();
        for (const auto& [begin, end] : strands) {
            for (size_t k = begin; k < end; ++k) {
                const uint32_t v = chain[k];
                const Vec3f& p = positions[v];
                s.points.push_back(to_vec3f(glm::dvec3(world * glm::dvec4(p[0], p[1], p[2], 1.0))));
                if (!radii.empty())
                    s.radius.push_back(static_cast<float>(radii[v] * scale));
                else if (stated_radius)
                    s.radius.push_back(static_cast<float>(*stated_radius * scale));
                else
                    s.radius.push_back(0.0f);  // filled by fill_missing_radii()
            }
            s.first_point.push_back(static_cast<uint32_t>(s.points.size()));
            s.material.push_back(material);
        }
        if (radii.empty() && !stated_radius)
            missing_radius_.push_back({first_new_point, s.points.size()});
    }

    static bool is_uniform_scale(const glm::dmat3& m, double scale) {
        for (int i = 0; i < 3; ++i) {
            if (std::abs(glm::length(m[i]) - scale) > 1e-4 * scale) return false;
            for (int j = i + 1; j < 3; ++j)
                if (std::abs(glm::dot(m[i], m[j])) > 1e-4 * scale * scale) return false;
        }
        return true;
    }

    void add_builtin() {
        const tinygltf::Value* spec = scene_extras_value("hairtrace_builtin");
        if (!spec) return;
        if (!spec->IsString()) scene_fail(file_, "extras.hairtrace_builtin must be a string");
        Scene builtin;
        try {
            builtin = make_builtin(spec->Get<std::string>(), opt_);
        } catch (const SceneError& e) {
            scene_fail(file_, "extras.hairtrace_builtin: ", e.what());
        }
        const tinygltf::Value* m = scene_extras_value("hairtrace_material");
        append_hair(builtin, "builtin:" + spec->Get<std::string>(), "the built-in hair",
                    m ? find_material(*m, "extras.hairtrace_material") : -1, nullptr);
        // The file's own camera and lights win; the built-in's frame its hair otherwise.
        if (!scene_.has_camera && builtin.has_camera) {
            scene_.camera = builtin.camera;
            scene_.has_camera = true;
        }
        if (scene_.lights.empty()) scene_.lights = builtin.lights;
    }

    // `what` names the key in messages, e.g. "extras.hairtrace_material".
    int find_material(const tinygltf::Value& v, const std::string& what) const {
        if (v.IsInt()) {
            const int index = v.Get<int>();
            if (index < 0 || static_cast<size_t>(index) >= model_.materials.size())
                scene_fail(file_, what, ": material ", index, " does not exist");
            return index;
        }
        if (v.IsString()) {
            for (size_t i = 0; i < model_.materials.size(); ++i)
                if (model_.materials[i].name == v.Get<std::string>()) return static_cast<int>(i);
            scene_fail(file_, what, ": no material named \"", v.Get<std::string>(), "\"");
        }
        scene_fail(file_, what, " must be a material index or name");
    }

    // Adds the strands of `other` (a built-in or a loaded hair file) under `label`: with the glTF
    // material `gltf_material` for all of them, else (-1) with `other`'s own materials; points moved by
    // `*world` when given, radii scaled by its uniform scale (as add_hair_primitive does).
    void append_hair(const Scene& other, const std::string& label, const std::string& what,
                     int gltf_material, const glm::dmat4* world) {
        std::vector<uint32_t> material_of(other.materials.size());
        for (size_t i = 0; i < material_of.size(); ++i) {
            if (gltf_material >= 0) {
                material_of[i] = material_index(gltf_material);
            } else {
                material_of[i] = static_cast<uint32_t>(scene_.materials.size());
                scene_.materials.push_back(other.materials[i]);
            }
        }
        Strands& s = scene_.strands;
        const Strands& b = other.strands;
        check_scene_size(file_, str_cat("with ", what, " the scene has"), s.strand_count() + b.strand_count(),
                         s.point_count() + b.point_count(), opt_);
        if (s.first_point.empty()) s.first_point.push_back(0);
        labels_.push_back({s.strand_count(), label});
        const uint32_t offset = static_cast<uint32_t>(s.points.size());
        if (world) {
            const double scale = std::cbrt(std::abs(glm::determinant(glm::dmat3(*world))));
            if (!is_uniform_scale(glm::dmat3(*world), scale)) ++nonuniform_hair_nodes_;
            for (const Vec3f& p : b.points)
                s.points.push_back(to_vec3f(glm::dvec3(*world * glm::dvec4(p[0], p[1], p[2], 1.0))));
            for (float r : b.radius) s.radius.push_back(static_cast<float>(r * scale));
        } else {
            s.points.insert(s.points.end(), b.points.begin(), b.points.end());
            s.radius.insert(s.radius.end(), b.radius.begin(), b.radius.end());
        }
        for (size_t i = 1; i < b.first_point.size(); ++i) s.first_point.push_back(offset + b.first_point[i]);
        for (uint32_t m : b.material) s.material.push_back(material_of.at(m));
    }

    // A node's extras.hairtrace_hair: {"uri": FILE, "material": INDEX|NAME (optional)}.
    void add_hair_file(const tinygltf::Value& v, const glm::dmat4& world, int node) {
        const std::string what = str_cat("node ", node, " extras.hairtrace_hair");
        if (!v.IsObject())
            scene_fail(file_, what, " must be an object like {\"uri\": \"straight.hair\", \"material\": 0}");
        for (const std::string& key : v.Keys())
            if (key != "uri" && key != "material")
                scene_fail(file_, what, ": unknown key \"", key, "\" (known: uri, material)");
        if (!v.Has("uri") || !v.Get("uri").IsString() || v.Get("uri").Get<std::string>().empty())
            scene_fail(file_, what, ": \"uri\" must name a hair file (a non-empty string)");
        const std::string uri = v.Get("uri").Get<std::string>();
        std::string ext = uri.substr(std::min(uri.size(), uri.find_last_of('.')));
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        // A glTF here could reference itself; and "builtin:" is the scene extras' job.
        if (ext == ".gltf" || ext == ".glb" || uri.rfind("builtin:", 0) == 0)
            scene_fail(file_, what, ": \"", uri, "\" is not a hair file (.hair, .data, .ply, .obj, .pbrt, .pbrt.gz)");
        const int material = v.Has("material") ? find_material(v.Get("material"), what + ".material") : -1;
        const double det = glm::determinant(glm::dmat3(world));
        if (!(std::abs(det) > 0.0)) scene_fail(file_, "node ", node, ": transform has zero scale");
        const std::string path = uri[0] == '/' ? uri : directory_of(file_) + "/" + uri;
        Scene hair;
        try {
            hair = load_scene(path, opt_);
        } catch (const SceneError& e) {
            scene_fail(file_, what, ": ", e.what());
        }
        for (const std::string& w : hair.warnings) scene_.warnings.push_back(w);
        append_hair(hair, uri, what, material, &world);
    }

    void fill_missing_radii() {
        if (missing_radius_.empty()) return;
        float radius = opt_.default_radius;
        if (!(radius > 0.0f)) {
            radius = radius_from_extent(scene_.strands.points);
            scene_.warnings.push_back(str_cat(file_, ": ", missing_radius_.size(),
                                              " hair primitives have no _RADIUS and no material "
                                              "extras.radius: using ", radius,
                                              " (1/1000 of the hair's extent)"));
        }
        for (const auto& [begin, end] : missing_radius_)
            std::fill(scene_.strands.radius.begin() + begin, scene_.strands.radius.begin() + end, radius);
    }

    void finish_warnings() {
        std::vector<std::string>& w = scene_.warnings;
        if (degenerate_triangles_ > 0)
            w.push_back(str_cat(file_, ": dropped ", degenerate_triangles_,
                                " degenerate (zero-area) triangles"));
        if (bad_normal_primitives_ > 0)
            w.push_back(str_cat(file_, ": ", bad_normal_primitives_,
                                " triangle primitives have zero or non-finite normals: using "
                                "geometric normals"));
        if (textured_without_uvs_ > 0)
            w.push_back(str_cat(file_, ": ", textured_without_uvs_,
                                " triangle primitives have a textured material but no TEXCOORD_0: "
                                "they use baseColorFactor alone"));
        if (textures_.ignored_transforms() > 0)
            w.push_back(str_cat(file_, ": ", textures_.ignored_transforms(),
                                " base colour textures have KHR_texture_transform, which is "
                                "ignored (coordinates are used as stored)"));
        if (other_primitives_ > 0)
            w.push_back(str_cat(file_, ": ignored ", other_primitives_,
                                " POINTS / LINE_LOOP primitives"));
        if (ignored_cameras_ > 0)
            w.push_back(str_cat(file_, ": ignored ", ignored_cameras_,
                                opt_.camera_index >= 0 ? " cameras (--camera chose one)"
                                                       : " cameras (only the first perspective camera is used)"));
        if (nonuniform_hair_nodes_ > 0)
            w.push_back(str_cat(file_, ": ", nonuniform_hair_nodes_,
                                " hair primitives have a non-uniform node scale: radii scaled "
                                "by its geometric mean"));
        if (!unknown_keys_.empty()) {
            std::string keys;
            for (const std::string& k : unknown_keys_) keys += (keys.empty() ? "" : ", ") + k;
            w.push_back(str_cat(file_, ": ignored ", unknown_keys_.size(),
                                " unknown material extras keys: ", keys));
        }
    }

    const std::string& file_;
    const tinygltf::Model& model_;
    const LoadOptions& opt_;
    Scene scene_;
    std::vector<bool> visited_;
    std::vector<StrandLabel> labels_;
    std::vector<std::pair<size_t, size_t>> missing_radius_;  // point ranges
    std::map<int, uint32_t> material_map_;
    int default_material_ = -1;
    std::set<std::string> unknown_keys_;
    size_t triangle_primitives_ = 0, other_primitives_ = 0, ignored_cameras_ = 0;
    size_t nonuniform_hair_nodes_ = 0;
    std::map<int, uint32_t> surface_material_map_;
    int default_surface_material_ = -1;
    size_t degenerate_triangles_ = 0, bad_normal_primitives_ = 0, textured_without_uvs_ = 0;
    GltfTextureReader textures_;  // after scene_: it fills scene_.textures
};

}  // namespace

Scene load_gltf(const std::string& path, const LoadOptions& opt) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keep_gltf_image_bytes, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool binary = ext == ".glb";
    require_regular_file(path);
    try {
        if (binary) {
            load_glb(loader, model, path, err, warn);
        } else {
            std::ifstream in(path, std::ios::binary);
            std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            check_json_depth(text.data(), text.size(), path);
            if (!loader.LoadASCIIFromString(&model, &err, &warn, text.data(), static_cast<unsigned int>(text.size()),
                                            directory_of(path)))
                scene_fail(path, "glTF parse error: ", err.empty() ? std::string("unknown") : err);
        }
        if (opt.camera_index >= 0 && static_cast<size_t>(opt.camera_index) >= model.cameras.size())
            scene_fail(path, "camera ", opt.camera_index, " was asked for but the file has ",
                       model.cameras.size(), " cameras");
        Scene scene = GltfSceneBuilder(path, model, opt).build();
        if (!warn.empty()) scene.warnings.push_back(one_line(path + ": glTF parser: " + warn));
        return scene;
    } catch (const SceneError&) {
        throw;
    } catch (const std::exception& e) {
        // tinygltf and the JSON parser may throw (bad_alloc on absurd sizes, json errors).
        scene_fail(path, "glTF error: ", e.what());
    }
}

}  // namespace ht
