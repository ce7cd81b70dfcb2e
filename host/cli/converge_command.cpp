// hairtrace converge: error against a reference as a function of render time, for several
// configurations side by side -- the run-time-against-error (Pareto) view of the renderer.
#include "cl/device.h"
#include "cli/commands.h"
#include "io/image_io.h"
#include "io/plot.h"
#include "render/error_metrics.h"
#include "render/renderer.h"
#include "kernels/types.h"

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace ht {

namespace {

struct ConvergeConfig {
    std::string label;
    std::map<std::string, std::string> keys;
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

// "model=zinke,depth=5;model=marschner,depth=1"
std::vector<ConvergeConfig> parse_configs(const std::string& text) {
    static const std::vector<std::string> known = {"model", "depth", "indirect", "field"};
    std::vector<ConvergeConfig> out;
    for (auto& c : split(text, ';')) {
        ConvergeConfig cfg;
        cfg.label = c;
        for (auto& kv : split(c, ',')) {
            auto eq = kv.find('=');
            if (eq == std::string::npos) throw UsageError("--configs: '" + kv + "' is not key=value");
            std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
            if (std::find(known.begin(), known.end(), k) == known.end())
                throw UsageError("--configs: unknown key '" + k + "' (known: model, depth, indirect, field)");
            cfg.keys[k] = v;
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

PlotSpec error_plot(const std::string& scene_name) {
    PlotSpec plot;
    plot.title = "error against render time: " + scene_name;
    plot.xlabel = "render seconds";
    plot.ylabel = "RMSE";
    plot.log_x = plot.log_y = true;
    return plot;
}

int replot(const std::string& csv_path, const std::string& png, const std::string& scene_name) {
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
        plot.series.back().x.push_back(std::stod(fields[1]));
        plot.series.back().y.push_back(std::stod(fields[2]));
    }
    write_plot_png(png, plot);
    return kExitOk;
}

}  // namespace

int cmd_converge(const std::vector<std::string>& args) {
    ArgParser p("converge");
    p.positional("SCENE", "scene file or builtin:NAME");
    p.option("--reference", "REF", "linear reference image (EXR) of the same size")
        .option("--configs", "LIST", "configurations separated by ';', each key=value pairs separated by ','; keys: model (kajiya|marschner|zinke|chiang), depth (bounces), indirect (exact|afs; afs without depth means depth 1), field (near|far|auto|material)", "depth=1")
        .option("--spp", "LIST", "increasing sample counts at which the error is measured", "1,2,4,8,16,32")
        .option("--width", "W", "image width (must match the reference)", "256")
        .option("--height", "H", "image height (must match the reference)", "256")
        .option("--seed", "S", "random seed", "1")
        .option("--csv", "FILE", "write config,spp,seconds,rmse,relmse,max_error,nonfinite rows", "converge.csv")
        .option("--png", "FILE", "log-log plot of RMSE against render time", "converge.png")
        .option("--device", "I", "OpenCL device index")
        .option("--replot", "CSV", "only redraw --png from a CSV this command wrote earlier (no rendering)");
    add_scene_options(p);
    p.flag("--quiet", "no progress on stderr").flag("--help", "this help");
    p.parse(args);
    if (p.has("--help")) { std::cout << p.help(); return kExitOk; }
    if (p.has("--replot")) return replot(p.get("--replot"), p.get("--png"), p.get("SCENE"));
    if (!p.has("--reference")) throw UsageError("converge: --reference REF.exr is required");
    auto configs = parse_configs(p.get("--configs"));
    auto spps = parse_spp_list(p.get("--spp"));
    const bool quiet = p.has("--quiet");
    int rw, rh;
    auto reference = read_rgb_image(p.get("--reference"), rw, rh);
    RenderSettings base;
    base.width = p.get_int("--width", 1, 16384);
    base.height = p.get_int("--height", 1, 16384);
    if (rw != base.width || rh != base.height)
        throw UsageError("--reference is " + std::to_string(rw) + "x" + std::to_string(rh) + ", the renders are " +
                         std::to_string(base.width) + "x" + std::to_string(base.height));
    base.seed = uint32_t(p.get_int("--seed", 0, 2147483647));
    Scene scene = load_scene(p.get("SCENE"), scene_load_options(p));
    apply_hair_color_options(p, scene);
    ensure_camera_and_light(scene, scene_view_options(p));
    ClContext cl(p.has("--device") ? p.get_int("--device", 0, 1000) : -1);

    std::ofstream csv(p.get("--csv"));
    if (!csv) throw ImageError(p.get("--csv") + ": cannot write");
    csv << "config,spp,seconds,rmse,relmse,max_error,nonfinite\n";
    PlotSpec plot = error_plot(scene.source);
    for (size_t ci = 0; ci < configs.size(); ++ci) {
        const ConvergeConfig& cfg = configs[ci];
        Scene s = scene;
        RenderSettings rs = base;
        if (cfg.keys.count("model")) apply_model_override(s, cfg.keys.at("model"));
        if (cfg.keys.count("depth")) {
            char* end = nullptr;
            long d = std::strtol(cfg.keys.at("depth").c_str(), &end, 10);
            if (*end || d < 1 || d > 1000) throw UsageError("--configs: depth must be 1..1000");
            rs.max_depth = int(d);
        }
        if (cfg.keys.count("indirect")) {
            const std::string& v = cfg.keys.at("indirect");
            if (v == "afs") {
                rs.indirect = RenderSettings::Indirect::Afs;
                if (!cfg.keys.count("depth")) rs.max_depth = 1;
            } else if (v != "exact") {
                throw UsageError("--configs: indirect must be exact or afs, got '" + v + "'");
            }
        }
        if (cfg.keys.count("field")) rs.fiber_field = parse_fiber_field("--configs field", cfg.keys.at("field"));
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
        double seconds = 0;
        size_t next = 0;
        for (int sample = 0; sample < spps.back(); ++sample) {
            auto t0 = std::chrono::steady_clock::now();
            r.render_sample(uint32_t(sample));
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (sample + 1 == spps[next]) {
                r.download_film(film);
                ErrorMetrics m = compare_images(film_to_rgb(film), reference);
                csv << '"' << cfg.label << "\"," << spps[next] << ',' << seconds << ',' << m.rmse << ',' << m.relmse
                    << ',' << m.max_abs << ',' << m.nonfinite << '\n';
                series.x.push_back(seconds);
                series.y.push_back(m.rmse);
                if (!quiet)
                    std::fprintf(stderr, "%-32s spp %6d  %8.3f s  RMSE %.5g  relMSE %.5g  max %.4g  non-finite %zu\n",
                                 cfg.label.c_str(), spps[next], seconds, m.rmse, m.relmse, m.max_abs, m.nonfinite);
                ++next;
            }
        }
        plot.series.push_back(series);
    }
    csv.close();
    write_plot_png(p.get("--png"), plot);
    if (!quiet) std::fprintf(stderr, "wrote %s and %s\n", p.get("--csv").c_str(), p.get("--png").c_str());
    return kExitOk;
}

}  // namespace ht
