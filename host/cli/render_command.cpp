// hairtrace render: parse the request, prepare (scene, devices, resumed samples), run the chunks
// with progress and checkpoints, report, write the images and the final checkpoint.
#include "cl/device.h"
#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "cli/render_request.h"
#include "core/errors.h"
#include "core/hash.h"
#include "core/image_files.h"
#include "io/image_io.h"
#include "render/adaptive.h"
#include "render/aovs.h"
#include "render/error_metrics.h"
#include "render/features.h"
#include "render/memory_plan.h"
#include "render/ray_dump.h"
#include "render/render_identity.h"
#include "render/renderer.h"
#include "split/accumulation.h"
#include "split/checkpoint.h"
#include "split/chunk_scheduler.h"
#include "split/distributed.h"
#include "split/partial_image.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

namespace ht {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
// A channel's mean over the reference's (NaN for a black reference channel: no ratio to print).
double ratio_or_nan(double x, double ref) { return ref != 0 ? x / ref : std::nan(""); }

int exit_code() { return g_stop_signal ? 128 + int(g_stop_signal) : kExitOk; }

const char* kSummary =
    "Renders SCENE progressively into every -o image; long renders stop, checkpoint and resume bit for bit.\n"
    "Every value and output path is checked before the scene is loaded.";
const char* kExitCodes =
    "exit codes: 0 ok, 2 bad input or usage, 3 device or runtime failure,\n"
    "            130/143 interrupted by SIGINT/SIGTERM after saving the images and the checkpoint";

// A render ready to run: inputs read, settings resolved, devices open, earlier samples resumed.
struct PreparedRender {
    Scene scene;
    RenderSettings settings;
    std::vector<float> reference;
    std::vector<std::unique_ptr<ClContext>> contexts;
    std::vector<std::string> device_names;
    std::unique_ptr<PreparedScene> prepared;  // once for every device (the renderers keep a reference)
    std::vector<std::unique_ptr<Renderer>> renderers;
    SampleRange range, my_range;  // the samples of the job and of this MPI rank
    std::string rank_suffix;      // each rank keeps its own checkpoint
    RenderIdentity identity;  // shared by checkpoints and render-farm parts
    std::unique_ptr<SampleAccumulator> acc;
    std::unique_ptr<RayDump> dump;  // --dump-rays
};

struct RunOutcome {
    Clock::time_point start;
    std::vector<DeviceShare> shares;
    double render_seconds = 0, total_seconds = 0, reduce_seconds = 0;
    int my_samples = 0;
    bool stopped_by_limit = false;
    bool converged = false;  // --target-error: every tile below the target before --spp
    std::vector<RankReport> reports;
};

void load_inputs(PreparedRender& job, const RenderRequest& request, bool quiet) {
    const RenderSettings& rs = request.image.settings;
    if (!request.reference.empty()) job.reference = read_reference_image(request.reference, rs.width, rs.height);
    job.scene = load_scene(request.image.scene, request.image.load);
    apply_scene_overrides(job.scene, request.image);
    std::string depth_why;
    job.settings = resolve_settings(job.scene, request.image, &depth_why);
    if (quiet) return;
    if (!depth_why.empty()) std::fprintf(stderr, "%s\n", depth_why.c_str());
    for (auto& w : job.scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

// On the main thread: opening the OpenCL runtime on a short-lived thread made AddressSanitizer fail
// at that thread's exit (PoCL's start-up replaces the thread's alternate signal stack).
void open_devices(PreparedRender& job, const RenderRequest& request, bool quiet) {
    for (int d : device_indices(request.image.devices)) {
        job.contexts.push_back(std::make_unique<ClContext>(d));
        const DeviceInfo& info = job.contexts.back()->info();
        job.device_names.push_back(info.name + (d >= 0 ? " #" + std::to_string(d) : ""));
        if (!quiet) std::fprintf(stderr, "device: %s (%s)\n", info.name.c_str(), info.platform.c_str());
    }
    if (!quiet)
        std::fprintf(stderr, "scene: %s, %zu strands, %zu segments\n", job.scene.source.c_str(),
                     job.scene.strands.strand_count(), job.scene.strands.segment_count());
    const auto start_builds = [&](const PreparedScene& recipe) {
        for (auto& c : job.contexts) prefetch_render_program(*c, recipe, job.scene);
    };
    const auto start_lists_build = [&](const PreparedScene& recipe) {
        for (auto& c : job.contexts) prefetch_lists_program(*c, recipe, job.scene);
    };
    job.prepared =
        std::make_unique<PreparedScene>(prepare_scene(job.scene, job.settings, start_builds, start_lists_build));
    // one device may render from the prepared scene's own arrays; several each take a copy
    const GeometryMemory geometry = job.contexts.size() > 1 ? GeometryMemory::Copy : GeometryMemory::Shared;
    for (auto& c : job.contexts) job.renderers.push_back(std::make_unique<Renderer>(*c, *job.prepared, geometry));
    // --first-hit-splits auto: one pilot, on the first device; every device uses its choice
    if (job.settings.first_hit_splits == kAutoFirstHitSplits) {
        const SplitChoice choice = job.renderers.front()->choose_first_hit_splits();
        for (size_t i = 1; i < job.renderers.size(); ++i) job.renderers[i]->set_first_hit_splits(choice.splits);
        if (!quiet && choice.seconds > 0) std::fprintf(stderr, "%s\n", choice.describe().c_str());
    }
    const Renderer& renderer = *job.renderers.front();
    if (!quiet && renderer.stats().clamp_indirect > 0)
        std::fprintf(stderr, "indirect light clamped at %g per sample (--clamp-indirect)\n",
                     double(renderer.stats().clamp_indirect));
    if (!request.verbose) return;
    const BvhStats& bvh = job.prepared->geometry.stats;
    std::fprintf(stderr, "bvh: %zu nodes (%zu oriented), %zu leaves, depth %zu, %.1f bytes/segment, built in %.0f ms\n",
                 bvh.nodes, bvh.oriented, bvh.leaves, bvh.max_depth, bvh.bytes_per_segment, bvh.build_ms);
    // after the upload: the geometry's paging depends on the device
    for (auto& line : describe_features(renderer.features())) std::fprintf(stderr, "feature %s\n", line.c_str());
    std::fprintf(stderr, "kernel options: %s\n", renderer.stats().kernel_options.c_str());
    for (const Texture& t : job.scene.textures)
        std::fprintf(stderr, "texture %s: %u x %u, %s on the device\n", t.name.c_str(), t.width, t.height,
                     format_bytes(t.texels.size() * sizeof(uint32_t)).c_str());
}

void resume_samples(PreparedRender& job, const RenderRequest& request, const DistContext& dist, bool quiet) {
    const SampleRange& my_range = job.my_range;
    SampleAccumulator& acc = *job.acc;
    const std::string path = request.resume + job.rank_suffix;
    Checkpoint c = load_checkpoint(path);
    if (c.identity != job.identity)
        throw UsageError("--resume " + path + ": the checkpoint was rendered with " + c.identity.differences(job.identity) +
                         "; resume with the scene and options it was started with");
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

void prepare(PreparedRender& job, const RenderRequest& request, const DistContext& dist, bool quiet) {
    job.range = request.sample_range.value_or(SampleRange{0, request.grid.spp});
    job.my_range = rank_range(job.range, request.grid, dist.rank, dist.ranks);
    job.rank_suffix = dist.ranks > 1 ? ".rank" + std::to_string(dist.rank) : "";
    if (dist.ranks > 1 && request.image.settings.target_error > 0)
        throw UsageError("render: --target-error cannot run on " + std::to_string(dist.ranks) +
                         " MPI ranks: which pixels a chunk renders depends on the chunks before it, which "
                         "other ranks render; run it as one process (--device all uses every local device)");
    if (!request.image.kernel_dir.empty()) set_kernel_dir(request.image.kernel_dir);
    load_inputs(job, request, quiet);
    if (!quiet && dist.mpi) {
        const std::string w = cpu_binding_warning(local_rank_count());
        if (!w.empty()) std::fprintf(stderr, "warning: %s\n", w.c_str());
    }
    open_devices(job, request, quiet);
    job.identity = render_identity(job.scene, *job.prepared, request.grid.chunk, request.aovs);
    job.acc = std::make_unique<SampleAccumulator>(request.grid, job.settings.width, job.settings.height,
                                                  aov_sums_per_pixel(request.aovs));
    if (!request.resume.empty()) resume_samples(job, request, dist, quiet);
}

void save_state(const PreparedRender& job, const RenderRequest& request, const DistContext& dist) {
    if (request.checkpoint.empty()) return;
    Checkpoint c;
    c.width = uint32_t(job.settings.width);
    c.height = uint32_t(job.settings.height);
    c.seed = job.settings.seed;
    c.max_depth = uint32_t(job.settings.max_depth);
    c.samples_done = uint32_t(job.acc->samples());
    c.spp_target = uint32_t(request.grid.spp);
    c.chunk = uint32_t(request.grid.chunk);
    c.range_first = uint32_t(job.my_range.first);
    c.range_end = uint32_t(job.my_range.end);
    c.rank = uint32_t(dist.rank);
    c.ranks = uint32_t(dist.ranks);
    c.aov_sums = uint32_t(job.acc->aov_sums());
    c.even_sums = job.settings.target_error > 0 ? 4 : 0;
    c.identity = job.identity;
    c.segments = job.acc->segments();
    save_checkpoint(request.checkpoint + job.rank_suffix, c);
}

void add_shares(std::vector<DeviceShare>& total, const std::vector<DeviceShare>& more) {
    if (total.empty()) total = more;
    else
        for (size_t d = 0; d < more.size(); ++d) {
            total[d].chunks += more[d].chunks;
            total[d].samples += more[d].samples;
            total[d].busy_seconds += more[d].busy_seconds;
        }
}

// --target-error: the chunks one at a time, in order, each on the tiles the film of the chunks
// before it leaves above the target (render/adaptive.h); stops when none is left.  One chunk at a
// time leaves all but one device idle, but keeps the image that of one device.
std::vector<DeviceShare> render_adaptive(PreparedRender& job, const std::vector<Renderer*>& devices,
                                         const std::vector<int>& pending, const ChunkRunHooks& hooks,
                                         RunOutcome& out) {
    const ChunkGrid& grid = job.acc->grid();
    std::vector<DeviceShare> shares;
    bool stopped = false;
    ChunkRunHooks once = hooks;
    int before = 0;  // samples rendered by the earlier calls, for the progress line
    once.progress = [&](int n) { hooks.progress(before + n); };
    once.should_stop = [&] { return stopped = stopped || hooks.should_stop(); };
    for (int j : pending) {
        const int first = grid.begin(j);
        std::vector<uint32_t> pixels;  // empty: every pixel
        if (first >= job.settings.adaptive_min_spp) {
            const AdaptiveState st = assess_film(job.acc->compose_before(first), first, job.settings.target_error);
            if (st.pixels.empty()) {
                out.converged = true;
                break;
            }
            pixels = st.pixels;
        }
        for (Renderer* r : devices) r->set_pixels(pixels);
        const int done = job.acc->samples();
        add_shares(shares, render_chunks(devices, job.device_names, *job.acc, {j}, once));
        before += job.acc->samples() - done;
        if (stopped) break;
    }
    return shares;
}

RunOutcome run(PreparedRender& job, const RenderRequest& request, DistContext& dist, bool quiet) {
    RunOutcome out;
    out.start = Clock::now();
    auto last_checkpoint = out.start;
    const int done_before = job.acc->samples();
    Progress progress(!quiet);
    ChunkRunHooks hooks;
    hooks.progress = [&](int n) { progress.update(done_before + n, job.my_range.count(), since(out.start)); };
    // Periodic checkpoints are taken when a chunk finishes (the device threads are not paused
    // for them); on a stop every unfinished chunk is saved too, so a signal loses nothing.
    hooks.chunk_finished = [&] {
        if (!request.checkpoint.empty() && since(last_checkpoint) >= request.checkpoint_every) {
            save_state(job, request, dist);
            last_checkpoint = Clock::now();
        }
    };
    hooks.should_stop = [&] {
        if (g_stop_signal) return true;
        if (request.time_limit > 0 && since(out.start) >= request.time_limit) return out.stopped_by_limit = true;
        return false;
    };
    std::vector<Renderer*> devices;
    for (auto& r : job.renderers) devices.push_back(r.get());
    const std::vector<int> pending = job.acc->pending_chunks(job.my_range);
    if (job.settings.target_error > 0) out.shares = render_adaptive(job, devices, pending, hooks, out);
    else out.shares = render_chunks(devices, job.device_names, *job.acc, pending, hooks);
    progress.finish();
    // The reduction replaces each rank's samples with the chain's: save them before it.
    if (dist.ranks > 1) save_state(job, request, dist);
    out.render_seconds = since(out.start);
    out.my_samples = job.acc->samples();
    RankReport mine;
    mine.samples = out.my_samples;
    mine.render_seconds = out.render_seconds;
    reduce_to_rank0(dist, *job.acc, &mine);
    out.reduce_seconds = mine.reduce_seconds;
    out.total_seconds = since(out.start);
    out.reports = gather_reports(dist, mine);  // collective: every rank calls it
    return out;
}

RenderStats summed_stats(const PreparedRender& job) {
    RenderStats st;
    for (const auto& r : job.renderers) st.add(r->stats());
    return st;
}

void report_split(const RunOutcome& out, const DistContext& dist) {
    if (out.shares.size() > 1)
        for (auto& sh : out.shares)
            std::fprintf(stderr, "device %s: %d chunks, %d samples, %.2f samples/s\n", sh.name.c_str(), sh.chunks,
                         sh.samples, sh.busy_seconds > 0 ? sh.samples / sh.busy_seconds : 0.0);
    if (dist.ranks <= 1) return;
    std::fprintf(stderr, "MPI: %d ranks; rank 0 rendered %d samples in %.2f s; all ranks done after %.2f s; "
                         "reduction %.3f s\n", dist.ranks, out.my_samples, out.render_seconds,
                 out.total_seconds - out.reduce_seconds, out.reduce_seconds);
    for (size_t r = 0; r < out.reports.size(); ++r)
        std::fprintf(stderr, "MPI rank %zu: %.0f samples, render %.3f s, reduction %.3f s, sent %.0f bytes, "
                             "received %.0f bytes\n", r, out.reports[r].samples, out.reports[r].render_seconds,
                     out.reports[r].reduce_seconds, out.reports[r].bytes_sent, out.reports[r].bytes_received);
}

// The error estimate of the image as written (render/adaptive.h).
AdaptiveState final_error(const PreparedRender& job) {
    return assess_film(job.acc->compose(), 0, job.settings.target_error);
}

void report(const PreparedRender& job, const RenderRequest& request, const RunOutcome& out, const DistContext& dist) {
    const RenderStats st = summed_stats(job);
    const int done = job.acc->samples();
    report_split(out, dist);
    std::fprintf(stderr, "done: %d spp in %.2f s; %llu camera + %llu extension + %llu shadow rays; kernel build %.0f ms%s\n",
                 done, out.render_seconds, (unsigned long long)st.camera_rays, (unsigned long long)st.extension_rays,
                 (unsigned long long)st.shadow_rays, st.build_ms, st.build_cached ? " (cached)" : "");
    if (st.light_rays)
        std::fprintf(stderr, "light vertices: %llu light rays traced (their connections are among the shadow rays)\n",
                     (unsigned long long)st.light_rays);
    if (st.background_samples)
        std::fprintf(stderr, "%zu of %d pixels see no geometry (found in %.0f ms): %llu of their samples are the background's, not traced\n",
                     st.empty_pixels, job.settings.width * job.settings.height, st.footprint_ms,
                     (unsigned long long)st.background_samples);
    if (st.candidate_entries)
        std::fprintf(stderr, "camera rays from per-pixel lists: %zu entries (made in %.0f ms), %zu pixels with more traverse the tree\n",
                     st.candidate_entries, st.candidates_ms, st.candidate_tree_pixels);
    if (st.shadow_list_entries)
        std::fprintf(stderr, "shadow rays from the lights' per-cell lists: %zu entries (made in %.0f ms)\n",
                     st.shadow_list_entries, st.shadow_lists_ms);
    if (st.path_grid_entries)
        std::fprintf(stderr, "path rays from a uniform grid: %zu cells (%zu hold capsules), %zu entries (made in %.0f ms)\n",
                     st.path_grid_cells, st.path_grid_occupied, st.path_grid_entries, st.path_grid_ms);
    if (st.path_grid_dropped)
        std::fprintf(stderr, "path rays' grid left out: an array of it exceeds the device's largest allocation (the rays traverse the BVH instead, the same image)\n");
    if (st.camera_lists_dropped || st.shadow_lists_dropped)
        std::fprintf(stderr, "%s left out: the render fits the device memory only without them (the rays traverse the BVH instead, the same image)\n",
                     st.camera_lists_dropped && st.shadow_lists_dropped ? "camera-ray and shadow-ray lists"
                     : st.camera_lists_dropped                          ? "camera-ray lists"
                                                                        : "shadow-ray lists");
    if (st.paths)
        std::fprintf(stderr, "max depth %d cut %llu of %llu paths (%.3g %%)\n", job.settings.max_depth,
                     (unsigned long long)st.cut_paths, (unsigned long long)st.paths,
                     100.0 * double(st.cut_paths) / double(st.paths));
    for (auto& [name, sec] : st.stage_seconds) std::fprintf(stderr, "stage %-26s %8.3f s\n", name.c_str(), sec);
    if (request.profile)
        for (size_t b = 0; b < st.bounces.size(); ++b) {
            const BounceStats& bs = st.bounces[b];
            const double rays = double(bs.paths + bs.shadow_rays);
            std::fprintf(stderr, "bounce %zu: %llu paths, %llu shadow rays, %llu cut, %.3f s: %.2f M paths/s, %.2f M rays/s\n", b,
                         (unsigned long long)bs.paths, (unsigned long long)bs.shadow_rays,
                         (unsigned long long)bs.cut_paths, bs.seconds,
                         bs.seconds > 0 ? bs.paths / bs.seconds * 1e-6 : 0.0,
                         bs.seconds > 0 ? rays / bs.seconds * 1e-6 : 0.0);
        }
    if (out.stopped_by_limit) std::fprintf(stderr, "stopped by --time-limit after %d of %d spp\n", done, job.range.count());
    if (job.settings.target_error > 0) {
        const AdaptiveState a = final_error(job);
        std::fprintf(stderr, "target error %g %s%s: error estimate %.4g (largest tile), %.4g (RMS over %d tiles); "
                             "%d tiles above it; spp per pixel %d-%d, mean %.1f\n",
                     double(job.settings.target_error), a.tiles_above ? "not reached" : "reached",
                     out.converged ? " before --spp" : "", a.max_error, a.rms_error, a.tiles, a.tiles_above,
                     a.min_spp, a.max_spp, a.mean_spp);
    }
    if (g_stop_signal)
        std::fprintf(stderr, "interrupted after %d of %d spp%s\n", done, job.range.count(),
                     request.checkpoint.empty() ? "" : "; continue with --resume");
    if (st.nonfinite_caught)
        std::fprintf(stderr, "warning: %llu non-finite shading values were caught and dropped\n",
                     (unsigned long long)st.nonfinite_caught);
}

std::string utc_now(const char* format) {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, format, &tm);
    return buf;
}

// What the image was made from, for anyone who finds the file later: command line, the render
// identity (render/render_identity.h: geometry, materials, lights, camera and settings digests),
// fibre models, light transport, the kernel features compiled in, and where and when.
ImageMetadata metadata_of(const PreparedRender& job, const RenderRequest& request, const RunOutcome& out) {
    const DeviceInfo& device = job.contexts.front()->info();
    ImageMetadata meta;
    meta.text["hairtrace:command_line"] = shell_words(request.command_line);
    meta.text["hairtrace:render_key"] = hex64(job.identity.key());
    meta.text["hairtrace:identity"] = job.identity.to_text();
    std::string models;
    for (const HairMaterialDesc& m : job.scene.materials) models += (models.empty() ? "" : ", ") + m.name + "=" + m.model;
    meta.text["hairtrace:fiber_model"] = models;
    const char* const field_names[] = {"material", "near", "far", "auto"};  // HT_FIELD_* order (kernels/types.h)
    meta.text["hairtrace:fiber_field"] = field_names[std::min<uint32_t>(job.settings.fiber_field, 3)];
    meta.text["hairtrace:indirect"] = request.image.indirect;
    std::string features = job.settings.features == FeatureMode::All        ? "all:"
                           : job.settings.features == FeatureMode::AllLobes ? "all-lobes:"
                                                                            : "scene:";
    const KernelFeatures& on = job.renderers.front()->features();
    for (size_t f = 0; f < kFeatureCount; ++f)
        if (on.on[f]) features += std::string(" ") + feature_define(Feature(f));
    meta.text["hairtrace:features"] = features;
    meta.text["hairtrace:date"] = utc_now("%Y-%m-%dT%H:%M:%SZ");
    meta.text["DateTime"] = utc_now("%Y:%m:%d %H:%M:%S");  // the TIFF/EXIF form OIIO maps to each format's own tag
    meta.ints["hairtrace:spp"] = job.acc->samples();
    meta.ints["hairtrace:seed"] = int(job.settings.seed);
    meta.ints["hairtrace:max_depth"] = job.settings.max_depth;
    meta.ints["hairtrace:first_hit_splits"] = job.renderers.front()->first_hit_splits();
    meta.text["hairtrace:first_hit_splits_mode"] = job.settings.first_hit_splits == kAutoFirstHitSplits ? "auto" : "fixed";
    meta.ints["hairtrace:first_hit_light_samples"] = job.settings.first_hit_light_samples;
    meta.text["hairtrace:light_pick"] =
        job.settings.light_pick == RenderSettings::LightPick::Importance ? "importance" : "uniform";
    meta.ints["hairtrace:chunk"] = request.grid.chunk;
    meta.floats["hairtrace:clamp_indirect"] = job.renderers.front()->stats().clamp_indirect;
    meta.floats["hairtrace:regularize_deg"] = job.settings.regularize_deg;
    meta.floats["hairtrace:light_threshold"] = job.settings.light_threshold;
    meta.floats["hairtrace:light_guiding"] = job.renderers.front()->stats().light_guiding;
    if (job.settings.light_vertices > 0) meta.ints["hairtrace:light_vertices"] = int(job.settings.light_vertices);
    meta.floats["hairtrace:render_seconds"] = float(since(out.start));
    meta.text["hairtrace:device"] = device.name + " / " + device.platform + " " + device.driver;
    meta.text["hairtrace:version"] = HT_VERSION;
    meta.text["hairtrace:scene"] = job.scene.source;
    return meta;
}

PartialImage partial_image_of(const PreparedRender& job, const RenderRequest& request) {
    PartialImage part;
    part.width = job.settings.width;
    part.height = job.settings.height;
    part.spp_target = request.grid.spp;
    part.chunk = request.grid.chunk;
    part.max_depth = job.settings.max_depth;
    part.seed = job.settings.seed;
    part.identity = job.identity;
    part.scene = job.scene.source;
    part.aovs = request.aovs;
    part.segments = job.acc->segments();
    return part;
}

void write_outputs(const PreparedRender& job, const RenderRequest& request, const RunOutcome& out, bool quiet) {
    const Film film = job.acc->compose();
    ImageMetadata meta = metadata_of(job, request, out);
    const float exposure = request.exposure ? *request.exposure : auto_exposure(film);
    meta.floats["hairtrace:exposure"] = exposure;
    meta.text["hairtrace:tonemap"] = tone_map_name(request.tone_map);
    const std::vector<ImageChannel> aovs = aov_channels(film, request.aovs);
    std::vector<ImageChannel> exr_channels = aovs;
    if (job.settings.target_error > 0) {
        const AdaptiveState a = final_error(job);
        meta.floats["hairtrace:target_error"] = job.settings.target_error;
        meta.floats["hairtrace:error_estimate"] = float(a.max_error);
        meta.floats["hairtrace:error_estimate_rms"] = float(a.rms_error);
        meta.floats["hairtrace:spp_mean"] = float(a.mean_spp);
        meta.ints["hairtrace:min_spp"] = job.settings.adaptive_min_spp;
        // where the samples went: cheap, and only EXR takes a channel of any name
        ImageChannel spp{"spp", std::vector<float>(size_t(film.width) * size_t(film.height))};
        for (size_t i = 0; i < spp.values.size(); ++i) spp.values[i] = film.rgba[4 * i + 3];
        exr_channels.push_back(std::move(spp));
    }
    for (auto& o : request.outputs) {
        // A part's .exr keeps the raw sums for the merge; other formats show its mean.
        if (request.sample_range && keeps_raw_sums(o)) write_partial_exr(o, partial_image_of(job, request), meta);
        else write_image(o, film, meta, exposure, request.tone_map, keeps_raw_sums(o) ? exr_channels : aovs);
        if (!quiet) std::fprintf(stderr, "wrote %s\n", o.c_str());
    }
    if (job.reference.empty()) return;
    const ErrorMetrics m = compare_images(film_to_rgb(film), job.reference, film.width, film.height);
    std::printf("error vs %s: RMSE %.6g  relMSE %.6g  max %.6g  mean %.6g (reference %.6g)  non-finite %zu  "
                "sparkles %.4g %% (%zu px > %gx local noise)  time %.3f s  spp %d  "
                "rgb mean / reference %.4f / %.4f / %.4f\n",
                request.reference.c_str(), m.rmse, m.relmse, m.max_abs, m.mean, m.ref_mean, m.nonfinite,
                100.0 * m.sparkle_share, m.sparkles, kSparkleFactor, since(out.start), job.acc->samples(),
                ratio_or_nan(m.channel_mean[0], m.ref_channel_mean[0]),
                ratio_or_nan(m.channel_mean[1], m.ref_channel_mean[1]),
                ratio_or_nan(m.channel_mean[2], m.ref_channel_mean[2]));
}

// --dump-rays on the first device of rank 0; the files are named after the scene.
void attach_ray_dump(PreparedRender& job, const RenderRequest& request, bool root) {
    if (request.dump_rays.empty() || !root) return;
    // "builtin:strand?hairs=200" -> strand, "data/ball.hair" -> ball
    std::string name = job.scene.source.substr(0, job.scene.source.find('?'));
    name = std::filesystem::path(name.substr(name.rfind(':') + 1)).stem().string();
    // the anchor's hash for hair alone: its format has no triangles
    const uint64_t hash = job.scene.meshes.empty() ? hair_file_hash(job.scene.strands) : 0;
    job.dump = std::make_unique<RayDump>(request.dump_rays, name.empty() ? "scene" : name, hash);
    job.renderers.front()->set_ray_dump(job.dump.get());
}

int render_main(const std::vector<std::string>& args, DistContext& dist) {
    ArgParser p("render", kSummary);
    add_render_options(p, RenderCommand::Render);
    p.epilog(kExitCodes);
    p.parse(args);
    // From here on SIGINT/SIGTERM only set a flag: even one arriving during start-up ends in
    // saved images and a checkpoint rather than a lost process.
    g_stop_signal = 0;
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    if (p.wants_help()) {
        std::cout << p.help();
        return kExitOk;
    }
    // OpenImageIO loads (~0.45 s) on the other core while the scene loads and the BVH builds;
    // parse() checked the outputs' formats against the kept list (host/io/image_formats.h), or
    // loaded it already.  The OpenCL runtime's libraries first: the dynamic loader takes one
    // library at a time, and the devices would wait for OpenImageIO's (docs/PERFORMANCE.md §3).
    // Asking for the devices is what loads PoCL's device drivers (the platforms alone left
    // "device:" at 0.5-0.7 s instead of 0.2 s on pbrt's lock); open_devices() asks again, cheaply.
    (void)list_devices();
    ImageFilesPreload image_files_loading;
    RenderRequest request = parse_render_request(p);
    request.command_line = {"hairtrace", "render"};
    request.command_line.insert(request.command_line.end(), args.begin(), args.end());
    const bool root = dist.rank == 0;
    const bool quiet = request.quiet || !root;  // one progress report per job, from rank 0
    PreparedRender job;
    prepare(job, request, dist, quiet);
    attach_ray_dump(job, request, root);
    const RunOutcome outcome = run(job, request, dist, quiet);
    if (!root) return exit_code();
    if (!quiet) report(job, request, outcome, dist);
    write_outputs(job, request, outcome, quiet);
    // after the images, which a ray file that cannot be written must not cost (nor the checkpoint)
    if (job.dump) try {
            for (const std::string& f : job.dump->write()) std::fprintf(stderr, "rays: %s\n", f.c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "warning: --dump-rays: %s\n", e.what());
        }
    // After the images: a checkpoint that cannot be written must not cost the render's images.
    if (dist.ranks == 1) save_state(job, request, dist);
    return exit_code();
}

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
        std::fprintf(stderr, "hairtrace (rank %d of %d): %s\n", dist.rank, dist.ranks, e.what());
        dist_abort(dist, exit_code_for(e));
    }
    dist_finalize(dist);
    return code;
}

}  // namespace ht
