// hairtrace command line: render, info, devices, bench, fiber.
//
// Exit codes: 0 success; 2 bad input or usage (the message names the file/option and the
// problem); 3 device or runtime failure (OpenCL, memory, writing outputs).
#include "bench/bench.h"
#include "bvh/bvh.h"
#include "cl/device.h"
#include "cl/kernel_source.h"
#include "cli/args.h"
#include "fiber/fiber_cli.h"
#include "io/image_io.h"
#include "render/features.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

using namespace ht;

namespace {

constexpr int kExitOk = 0, kExitUsage = 2, kExitRuntime = 3;

const char* kTopHelp =
    "hairtrace " HT_VERSION " - photo-realistic hair rendering (Zinke et al. 2004) on OpenCL\n"
    "\n"
    "usage: hairtrace <command> [arguments] [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE -o OUT ...   render a scene to images (.exr linear, .png sRGB; -o repeatable)\n"
    "  info SCENE [--json]       strands, points, segments, bounds, materials, BVH statistics\n"
    "  devices [--json]          list OpenCL platforms and devices (indices for --device)\n"
    "  bench [...]               BVH build and ray throughput benchmark (validated hits)\n"
    "  fiber eval|sample|furnace|afs ...   query the fibre scattering models\n"
    "  help [COMMAND]            this text, or a command's options (same as COMMAND --help)\n"
    "  version                   print the version\n"
    "\n"
    "SCENE is a .gltf/.glb, a Cem Yuksel .hair, a USC-HairSalon .data file, or builtin:strand /\n"
    "builtin:ball (the paper's Fig. 5 strand and Fig. 6 ball).\n"
    "\n"
    "exit codes: 0 ok, 2 bad input or usage, 3 device or runtime failure.\n"
    "environment: HAIRTRACE_KERNEL_DIR (load kernels from a folder instead of the embedded\n"
    "copies), HAIRTRACE_CACHE_DIR (compiled-kernel cache, 'off' to disable).\n";

std::vector<std::string> tail_args(int argc, char** argv, int from) {
    std::vector<std::string> v;
    for (int i = from; i < argc; ++i) v.push_back(argv[i]);
    return v;
}

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

Vec3f parse_rgb(const std::string& opt, const std::string& s) {
    Vec3f v{};
    std::stringstream ss(s);
    std::string item;
    int n = 0;
    while (std::getline(ss, item, ',') && n < 3) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (item.empty() || *end || !std::isfinite(d)) throw UsageError(opt + " expects r,g,b numbers, got '" + s + "'");
        v[n++] = float(d);
    }
    if (n == 1) v[1] = v[2] = v[0];
    else if (n != 3) throw UsageError(opt + " expects r,g,b numbers, got '" + s + "'");
    return v;
}

// ---------------------------------------------------------------------------- progress
class Progress {
public:
    explicit Progress(bool quiet) : quiet_(quiet), t0_(std::chrono::steady_clock::now()) {}
    void operator()(int done, int total) {
        if (quiet_) return;
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        double eta = done > 0 ? s / done * (total - done) : 0;
        std::fprintf(stderr, "\rrendering: %d/%d spp  %.1f s elapsed  ETA %.1f s   ", done, total, s, eta);
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    bool quiet_;
    std::chrono::steady_clock::time_point t0_;
};

// ---------------------------------------------------------------------------- commands
int cmd_render(const std::vector<std::string>& args) {
    ArgParser p("render");
    p.positional("SCENE", "scene file or builtin:NAME");
    p.option("-o", "OUT", "output image; the extension picks the format (.exr linear float, .png sRGB 8-bit)", "", true)
        .option("--width", "W", "image width in pixels", "512")
        .option("--height", "H", "image height in pixels", "512")
        .option("--spp", "N", "samples per pixel", "16")
        .option("--seed", "S", "random seed; the image depends only on seed, spp and scene", "1")
        .option("--max-depth", "D", "path length in fibre bounces (1 = direct light only)", "1")
        .option("--model", "M", "override every material's fibre model: kajiya|marschner|zinke|chiang")
        .option("--background", "R,G,B", "constant radiance of rays that leave the scene", "0,0,0")
        .option("--exposure", "E", "multiplier applied before tone mapping 8-bit outputs", "1")
        .option("--device", "I", "OpenCL device index from `hairtrace devices` (default: first CPU/GPU)")
        .option("--kernel-dir", "DIR", "load kernel sources from DIR instead of the embedded copies");
    add_scene_options(p);
    p.flag("--verbose", "print the kernel features chosen for the scene and the build options")
        .flag("--quiet", "no progress output on stderr")
        .flag("--help", "this help");
    p.parse(args);
    if (p.has("--help")) { std::cout << p.help(); return kExitOk; }
    auto outputs = p.all("-o");
    if (outputs.empty()) throw UsageError("render: no output given (-o OUT.exr and/or -o OUT.png)");
    for (auto& o : outputs)
        if (o.find('.') == std::string::npos) throw UsageError("render: output '" + o + "' has no extension");

    RenderSettings rs;
    rs.width = p.get_int("--width", 1, 16384);
    rs.height = p.get_int("--height", 1, 16384);
    rs.spp = p.get_int("--spp", 1, 1 << 24);
    rs.seed = uint32_t(std::stoul(p.get("--seed")));
    rs.max_depth = p.get_int("--max-depth", 1, 1000);
    rs.background = parse_rgb("--background", p.get("--background"));
    float exposure = float(p.get_double("--exposure", 0, 1e9));
    bool quiet = p.has("--quiet");
    if (p.has("--kernel-dir")) set_kernel_dir(p.get("--kernel-dir"));

    Scene scene = load_scene(p.get("SCENE"), scene_load_options(p));
    if (p.has("--model")) {
        std::string m = p.get("--model");
        if (m != "kajiya" && m != "marschner" && m != "zinke" && m != "chiang")
            throw UsageError("--model must be kajiya, marschner, zinke or chiang, got '" + m + "'");
        for (auto& mat : scene.materials) mat.model = m;
    }
    ensure_camera_and_light(scene);
    if (!quiet)
        for (auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

    ClContext cl(p.has("--device") ? p.get_int("--device", 0, 1000) : -1);
    if (!quiet)
        std::fprintf(stderr, "device: %s (%s)\nscene: %s, %zu strands, %zu segments\n", cl.info().name.c_str(),
                     cl.info().platform.c_str(), scene.source.c_str(), scene.strands.strand_count(),
                     scene.strands.segment_count());
    if (p.has("--verbose")) {
        for (auto& line : describe_features(scene_features(scene))) std::fprintf(stderr, "feature %s\n", line.c_str());
        std::fprintf(stderr, "kernel options: %s\n", kernel_build_options(scene).c_str());
    }
    Renderer renderer(cl, scene, rs);
    Film film;
    Progress progress(quiet);
    RenderStats st = renderer.render(film, std::ref(progress));
    if (!quiet)
        std::fprintf(stderr, "done: %.2f s, %llu camera + %llu extension + %llu shadow rays, kernel build %.0f ms%s\n",
                     st.seconds, (unsigned long long)st.camera_rays, (unsigned long long)st.extension_rays,
                     (unsigned long long)st.shadow_rays, st.build_ms, st.build_cached ? " (cached)" : "");
    if (st.nonfinite_caught && !quiet)
        std::fprintf(stderr, "warning: %llu non-finite shading values were caught and dropped\n",
                     (unsigned long long)st.nonfinite_caught);

    ImageMetadata meta;
    meta.ints["hairtrace:spp"] = st.samples;
    meta.ints["hairtrace:seed"] = int(rs.seed);
    meta.ints["hairtrace:max_depth"] = rs.max_depth;
    meta.floats["hairtrace:render_seconds"] = float(st.seconds);
    meta.text["hairtrace:device"] = cl.info().name + " / " + cl.info().platform + " " + cl.info().driver;
    meta.text["hairtrace:version"] = HT_VERSION;
    meta.text["hairtrace:scene"] = scene.source;
    for (auto& o : outputs) {
        write_image(o, film, meta, exposure);
        if (!quiet) std::fprintf(stderr, "wrote %s\n", o.c_str());
    }
    return kExitOk;
}

int cmd_info(const std::vector<std::string>& args) {
    ArgParser p("info");
    p.positional("SCENE", "scene file or builtin:NAME");
    add_scene_options(p);
    p.flag("--json", "machine-readable output").flag("--help", "this help");
    p.parse(args);
    if (p.has("--help")) { std::cout << p.help(); return kExitOk; }
    Scene scene = load_scene(p.get("SCENE"), scene_load_options(p));
    SceneGeometry g = build_geometry(scene.strands);
    Bounds b = scene_bounds(scene);
    nlohmann::json j;
    j["scene"] = scene.source;
    j["strands"] = scene.strands.strand_count();
    j["points"] = scene.strands.point_count();
    j["segments"] = scene.strands.segment_count();
    j["bounds"] = {{"min", {b.lo[0], b.lo[1], b.lo[2]}}, {"max", {b.hi[0], b.hi[1], b.hi[2]}}};
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
    std::printf("lights     %zu\ncamera     %s\n", scene.lights.size(), scene.has_camera ? "from scene" : "automatic");
    std::printf("bvh        %zu nodes, %zu leaves, depth %d, SAH cost %.2f, %.1f bytes/segment, built in %.1f ms\n",
                size_t(g.stats.nodes), size_t(g.stats.leaves), int(g.stats.max_depth), double(g.stats.sah_cost),
                double(g.stats.bytes_per_segment), double(g.stats.build_ms));
    for (auto& w : scene.warnings) std::printf("warning    %s\n", w.c_str());
    return kExitOk;
}

int cmd_devices(const std::vector<std::string>& args) {
    ArgParser p("devices");
    p.flag("--json", "machine-readable output").flag("--help", "this help");
    p.parse(args);
    if (p.has("--help")) { std::cout << p.help(); return kExitOk; }
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

int dispatch(int argc, char** argv) {
    if (argc < 2) {
        std::fputs(kTopHelp, stderr);
        return kExitUsage;
    }
    std::string cmd = argv[1];
    auto rest = tail_args(argc, argv, 2);
    if (cmd == "render") return cmd_render(rest);
    if (cmd == "info") return cmd_info(rest);
    if (cmd == "devices") return cmd_devices(rest);
    if (cmd == "bench") return bench_main(rest);
    if (cmd == "fiber") return fiber_main(rest);
    if (cmd == "version" || cmd == "--version") {
        std::printf("hairtrace %s\n", HT_VERSION);
        return kExitOk;
    }
    if (cmd == "help" || cmd == "--help" || cmd == "-h") {
        if (!rest.empty() && rest[0] != "help") {
            std::vector<std::string> h{"--help"};
            if (rest[0] == "render") return cmd_render(h);
            if (rest[0] == "info") return cmd_info(h);
            if (rest[0] == "devices") return cmd_devices(h);
            if (rest[0] == "bench") return bench_main(h);
            if (rest[0] == "fiber") return fiber_main(h);
        }
        std::fputs(kTopHelp, stdout);
        return kExitOk;
    }
    throw UsageError("unknown command '" + cmd + "' (see hairtrace --help)");
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return dispatch(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return kExitUsage;
    } catch (const SceneError& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return kExitUsage;
    } catch (const DeviceError& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return kExitRuntime;
    } catch (const ImageError& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return kExitRuntime;
    } catch (const cl::Error& e) {
        std::fprintf(stderr, "hairtrace: OpenCL error in %s: %s\n", e.what(), cl_error_name(e.err()).c_str());
        return kExitRuntime;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "hairtrace: out of host memory\n");
        return kExitRuntime;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return kExitRuntime;
    }
}
