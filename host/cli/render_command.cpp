// hairtrace render: load, build, render progressively with checkpoints, write images.
#include "cl/device.h"
#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "dist/accumulation.h"
#include "dist/chunk_scheduler.h"
#include "dist/distributed.h"
#include "dist/partial_image.h"
#include "io/image_io.h"
#include "render/checkpoint.h"
#include "render/depth_choice.h"
#include "render/error_metrics.h"
#include "render/features.h"
#include "render/memory_plan.h"
#include "render/renderer.h"
#include "kernels/types.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace ht {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

using Clock = std::chrono::steady_clock;

bool fs_ext_is_exr(const std::string& path) {
    auto dot = path.rfind('.');
    if (dot == std::string::npos) return false;
    std::string e = path.substr(dot);
    for (auto& ch : e) ch = char(std::tolower((unsigned char)ch));
    return e == ".exr";
}
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void print_progress(int done, int total, double elapsed) {
    double eta = done > 0 ? elapsed / done * (total - done) : 0;
    std::fprintf(stderr, "\rrendering: %d/%d spp  %.1f s elapsed  ETA %.1f s   ", done, total, elapsed, eta);
    std::fflush(stderr);
}

// Everything besides the sample count that shapes the image: a checkpoint from another
// render must not be continued by this one.
uint64_t render_key(const Scene& scene, const RenderSettings& rs, const std::string& kernel_options, int chunk) {
    std::string k = "chunk " + std::to_string(chunk) + "|" + scene.source + "|" + std::to_string(scene.strands.point_count()) + "|" +
                    std::to_string(scene.strands.strand_count()) + "|" + kernel_options + "|" +
                    std::to_string(rs.width) + "x" + std::to_string(rs.height) + "|" + std::to_string(rs.seed) + "|" +
                    std::to_string(rs.max_depth) + "|" + std::to_string(int(rs.indirect)) + "|" + std::to_string(rs.fiber_field) + "|" + scene.environment.map_path + "|" +
                    std::to_string(scene.environment.color[0]) + "," + std::to_string(scene.environment.color[1]) +
                    "," + std::to_string(scene.environment.color[2]) + "x" + std::to_string(scene.environment.intensity);
    for (auto& m : scene.materials) k += "|" + m.model;
    return hash_text(k);
}

// --clamp-indirect: "off" (0) or a positive cap.
float parse_clamp_indirect(const std::string& v) {
    if (v == "off") return 0.0f;
    char* end = nullptr;
    const double c = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(c) || !(c > 0) || c > 3.0e38)
        throw UsageError("--clamp-indirect must be off or a positive number, got '" + v + "'");
    return float(c);
}

// --device: absent (the default device), an index, "all", or a comma list "0,2".
std::vector<int> parse_devices(const ArgParser& p) {
    if (!p.has("--device")) return {-1};
    const std::string v = p.get("--device");
    std::vector<int> out;
    if (v == "all") {
        for (size_t i = 0; i < list_devices().size(); ++i) out.push_back(int(i));
        if (out.empty()) throw DeviceError("--device all: no OpenCL device found");
        return out;
    }
    std::stringstream ss(v);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos || item.size() > 4)
            throw UsageError("--device must be an index, a list like 0,2, or all; got '" + v + "'");
        int d = std::stoi(item);
        for (int e : out)
            if (e == d) throw UsageError("--device " + v + ": device " + item + " is listed twice");
        out.push_back(d);
    }
    if (out.empty()) throw UsageError("--device must be an index, a list like 0,2, or all; got '" + v + "'");
    return out;
}

int render_main(const std::vector<std::string>& args, DistContext& dist);

}  // namespace

// MPI wraps the whole command: every rank must reach MPI_Finalize, and an error on one rank must
// end all of them (the others would wait forever in the reduction).
int cmd_render(const std::vector<std::string>& args) {
    DistContext dist = dist_init();
    int code = 0;
    try {
        code = render_main(args, dist);
    } catch (const std::exception& e) {
        if (dist.ranks <= 1) {
            dist_finalize(dist);
            throw;
        }
        const bool bad_input = dynamic_cast<const UsageError*>(&e) || dynamic_cast<const SceneError*>(&e);
        std::fprintf(stderr, "hairtrace (rank %d of %d): %s\n", dist.rank, dist.ranks, e.what());
        dist_abort(dist, bad_input ? kExitUsage : kExitRuntime);
    }
    dist_finalize(dist);
    return code;
}

namespace {
int render_main(const std::vector<std::string>& args, DistContext& dist) {
    ArgParser p("render");
    p.positional("SCENE", "scene file or builtin:NAME");
    p.option("-o", "OUT", "output image; the extension picks the format (.exr linear float, .png sRGB 8-bit)", "", true)
        .option("--width", "W", "image width in pixels", "512")
        .option("--height", "H", "image height in pixels", "512")
        .option("--spp", "N", "samples per pixel (hair-to-hair light through narrow fibre lobes sparkles below ~64)", "64")
        .option("--time-limit", "SECONDS", "stop after the sample that crosses this wall time (0 = none)", "0")
        .option("--seed", "S", "random seed; the image depends only on seed, spp and scene", "1")
        .option("--max-depth", "D|auto", "path length in fibre bounces (1 = direct light only); auto: from the materials' averaged attenuation (AFS_TT^avg^D < 0.2, Zinke 2004 §5)", "auto")
        .option("--model", "M", "override every material's fibre model: kajiya|marschner|zinke|chiang")
        .option("--sigma-a", "R,G,B", "override every hair material's absorption: sigma_a per unit radius (replaces melanin or colour)")
        .option("--features", "scene|all|all-lobes", "what the kernels are compiled with: what the scene needs (lights, models, meshes, fibre lobes above 1e-3 of R's energy for some material; --verbose lists them), everything, or the scene's choice with every lobe kept (A/B comparisons)", "scene")
        .option("--indirect", "exact|afs|none", "hair-to-hair light: exact = path traced to --max-depth; afs = traced to --max-depth (auto: 1), then the paper's averaged attenuation: the last bounce's shadow rays cross hair with AFS_TT^avg per fibre; none = direct light with opaque hair (depth 1)", "exact")
        .option("--clamp-indirect", "C|off", "cap the contribution of every light path that scattered at two or more surfaces at C (radiance, largest rgb channel, hue kept): fewer sparkles at low sample counts at the cost of a bias that must be measured per scene (builtin:strand, irradiance 1: C = 3 removes 2.8 % of the light, C = 1 14.5 %)", "off")
        .option("--regularize", "DEG|off", "path regularisation: where a path meets hair after a first scattering, widen the marschner/zinke lobes to at least DEG degrees (longitudinal widths and zinke's azimuthal spread); bright two-lobe sparkles become a blur of indirect highlights (biased; measured in docs/PERFORMANCE.md)", "off")
        .option("--fiber-field", "near|far|auto|material", "for marschner/zinke materials: near field (zinke) everywhere, far field (marschner) everywhere, or auto: near where a fibre covers at least half a camera pixel's footprint and for hair-to-hair light, far elsewhere; with --model and no --fiber-field: material", "auto")
        .option("--background", "R,G,B", "uniform environment radiance (importance sampled like any light); replaces the scene's")
        .option("--environment", "FILE", "lat-long HDR environment map (.exr/.hdr, +y up); replaces the scene's")
        .option("--environment-intensity", "K", "multiplier for the environment", "1")
        .option("--exposure", "E|auto", "multiplier applied before tone mapping 8-bit outputs; auto maps the 95th percentile of lit pixels to 0.8 (linear outputs are never scaled)", "auto")
        .option("--checkpoint", "FILE", "write the progressive state to FILE (atomically) every --checkpoint-every seconds, at the end and on SIGINT/SIGTERM")
        .option("--checkpoint-every", "SECONDS", "checkpoint interval", "60")
        .option("--resume", "FILE", "continue a render from a checkpoint (same scene, options and seed)")
        .option("--reference", "REF", "linear image to compare with: prints RMSE, relMSE, max error, NaN count")
        .option("--max-memory", "SIZE", "upper bound for host memory while loading and for device memory while rendering, e.g. 512M or 8G; inputs that need more are refused before allocating, with the size named")
        .option("--device", "I|I,J,..|all", "OpenCL device index from `hairtrace devices` (default: first CPU/GPU); several devices split the chunks between them (one host thread each, work stealing), with the same image")
        .option("--chunk", "K", "samples per chunk: the image is the sum of K-sample chunk films added in chunk order, which every split (devices, MPI ranks, --sample-range parts) reproduces exactly; K >= spp is the plain sequential sum", "16")
        .option("--sample-range", "A:B", "render-farm part: render samples [A, B) of --spp only (A, B multiples of --chunk or B = spp); the .exr output then holds the raw sums for `hairtrace merge`")
        .option("--kernel-dir", "DIR", "load kernel sources from DIR instead of the embedded copies");
    add_scene_options(p);
    p.flag("--verbose", "print the kernel features chosen for the scene and the build options")
        .flag("--profile", "time every stage kernel separately and print the split (slows the render a little)")
        .flag("--quiet", "no progress output on stderr")
        .flag("--help", "this help");
    p.parse(args);
    // From here on SIGINT/SIGTERM only set a flag: even one arriving during start-up ends in a
    // saved checkpoint and images rather than a lost process.
    g_stop_signal = 0;
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    if (p.has("--help")) {
        std::cout << p.help()
                  << "exit codes: 0 ok, 2 bad input or usage, 3 device or runtime failure,\n"
                     "            130/143 interrupted by SIGINT/SIGTERM after saving the checkpoint and images\n";
        return kExitOk;
    }
    auto outputs = p.all("-o");
    if (outputs.empty()) throw UsageError("render: no output given (-o OUT.exr and/or -o OUT.png)");
    for (auto& o : outputs)
        if (o.find('.') == std::string::npos) throw UsageError("render: output '" + o + "' has no extension");

    RenderSettings rs;
    rs.width = p.get_int("--width", 1, 16384);
    rs.height = p.get_int("--height", 1, 16384);
    rs.spp = p.get_int("--spp", 1, 1 << 24);
    rs.seed = uint32_t(p.get_int("--seed", 0, 2147483647));
    const ChunkGrid grid{rs.spp, p.get_int("--chunk", 1, 1 << 24)};
    const bool partial = p.has("--sample-range");
    const SampleRange range = partial ? parse_sample_range(p.get("--sample-range"), grid) : SampleRange{0, rs.spp};
    const SampleRange my_range = rank_range(range, grid, dist.rank, dist.ranks);
    if (partial && std::none_of(outputs.begin(), outputs.end(), fs_ext_is_exr))
        throw UsageError("--sample-range needs an .exr output: only it keeps the raw sums `hairtrace merge` combines");
    const bool root = dist.rank == 0;
    // An explicit --model is taken literally unless --fiber-field says otherwise.
    rs.fiber_field = parse_fiber_field("--fiber-field", p.has("--model") && !p.has("--fiber-field")
                                                           ? std::string("material") : p.get("--fiber-field"));
    rs.clamp_indirect = parse_clamp_indirect(p.get("--clamp-indirect"));
    if (p.get("--regularize") != "off") rs.regularize_deg = float(p.get_double("--regularize", 0.1, 90));
    const double time_limit = p.get_double("--time-limit", 0, 1e9);
    const double checkpoint_every = p.get_double("--checkpoint-every", 0.01, 1e9);
    const bool auto_expose = p.get("--exposure") == "auto";
    const float fixed_exposure = auto_expose ? 1.0f : float(p.get_double("--exposure", 0, 1e9));
    const bool quiet = p.has("--quiet") || !root;  // one progress report per job, from rank 0
    rs.profile_stages = p.has("--profile");
    // Each rank keeps its own checkpoint; they resume together (same --resume FILE, same -np).
    const std::string rank_suffix = dist.ranks > 1 ? ".rank" + std::to_string(dist.rank) : "";
    const std::string checkpoint_path = p.has("--checkpoint") ? p.get("--checkpoint") + rank_suffix : "";
    if (p.has("--kernel-dir")) set_kernel_dir(p.get("--kernel-dir"));

    std::vector<float> reference;
    if (p.has("--reference")) {
        int rw, rh;
        reference = read_rgb_image(p.get("--reference"), rw, rh);
        if (rw != rs.width || rh != rs.height)
            throw UsageError("--reference " + p.get("--reference") + " is " + std::to_string(rw) + "x" +
                             std::to_string(rh) + ", the render is " + std::to_string(rs.width) + "x" +
                             std::to_string(rs.height));
    }

    LoadOptions load_options = scene_load_options(p);
    if (p.has("--max-memory")) {
        try {
            rs.max_device_bytes = parse_bytes(p.get("--max-memory"));
        } catch (const std::exception& e) {
            throw UsageError(std::string("--max-memory: ") + e.what());
        }
        load_options.max_bytes = rs.max_device_bytes;
    }
    Scene scene = load_scene(p.get("SCENE"), load_options);
    if (p.has("--model")) apply_model_override(scene, p.get("--model"));
    apply_hair_color_options(p, scene);
    if (p.has("--sigma-a")) {
        const Vec3f sa = parse_rgb("--sigma-a", p.get("--sigma-a"));
        for (auto& mat : scene.materials) {
            mat.has_sigma_a = true;
            mat.has_melanin = mat.has_color = false;
            mat.sigma_a = sa;
        }
    }
    {
        const std::string f = p.get("--features");
        if (f == "scene") rs.features = FeatureMode::Scene;
        else if (f == "all") rs.features = FeatureMode::All;
        else if (f == "all-lobes") rs.features = FeatureMode::AllLobes;
        else throw UsageError("--features must be scene, all or all-lobes, got '" + f + "'");
    }
    if (p.has("--background")) scene.environment = Environment{"", parse_rgb("--background", p.get("--background")), 1.0f};
    if (p.has("--environment")) scene.environment.map_path = p.get("--environment");
    scene.environment.intensity *= float(p.get_double("--environment-intensity", 0, 1e12));
    ensure_camera_and_light(scene, scene_view_options(p));
    const std::string indirect = p.get("--indirect");
    if (indirect != "exact" && indirect != "afs" && indirect != "none")
        throw UsageError("--indirect must be exact, afs or none, got '" + indirect + "'");
    if (indirect == "afs") rs.indirect = RenderSettings::Indirect::Afs;
    if (indirect == "none" || (indirect == "afs" && p.get("--max-depth") == "auto")) {
        if (p.get("--max-depth") != "auto" && p.get_int("--max-depth", 1, 1000) != 1 && indirect == "none")
            throw UsageError("--indirect none renders direct light only; it contradicts --max-depth " + p.get("--max-depth"));
        rs.max_depth = 1;
    } else if (p.get("--max-depth") == "auto") {
        DepthChoice dc = choose_max_depth(scene);
        rs.max_depth = dc.depth;
        if (!quiet) std::fprintf(stderr, "%s\n", dc.why.c_str());
    } else {
        rs.max_depth = p.get_int("--max-depth", 1, 1000);
    }
    if (!quiet)
        for (auto& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!quiet && dist.mpi) {
        const std::string w = cpu_binding_warning(local_rank_count());
        if (!w.empty()) std::fprintf(stderr, "warning: %s\n", w.c_str());
    }

    std::vector<std::unique_ptr<ClContext>> contexts;
    std::vector<std::string> device_names;
    for (int d : parse_devices(p)) {
        contexts.push_back(std::make_unique<ClContext>(d));
        const ClContext& cl = *contexts.back();
        device_names.push_back(cl.info().name + (d >= 0 ? " #" + std::to_string(d) : ""));
        if (!quiet) std::fprintf(stderr, "device: %s (%s)\n", cl.info().name.c_str(), cl.info().platform.c_str());
    }
    const ClContext& cl = *contexts.front();
    if (!quiet)
        std::fprintf(stderr, "scene: %s, %zu strands, %zu segments\n", scene.source.c_str(),
                     scene.strands.strand_count(), scene.strands.segment_count());
    std::vector<std::unique_ptr<Renderer>> renderers;
    std::vector<Renderer*> devices;
    for (auto& c : contexts) {
        renderers.push_back(std::make_unique<Renderer>(*c, scene, rs));
        devices.push_back(renderers.back().get());
    }
    const Renderer& renderer = *renderers.front();
    if (!quiet && renderer.stats().clamp_indirect > 0)
        std::fprintf(stderr, "indirect light clamped at %g per sample (--clamp-indirect)\n",
                     double(renderer.stats().clamp_indirect));
    if (p.has("--verbose")) {
        // after the upload: the geometry's paging depends on the device
        for (auto& line : describe_features(renderer.features())) std::fprintf(stderr, "feature %s\n", line.c_str());
        std::fprintf(stderr, "kernel options: %s\n", renderer.stats().kernel_options.c_str());
        for (const Texture& t : scene.textures)
            std::fprintf(stderr, "texture %s: %u x %u, %s on the device\n", t.name.c_str(), t.width, t.height,
                         format_bytes(t.texels.size() * sizeof(uint32_t)).c_str());
    }
    const uint64_t key = render_key(scene, rs, renderer.kernel_options(), grid.chunk);
    SampleAccumulator acc(grid, rs.width, rs.height);
    if (p.has("--resume")) {
        const std::string path = p.get("--resume") + rank_suffix;
        Checkpoint c = load_checkpoint(path);
        if (c.render_key != key || c.width != uint32_t(rs.width) || c.height != uint32_t(rs.height) ||
            c.seed != rs.seed || c.max_depth != uint32_t(rs.max_depth) || c.chunk != uint32_t(grid.chunk))
            throw UsageError("--resume " + path +
                             ": the checkpoint belongs to a different render (scene, size, seed, depth, chunk or options differ)");
        if (c.ranks != uint32_t(dist.ranks))
            throw UsageError("--resume " + path + ": written by a run with " + std::to_string(c.ranks) +
                             " MPI ranks; resume with the same number");
        for (auto& seg : c.segments) {
            if (seg.first < my_range.first || seg.first + seg.count > my_range.end)
                throw UsageError("--resume " + path + ": it holds samples [" + std::to_string(seg.first) + ", " +
                                 std::to_string(seg.first + seg.count) + ") outside the samples this run renders [" +
                                 std::to_string(my_range.first) + ", " + std::to_string(my_range.end) + ")");
            acc.add(std::move(seg));
        }
        if (!quiet) std::fprintf(stderr, "resuming with %d of %d samples done\n", acc.samples(), my_range.count());
    }

    auto save = [&] {
        if (checkpoint_path.empty()) return;
        Checkpoint c;
        c.width = uint32_t(rs.width);
        c.height = uint32_t(rs.height);
        c.seed = rs.seed;
        c.max_depth = uint32_t(rs.max_depth);
        c.samples_done = uint32_t(acc.samples());
        c.spp_target = uint32_t(rs.spp);
        c.chunk = uint32_t(grid.chunk);
        c.range_first = uint32_t(my_range.first);
        c.range_end = uint32_t(my_range.end);
        c.rank = uint32_t(dist.rank);
        c.ranks = uint32_t(dist.ranks);
        c.render_key = key;
        c.segments = acc.segments();
        save_checkpoint(checkpoint_path, c);
    };

    const auto t0 = Clock::now();
    auto last_checkpoint = t0;
    const int done_before = acc.samples();
    bool stopped_by_limit = false;
    ChunkRunHooks hooks;
    int last_reported = -1;
    hooks.progress = [&](int n) {  // polled every 50 ms; print only when a sample finished
        if (quiet || n == last_reported) return;
        last_reported = n;
        print_progress(done_before + n, my_range.count(), since(t0));
    };
    // Periodic checkpoints are taken when a chunk finishes (the device threads are not paused
    // for them); on a stop every unfinished chunk is saved too, so a signal loses nothing.
    hooks.chunk_finished = [&] {
        if (!checkpoint_path.empty() && since(last_checkpoint) >= checkpoint_every) {
            save();
            last_checkpoint = Clock::now();
        }
    };
    hooks.should_stop = [&] {
        if (g_stop_signal) return true;
        if (time_limit > 0 && since(t0) >= time_limit) return stopped_by_limit = true;
        return false;
    };
    const auto shares = render_chunks(devices, device_names, acc, acc.pending_chunks(my_range), hooks);
    if (!quiet) std::fprintf(stderr, "\n");
    save();
    const double render_seconds = since(t0);
    const int my_done = acc.samples();
    RankReport mine;
    mine.samples = my_done;
    mine.render_seconds = render_seconds;
    reduce_to_rank0(dist, acc, &mine);
    const double reduce_seconds = mine.reduce_seconds;
    const double total_seconds = since(t0);
    const std::vector<RankReport> reports = gather_reports(dist, mine);  // collective: before any return
    if (!root) return g_stop_signal ? 128 + int(g_stop_signal) : kExitOk;
    const int done = acc.samples();
    const Film film = acc.compose();

    RenderStats st;
    for (auto* r : devices) {
        const RenderStats& rst = r->stats();
        st.camera_rays += rst.camera_rays;
        st.extension_rays += rst.extension_rays;
        st.shadow_rays += rst.shadow_rays;
        st.nonfinite_caught += rst.nonfinite_caught;
        st.build_ms += rst.build_ms;
        st.build_cached = rst.build_cached;
        for (auto& [name, sec] : rst.stage_seconds) st.stage_seconds.push_back({name, sec});
        if (st.bounces.size() < rst.bounces.size()) st.bounces.resize(rst.bounces.size());
        for (size_t b = 0; b < rst.bounces.size(); ++b) {
            st.bounces[b].paths += rst.bounces[b].paths;
            st.bounces[b].shadow_rays += rst.bounces[b].shadow_rays;
            st.bounces[b].seconds += rst.bounces[b].seconds;
        }
    }
    if (!quiet) {
        if (shares.size() > 1)
            for (auto& sh : shares)
                std::fprintf(stderr, "device %s: %d chunks, %d samples, %.2f samples/s\n", sh.name.c_str(), sh.chunks,
                             sh.samples, sh.busy_seconds > 0 ? sh.samples / sh.busy_seconds : 0.0);
        if (dist.ranks > 1)
            std::fprintf(stderr, "MPI: %d ranks; rank 0 rendered %d samples in %.2f s; all ranks done after %.2f s; "
                                 "reduction %.3f s\n", dist.ranks, my_done, render_seconds, total_seconds - reduce_seconds,
                         reduce_seconds);
        if (dist.ranks > 1)
            for (size_t r = 0; r < reports.size(); ++r)
                std::fprintf(stderr, "MPI rank %zu: %.0f samples, render %.3f s, reduction %.3f s, sent %.0f bytes, "
                                     "received %.0f bytes\n", r, reports[r].samples, reports[r].render_seconds,
                             reports[r].reduce_seconds, reports[r].bytes_sent, reports[r].bytes_received);
        std::fprintf(stderr, "done: %d spp in %.2f s; %llu camera + %llu extension + %llu shadow rays; kernel build %.0f ms%s\n",
                     done, render_seconds, (unsigned long long)st.camera_rays, (unsigned long long)st.extension_rays,
                     (unsigned long long)st.shadow_rays, st.build_ms, st.build_cached ? " (cached)" : "");
        for (auto& [name, sec] : st.stage_seconds)
            std::fprintf(stderr, "stage %-22s %8.3f s\n", name.c_str(), sec);
        if (rs.profile_stages)
            for (size_t b = 0; b < st.bounces.size(); ++b) {
                const BounceStats& bs = st.bounces[b];
                const double rays = double(bs.paths + bs.shadow_rays);
                std::fprintf(stderr, "bounce %zu: %llu paths, %llu shadow rays, %.3f s: %.2f M paths/s, %.2f M rays/s\n", b,
                             (unsigned long long)bs.paths, (unsigned long long)bs.shadow_rays, bs.seconds,
                             bs.seconds > 0 ? bs.paths / bs.seconds * 1e-6 : 0.0,
                             bs.seconds > 0 ? rays / bs.seconds * 1e-6 : 0.0);
            }
        if (stopped_by_limit) std::fprintf(stderr, "stopped by --time-limit after %d of %d spp\n", done, range.count());
        if (g_stop_signal)
            std::fprintf(stderr, "interrupted after %d of %d spp%s\n", done, range.count(),
                         checkpoint_path.empty() ? "" : "; continue with --resume");
    }
    if (st.nonfinite_caught && !quiet)
        std::fprintf(stderr, "warning: %llu non-finite shading values were caught and dropped\n",
                     (unsigned long long)st.nonfinite_caught);

    ImageMetadata meta;
    meta.ints["hairtrace:spp"] = done;
    meta.ints["hairtrace:seed"] = int(rs.seed);
    meta.ints["hairtrace:max_depth"] = rs.max_depth;
    meta.ints["hairtrace:chunk"] = grid.chunk;
    meta.floats["hairtrace:clamp_indirect"] = renderers.front()->stats().clamp_indirect;
    meta.floats["hairtrace:regularize_deg"] = rs.regularize_deg;
    meta.floats["hairtrace:render_seconds"] = float(since(t0));
    meta.text["hairtrace:device"] = cl.info().name + " / " + cl.info().platform + " " + cl.info().driver;
    meta.text["hairtrace:version"] = HT_VERSION;
    meta.text["hairtrace:scene"] = scene.source;
    const float exposure = auto_expose ? auto_exposure(film) : fixed_exposure;
    if (auto_expose) meta.floats["hairtrace:exposure"] = exposure;
    PartialImage part;
    if (partial) {
        part.width = rs.width;
        part.height = rs.height;
        part.spp_target = rs.spp;
        part.chunk = grid.chunk;
        part.max_depth = rs.max_depth;
        part.seed = rs.seed;
        part.render_key = key;
        part.scene = scene.source;
        part.segments = acc.segments();
    }
    for (auto& o : outputs) {
        // A part's .exr keeps the raw sums for the merge; other formats show its mean.
        if (partial && fs_ext_is_exr(o)) write_partial_exr(o, part, meta);
        else write_image(o, film, meta, exposure);
        if (!quiet) std::fprintf(stderr, "wrote %s\n", o.c_str());
    }
    if (!reference.empty()) {
        ErrorMetrics m = compare_images(film_to_rgb(film), reference);
        std::printf("error vs %s: RMSE %.6g  relMSE %.6g  max %.6g  mean %.6g (reference %.6g)  non-finite %zu  time %.3f s  spp %d\n",
                    p.get("--reference").c_str(), m.rmse, m.relmse, m.max_abs, m.mean, m.ref_mean, m.nonfinite,
                    since(t0), done);
    }
    if (g_stop_signal) return 128 + int(g_stop_signal);
    return kExitOk;
}

}  // namespace

}  // namespace ht
