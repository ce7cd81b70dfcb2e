// hairtrace info / hairtrace devices.
#include "bvh/bvh.h"
#include "cl/device.h"
#include "cli/commands.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

namespace ht {

namespace {
const char* wrap_name(TextureWrap w) {
    switch (w) {
    case TextureWrap::ClampToEdge: return "clamp";
    case TextureWrap::MirroredRepeat: return "mirror";
    case TextureWrap::Repeat: break;
    }
    return "repeat";
}
}  // namespace

int cmd_info(const std::vector<std::string>& args) {
    ArgParser p("info", "Strands, points, segments, bounds, materials, textures, lights and BVH statistics of a scene.");
    add_scene_argument(p);
    add_scene_options(p);
    p.flag("--json", "machine-readable output");
    p.parse(args);
    if (p.wants_help()) { std::cout << p.help(); return kExitOk; }
    Scene scene = load_scene(p.get("SCENE"), scene_load_options(p));
    SceneGeometry g = build_geometry(scene);
    Bounds b = scene_bounds(scene);
    nlohmann::json j;
    j["scene"] = scene.source;
    j["strands"] = scene.strands.strand_count();
    j["points"] = scene.strands.point_count();
    j["segments"] = scene.strands.segment_count();
    j["bounds"] = {{"min", {b.lo[0], b.lo[1], b.lo[2]}}, {"max", {b.hi[0], b.hi[1], b.hi[2]}}};
    j["meshes"] = scene.meshes.size();
    j["triangles"] = g.triangle_count;
    j["surface_materials"] = nlohmann::json::array();
    for (auto& m : scene.surface_materials) {
        nlohmann::json sm = {{"name", m.name}, {"albedo", {m.albedo[0], m.albedo[1], m.albedo[2]}}};
        if (m.texture >= 0) sm["texture"] = m.texture;
        j["surface_materials"].push_back(sm);
    }
    j["textures"] = nlohmann::json::array();
    for (auto& t : scene.textures)
        j["textures"].push_back({{"name", t.name}, {"width", t.width}, {"height", t.height},
                                 {"wrap", {wrap_name(t.wrap_s), wrap_name(t.wrap_t)}}});
    j["materials"] = nlohmann::json::array();
    for (auto& m : scene.materials) j["materials"].push_back({{"name", m.name}, {"model", m.model}});
    j["lights"] = scene.lights.size();
    j["camera"] = scene.has_camera;
    j["bvh"] = {{"nodes", g.stats.nodes}, {"leaves", g.stats.leaves}, {"max_depth", g.stats.max_depth},
                {"sah_cost", g.stats.sah_cost}, {"bytes_per_segment", g.stats.bytes_per_segment},
                {"build_ms", g.stats.build_ms}};
    j["warnings"] = scene.warnings;
    if (p.has("--json")) {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::printf("scene      %s\n", scene.source.c_str());
    std::printf("strands    %zu\npoints     %zu\nsegments   %zu\n", scene.strands.strand_count(),
                scene.strands.point_count(), scene.strands.segment_count());
    std::printf("bounds     (%g, %g, %g) .. (%g, %g, %g)\n", b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]);
    for (auto& m : scene.materials) std::printf("material   %s (%s)\n", m.name.c_str(), m.model.c_str());
    if (!scene.meshes.empty())
        std::printf("meshes     %zu (%zu triangles)\n", scene.meshes.size(), size_t(g.triangle_count));
    for (auto& m : scene.surface_materials) {
        std::printf("surface    %s (diffuse %g, %g, %g", m.name.c_str(), m.albedo[0], m.albedo[1], m.albedo[2]);
        if (m.texture >= 0) std::printf(" x texture %d", m.texture);
        std::printf(")\n");
    }
    for (size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& t = scene.textures[i];
        std::printf("texture    %zu: %s, %u x %u, wrap %s / %s, %.1f KiB\n", i, t.name.c_str(), t.width, t.height,
                    wrap_name(t.wrap_s), wrap_name(t.wrap_t), t.texels.size() * 4 / 1024.0);
    }
    std::printf("lights     %zu\ncamera     %s\n", scene.lights.size(), scene.has_camera ? "from scene" : "automatic");
    std::printf("bvh        %zu nodes, %zu leaves, depth %d, SAH cost %.2f, %.1f bytes/segment, built in %.1f ms\n",
                size_t(g.stats.nodes), size_t(g.stats.leaves), int(g.stats.max_depth), double(g.stats.sah_cost),
                double(g.stats.bytes_per_segment), double(g.stats.build_ms));
    for (auto& w : scene.warnings) std::printf("warning    %s\n", w.c_str());
    return kExitOk;
}

int cmd_devices(const std::vector<std::string>& args) {
    ArgParser p("devices", "The OpenCL platforms and devices, with the indices render --device takes.");
    p.flag("--json", "machine-readable output");
    p.parse(args);
    if (p.wants_help()) { std::cout << p.help(); return kExitOk; }
    auto devs = list_devices();
    if (p.has("--json")) {
        nlohmann::json j = nlohmann::json::array();
        for (auto& d : devs)
            j.push_back({{"index", d.index}, {"platform", d.platform}, {"name", d.name}, {"type", d.type},
                         {"version", d.version}, {"driver", d.driver}, {"opencl_c", d.c_version},
                         {"compute_units", d.compute_units}, {"global_mem", d.global_mem}, {"max_alloc", d.max_alloc}});
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    for (auto& d : devs)
        std::printf("%d: %s [%s] on %s; %s; %s; driver %s; %u compute units; %.1f GiB (max alloc %.1f GiB)\n", d.index,
                    d.name.c_str(), d.type.c_str(), d.platform.c_str(), d.version.c_str(), d.c_version.c_str(),
                    d.driver.c_str(), d.compute_units, d.global_mem / 1073741824.0, d.max_alloc / 1073741824.0);
    return kExitOk;
}

}  // namespace ht
