// hairtrace converge: error against a reference as a function of render time, for several
// configurations side by side -- the run-time-against-error (Pareto) view of the renderer.
#include "cl/device.h"
#include "cli/commands.h"
#include "cli/render_request.h"
#include "cl/kernel_source.h"
#include "io/image_io.h"
#include "io/plot.h"
#include "render/error_metrics.h"
#include "render/renderer.h"
#include "kernels/types.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <sys/resource.h>

namespace ht {

namespace {

// One curve of the plot: the shared request with a configuration's keys applied.
struct ConvergeConfig {
    std::string label;
    ImageRequest request;
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

// "model=zinke,depth=5;model=marschner,depth=1": each key means what its render option means
// (model = --model, depth = --max-depth, indirect = --indirect, field = --fiber-field, sampler =
// --sampler, splits = --first-hit-splits, light_samples = --first-hit-light-samples,
// light_threshold = --light-threshold, a value or off, light_guiding = --light-guiding, a value,
// auto or off, light_vertices = --light-vertices, a count or off, light_pick = --light-pick, empty_pixels = --empty-pixels, camera_rays = --camera-rays, shadow_rays = --shadow-rays, samples_per_pass =
// --samples-per-pass), on top of the options given on the command line.
std::vector<ConvergeConfig> parse_configs(const std::string& text, const ImageRequest& base) {
    static const std::vector<std::string> known = {"model",   "depth",  "indirect",     "field",
                                                   "sampler", "splits", "light_samples", "light_threshold", "light_guiding",
                                                   "light_vertices", "light_pick", "empty_pixels", "camera_rays", "shadow_rays",
                                                   "samples_per_pass"};
    std::vector<ConvergeConfig> out;
    for (auto& c : split(text, ';')) {
        ConvergeConfig cfg{c, base};
        ImageRequest& r = cfg.request;
        for (auto& kv : split(c, ',')) {
            auto eq = kv.find('=');
            if (eq == std::string::npos) throw UsageError("--configs: '" + kv + "' is not key=value");
            const std::string k = require_choice("--configs key", kv.substr(0, eq), known), v = kv.substr(eq + 1);
            if (k == "model") r.model = require_choice("--configs model", v, fiber_model_names());
            if (k == "depth") r.max_depth = parse_int("--configs depth", v, 1, 1000);
            if (k == "indirect") r.indirect = require_choice("--configs indirect", v, indirect_mode_names());
            if (k == "field") r.fiber_field = parse_fiber_field("--configs field", v);
            if (k == "sampler")
                r.settings.sampler = require_choice("--configs sampler", v, {"sobol", "independent"}) == "sobol"
                                         ? RenderSettings::Sampler::Sobol
                                         : RenderSettings::Sampler::Independent;
            if (k == "splits")
                r.settings.first_hit_splits =
                    v == "auto" ? kAutoFirstHitSplits : parse_int("--configs splits", v, 1, kMaxFirstHitSplits);
            if (k == "light_samples") r.light_samples = parse_int("--configs light_samples", v, 1, kMaxFirstHitSplits);
            if (k == "light_threshold")
                r.settings.light_threshold = v == "off" ? 0.0f : float(parse_double("--configs light_threshold", v, kMinLightThreshold, kMaxLightThreshold));
            if (k == "light_guiding")
                r.settings.light_guiding = parse_light_guiding("--configs light_guiding", v);
            if (k == "light_vertices")
                r.settings.light_vertices =
                    v == "off" ? 0u : uint32_t(parse_int("--configs light_vertices", v, 1, int(kMaxLightVertices)));
            if (k == "camera_rays")
                r.settings.camera_lists = list_choice(require_choice("--configs camera_rays", v, {"auto", "lists", "tree"}));
            if (k == "shadow_rays")
                r.settings.shadow_lists = list_choice(require_choice("--configs shadow_rays", v, {"auto", "lists", "tree"}));
            if (k == "samples_per_pass")
                r.settings.samples_per_pass = parse_int("--configs samples_per_pass", v, 1, kMaxSamplesPerPass);
            if (k == "empty_pixels")
                r.settings.skip_empty_pixels = require_choice("--configs empty_pixels", v, {"skip", "trace"}) == "skip";
            if (k == "light_pick")
                r.settings.light_pick = require_choice("--configs light_pick", v, {"importance", "uniform"}) == "importance"
                                            ? RenderSettings::LightPick::Importance
                                            : RenderSettings::LightPick::Uniform;
        }
        out.push_back(cfg);
    }
    if (out.empty()) throw UsageError("--configs is empty");
    return out;
}

std::vector<int> parse_spp_list(const std::string& text) {
    std::vector<int> out;
    for (auto& s : split(text, ',')) {
        char* end = nullptr;
        long v = std::strtol(s.c_str(), &end, 10);
        if (*end || v < 1 || v > (1 << 24)) throw UsageError("--spp: '" + s + "' is not a sample count");
        if (!out.empty() && v <= out.back()) throw UsageError("--spp must increase: " + text);
        out.push_back(int(v));
    }
    if (out.empty()) throw UsageError("--spp is empty");
    return out;
}

// CPU seconds of this process, every thread (PoCL's workers too): on a machine shared with other
// work the wall time of a render grows with the load, its CPU time much less, so the CSV carries
// both (docs/PERFORMANCE.md §8 compares against timings taken on a quiet machine).
double process_cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

PlotSpec error_plot(const std::string& scene_name) {
    PlotSpec plot;
    plot.title = "error against render time: " + scene_name;
    plot.xlabel = "render seconds";
    plot.ylabel = "RMSE";
    plot.log_x = plot.log_y = true;
    return plot;
}

// Points measured elsewhere (--external): a CSV whose header names at least the columns spp,
// seconds and rmse (any order, other columns ignored); an optional label column splits the rows
// into curves, else the file name labels them. Quoted fields are not supported: labels are plain.
void add_external_points(PlotSpec& plot, const std::string& path) {
    std::ifstream in(path);
    if (!in) throw UsageError("--external: cannot read " + path);
    std::string line;
    if (!std::getline(in, line)) throw UsageError("--external " + path + ": empty file");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto header = split(line, ',');
    auto column = [&](const std::string& name) {
        auto it = std::find(header.begin(), header.end(), name);
        return it == header.end() ? -1 : int(it - header.begin());
    };
    const int c_spp = column("spp"), c_sec = column("seconds"), c_rmse = column("rmse"), c_label = column("label");
    if (c_spp < 0 || c_sec < 0 || c_rmse < 0)
        throw UsageError("--external " + path + ": the header must name the columns spp, seconds and rmse (it is: " + line + ")");
    const std::string fallback = path.substr(path.find_last_of('/') + 1);
    std::vector<PlotSeries> curves;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();  // a CSV saved with CRLF line ends
        if (line.empty()) continue;
        const auto f = split(line, ',');
        if (int(f.size()) != int(header.size())) throw UsageError("--external " + path + ": malformed line: " + line);
        const std::string label = c_label >= 0 ? f[size_t(c_label)] : fallback;
        auto it = std::find_if(curves.begin(), curves.end(), [&](const PlotSeries& c) { return c.label == label; });
        if (it == curves.end()) {
            PlotSeries c;
            c.label = label;
            curves.push_back(c);
            it = curves.end() - 1;
        }
        parse_int("--external " + path + " spp", f[size_t(c_spp)], 1, 1 << 30);
        it->x.push_back(parse_double("--external " + path + " seconds", f[size_t(c_sec)], 1e-9, 1e30));
        it->y.push_back(parse_double("--external " + path + " rmse", f[size_t(c_rmse)], 1e-30, 1e30));
    }
    for (auto& c : curves) {
        c.color = plot_color(plot.series.size());
        plot.series.push_back(c);
    }
}

int replot(const std::string& csv_path, const std::string& png, const std::string& scene_name,
           const std::vector<std::string>& externals) {
    std::ifstream in(csv_path);
    if (!in) throw UsageError("--replot: cannot read " + csv_path);
    std::string line;
    std::getline(in, line);  // header
    PlotSpec plot = error_plot(scene_name);
    while (std::getline(in, line)) {
        // "config",spp,seconds,rmse,...
        auto q = line.find('"', 1);
        if (line.empty() || line[0] != '"' || q == std::string::npos) throw UsageError("--replot: malformed line: " + line);
        std::string label = line.substr(1, q - 1);
        auto fields = split(line.substr(q + 2), ',');
        if (fields.size() < 3) throw UsageError("--replot: malformed line: " + line);
        if (plot.series.empty() || plot.series.back().label != label) {
            PlotSeries s;
            s.label = label;
            s.color = plot_color(plot.series.size());
            plot.series.push_back(s);
        }
        plot.series.back().x.push_back(parse_double("--replot " + csv_path + " seconds", fields[1], 0, 1e30));
        plot.series.back().y.push_back(parse_double("--replot " + csv_path + " rmse", fields[2], 0, 1e30));
    }
    for (auto& e : externals) add_external_points(plot, e);
    write_plot_png(png, plot);
    return kExitOk;
}

}  // namespace

int cmd_converge(const std::vector<std::string>& args) {
    ArgParser p("converge", "Error against a reference as a function of render time, one curve per configuration:\n"
                            "a CSV of the measurements and a log-log plot.");
    p.group("convergence")
        .path("--reference", "REF", "linear reference image (EXR) of the same size", PathKind::Input)
        .option("--configs", "LIST", "configurations separated by ';', each key=value pairs separated by ','; keys as the render options: model (--model), depth (--max-depth), indirect (--indirect), field (--fiber-field), sampler (--sampler), splits (--first-hit-splits), light_samples (--first-hit-light-samples), light_threshold (--light-threshold, a value or off), light_guiding (--light-guiding, a value, auto or off), light_vertices (--light-vertices, a count or off), light_pick (--light-pick), empty_pixels (--empty-pixels), camera_rays (--camera-rays), shadow_rays (--shadow-rays), samples_per_pass (--samples-per-pass)", "depth=1")
        .option("--spp", "LIST", "increasing sample counts at which the error is measured", "1,2,4,8,16,32")
        .path("--csv", "FILE", "write config,spp,seconds,rmse,relmse,max_error,nonfinite,sparkle_share,cpu_seconds rows (sparkle_share: pixels whose error exceeds 10x the reference's 3x3 local standard deviation, as render --reference prints; cpu_seconds: the process's CPU time, all threads)", PathKind::Csv, "converge.csv")
        .path("--png", "FILE", "log-log plot of RMSE against render time", PathKind::Image, "converge.png")
        .path("--replot", "CSV", "only redraw --png from a CSV this command wrote earlier (no rendering)", PathKind::Input)
        .path("--external", "CSV", "also draw points measured elsewhere (e.g. another renderer's timings): a CSV with a header naming spp,seconds,rmse and optionally label (one curve per label); repeatable", PathKind::Input, "", true)
        .option("--reference-noise", "SIGMA", "the reference's own noise (RMSE of the reference against the truth); when given, RMSE is plotted and written with it removed: sqrt(max(0, RMSE^2 - SIGMA^2)) (as pbrt's timings do)", "0");
    add_render_options(p, RenderCommand::Converge);
    p.parse(args);
    if (p.wants_help()) { std::cout << p.help(); return kExitOk; }
    const std::vector<std::string> externals = p.all("--external");
    if (p.has("--replot")) return replot(p.get("--replot"), p.get("--png"), p.get("SCENE"), externals);
    const double ref_noise = p.get_double("--reference-noise", 0, 1e30);
    if (!p.has("--reference")) throw UsageError("converge: --reference REF.exr is required");
    const ImageRequest base = parse_image_request(p);
    if (base.devices.all || base.devices.indices.size() > 1) throw UsageError("converge: --device takes one device index");
    const auto configs = parse_configs(p.get("--configs"), base);
    const auto spps = parse_spp_list(p.get("--spp"));
    const bool quiet = p.has("--quiet");
    const auto reference = read_reference_image(p.get("--reference"), base.settings.width, base.settings.height);
    if (!base.kernel_dir.empty()) set_kernel_dir(base.kernel_dir);
    const Scene scene = load_scene(base.scene, base.load);
    ClContext cl(device_indices(base.devices).front());

    std::ofstream csv(p.get("--csv"));
    if (!csv) throw ImageError(p.get("--csv") + ": cannot write");
    csv << "config,spp,seconds,rmse,relmse,max_error,nonfinite,sparkle_share,cpu_seconds\n";
    PlotSpec plot = error_plot(scene.source);
    for (size_t ci = 0; ci < configs.size(); ++ci) {
        const ConvergeConfig& cfg = configs[ci];
        Scene s = scene;
        apply_scene_overrides(s, cfg.request);
        RenderSettings rs = resolve_settings(s, cfg.request);
        rs.spp = spps.back();
        Renderer r(cl, s, rs);
        Film film;
        film.width = rs.width;
        film.height = rs.height;
        film.rgba.assign(4 * size_t(rs.width) * rs.height, 0.0f);
        r.upload_film(film);
        PlotSeries series;
        series.label = cfg.label;
        series.color = plot_color(ci);
        // One untimed sample first: it pays PoCL's first-launch work-group compile (up to 10 s on
        // the pbrt lock, docs/PERFORMANCE.md §7), which a user pays once per kernel and image size,
        // not per sample; then the film starts again from zero (the sample is a pure function of
        // its index, so sample 0 is rendered again identically).
        {
            auto t0 = std::chrono::steady_clock::now();
            r.render_sample(0);
            r.upload_film(film);
            if (!quiet)
                std::fprintf(stderr, "%-32s warm-up sample (first launch, not counted) %.3f s\n", cfg.label.c_str(),
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        // The per-render work on the host that depends on the camera (the empty pixels, the camera
        // rays' candidate lists, the shadow lists) counts: it is paid once per image like the samples, and an A/B
        // of those options must see it.  The scene's load and BVH build are not counted.
        double seconds = (r.stats().footprint_ms + r.stats().candidates_ms + r.stats().shadow_lists_ms) / 1000.0, cpu_seconds = 0;
        // --first-hit-splits auto: the warm-up sample ran the pilot untimed; it runs again here,
        // warm and timed, and makes the same choice (render/split_choice.h)
        if (rs.first_hit_splits == kAutoFirstHitSplits) {
            auto t0 = std::chrono::steady_clock::now();
            const double c0 = process_cpu_seconds();
            const SplitChoice choice = r.choose_first_hit_splits();
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            cpu_seconds += process_cpu_seconds() - c0;
            if (!quiet) std::fprintf(stderr, "%-32s %s\n", cfg.label.c_str(), choice.describe().c_str());
        }
        size_t next = 0;
        for (int sample = 0; sample < spps.back();) {
            auto t0 = std::chrono::steady_clock::now();
            const double c0 = process_cpu_seconds();
            // several samples per pass, never past the next point of the curve
            const int n = std::min(r.samples_per_pass(), spps[next] - sample);
            r.render_samples(uint32_t(sample), uint32_t(n));
            sample += n;
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            cpu_seconds += process_cpu_seconds() - c0;
            if (sample == spps[next]) {
                r.download_film(film);
                ErrorMetrics m = compare_images(film_to_rgb(film), reference, film.width, film.height);
                const double rmse = std::sqrt(std::max(0.0, m.rmse * m.rmse - ref_noise * ref_noise));
                csv << '"' << cfg.label << "\"," << spps[next] << ',' << seconds << ',' << rmse << ',' << m.relmse
                    << ',' << m.max_abs << ',' << m.nonfinite << ',' << m.sparkle_share << ',' << cpu_seconds << '\n';
                series.x.push_back(seconds);
                series.y.push_back(rmse);
                if (!quiet)
                    std::fprintf(stderr, "%-32s spp %6d  %8.3f s (CPU %.3f s)  RMSE %.5g  relMSE %.5g  max %.4g  non-finite %zu  sparkles %.4g %%\n",
                                 cfg.label.c_str(), spps[next], seconds, cpu_seconds, rmse, m.relmse, m.max_abs, m.nonfinite,
                                 100.0 * m.sparkle_share);
                ++next;
            }
        }
        plot.series.push_back(series);
    }
    csv.close();
    for (auto& e : externals) add_external_points(plot, e);
    write_plot_png(p.get("--png"), plot);
    if (!quiet) std::fprintf(stderr, "wrote %s and %s\n", p.get("--csv").c_str(), p.get("--png").c_str());
    return kExitOk;
}

}  // namespace ht
