#include "cli/fiber_command.h"

#include "cli/args.h"
#include "cli/commands.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cl/device.h"
#include "fiber/afs_quadrature.h"
#include "fiber/furnace.h"
#include "fiber/fiber_query_runner.h"
#include "fiber/material.h"
#include "fiber/query_json.h"
#include "kernels/fiber/bcsdf.h"
#include "kernels/fiber/query.h"

namespace ht {

namespace {

using nlohmann::json;

const char* kOverview =
    "usage: hairtrace fiber eval|sample|furnace|afs [options]\n"
    "The fibre scattering models from the command line.\n"
    "\n"
    "subcommands:\n"
    "  eval      evaluate the BCSDF for JSON query lines on stdin: one JSON line out per query\n"
    "  sample    sample the BCSDF for JSON query lines on stdin (each with \"u\":[u0,u1,u2,u3])\n"
    "  furnace   directional albedo of a material over incidence angles (white furnace test)\n"
    "  afs       the paper's averaged forward scattering AFS^avg (Zinke 2004 Fig. 4)\n"
    "\n"
    "hairtrace fiber SUBCOMMAND --help lists its options.\n"
    "exit codes: 0 ok, 2 bad input (a bad JSON line gets {\"error\": ...} and the run continues),\n"
    "            3 device failure (--precision float)\n";

std::vector<double> parse_list(const std::string& opt, const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(parse_double(opt, item, -1e30, 1e30));
    if (v.empty()) throw UsageError(opt + ": empty list");
    return v;
}

json arr3(double a, double b, double c) { return json::array({a, b, c}); }
json arr3(real3 v) { return arr3(v.x, v.y, v.z); }

// The double-precision path uses the query's exact inputs; the float path their float copies.
int run_queries(const ArgParser& p, bool sample, std::istream& in, std::ostream& out) {
    const std::string precision = p.get_choice("--precision", {"double", "float"});
    const int device = p.has("--device") ? p.get_int("--device", 0, 1000) : -1;
    std::vector<std::string> lines;
    std::string line;
    while (std::getline(in, line)) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        lines.push_back(line);
    }
    std::vector<FiberJsonQuery> qs;
    qs.reserve(lines.size());
    for (auto& l : lines) qs.push_back(parse_fiber_query(l, sample));
    std::vector<HtFiberResult> res(qs.size());
    if (precision == "double") {
        for (size_t i = 0; i < qs.size(); ++i) {
            if (!qs[i].valid) continue;
            const real3 wo = qs[i].wo;
            const double h = qs[i].h;
            if (!sample) {
                real3 wi = qs[i].wi, lobes[4], value;
                real pdf;
                ht_bcsdf_eval_lobes(&qs[i].m, wo, wi, h, lobes, &value, &pdf);
                json o;
                o["value"] = arr3(value);
                o["pdf"] = pdf;
                o["lobes"] = {{"R", arr3(lobes[0])}, {"TT", arr3(lobes[1])}, {"TRT", arr3(lobes[2])}, {"residual", arr3(lobes[3])}};
                lines[i] = o.dump();
            } else {
                const double* u = qs[i].u;
                real3 wi, weight;
                real pdf;
                ht_bcsdf_sample(&qs[i].m, wo, h, u[0], u[1], u[2], u[3], &wi, &weight, &pdf);
                json o;
                o["wi"] = arr3(wi);
                o["weight"] = arr3(weight);
                o["pdf"] = pdf;
                lines[i] = o.dump();
            }
        }
    } else {
        std::vector<HtMaterial> mats;
        std::vector<HtFiberQuery> qv;
        std::vector<size_t> index;
        for (size_t i = 0; i < qs.size(); ++i)
            if (qs[i].valid) { mats.push_back(qs[i].m); qv.push_back(qs[i].q); index.push_back(i); }
        if (!qv.empty()) {
            try {
                ClContext ctx(device);
                cl::Program prog = ctx.build("fiber/fiber_query.cl", base_kernel_options());
                const std::vector<HtFiberResult> out_r =
                    run_fiber_queries(ctx, prog, sample ? "fiber_sample" : "fiber_eval", mats, qv);
                for (size_t t = 0; t < index.size(); ++t) res[index[t]] = out_r[t];
            } catch (const cl::Error& e) {
                throw DeviceError(std::string("OpenCL: ") + e.what() + " (" + cl_error_name(e.err()) + ")");
            }
        }
        for (size_t i = 0; i < qs.size(); ++i) {
            if (!qs[i].valid) continue;
            const HtFiberResult& r = res[i];
            json o;
            if (!sample) {
                o["value"] = arr3(r.value[0], r.value[1], r.value[2]);
                o["pdf"] = r.pdf;
                o["lobes"] = {{"R", arr3(r.lobes[0][0], r.lobes[0][1], r.lobes[0][2])},
                              {"TT", arr3(r.lobes[1][0], r.lobes[1][1], r.lobes[1][2])},
                              {"TRT", arr3(r.lobes[2][0], r.lobes[2][1], r.lobes[2][2])},
                              {"residual", arr3(r.lobes[3][0], r.lobes[3][1], r.lobes[3][2])}};
            } else {
                o["wi"] = arr3(r.wi[0], r.wi[1], r.wi[2]);
                o["weight"] = arr3(r.value[0], r.value[1], r.value[2]);
                o["pdf"] = r.pdf;
            }
            lines[i] = o.dump();
        }
    }
    int rc = 0;
    for (size_t i = 0; i < qs.size(); ++i) {
        if (!qs[i].valid) {
            out << json{{"error", qs[i].error}}.dump() << '\n';
            rc = 2;
        } else {
            out << lines[i] << '\n';
        }
    }
    return rc;
}

// ---------------------------------------------------------------- furnace
// The material parameters furnace takes, one row each: option, help, field.
struct ScalarParameter {
    const char* option;
    const char* help;
    float HairMaterialDesc::*field;
};
using Desc = HairMaterialDesc;
const ScalarParameter kScalarParameters[] = {
    {"--eta", "index of refraction", &Desc::eta},
    {"--beta-m", "chiang: longitudinal roughness", &Desc::beta_m}, {"--beta-n", "chiang: azimuthal roughness", &Desc::beta_n},
    {"--alpha-deg", "chiang: cuticle tilt in degrees", &Desc::alpha_deg},
    {"--alpha-r-deg", "marschner/zinke: R lobe shift in degrees", &Desc::alpha_r_deg},
    {"--beta-r-deg", "marschner/zinke: R lobe width in degrees", &Desc::beta_r_deg},
    {"--caustic-wc-deg", "marschner/zinke: caustic width in degrees", &Desc::caustic_wc_deg}, {"--caustic-kg", "marschner/zinke: glint scale", &Desc::caustic_kg},
    {"--caustic-deta", "marschner/zinke: caustic fade range of eta", &Desc::caustic_deta}, {"--caustic-dhm", "marschner/zinke: caustic merge range of h", &Desc::caustic_dhm},
    {"--eccentricity", "marschner/zinke: cross-section eccentricity", &Desc::eccentricity},
    {"--ks-exponent", "kajiya: specular exponent", &Desc::ks_exponent},
};

void declare_furnace(ArgParser& p) {
    p.option("--model", "kajiya|marschner|zinke|chiang", "the fibre model (required)");
    p.group("material");
    for (const ScalarParameter& s : kScalarParameters) p.option(s.option, "X", s.help);
    p.option("--sigma-a", "S|R,G,B", "absorption per unit radius")
        .option("--eumelanin", "C", "eumelanin concentration (with --pheomelanin: absorption from melanin)")
        .option("--pheomelanin", "C", "pheomelanin concentration")
        .option("--color", "R,G,B", "absorption from a target colour")
        .option("--kd", "R,G,B", "kajiya: diffuse colour")
        .option("--ks", "R,G,B", "kajiya: specular colour");
    p.group("measurement")
        .option("--theta-deg", "T1,T2,..", "incidence angles in degrees, each in [-90, 90]", "0,15,30,45,60,75,85")
        .option("--nh", "N", "Gauss-Legendre points over the offset h, in [1, 64]", "8")
        .flag("--json", "one JSON object instead of a table");
}

int run_furnace(const ArgParser& p, std::ostream& out) {
    HairMaterialDesc d;
    d.name = "furnace";
    const bool as_json = p.has("--json");
    const bool has_model = p.has("--model");
    if (has_model) d.model = p.get("--model");
    for (const ScalarParameter& s : kScalarParameters)
        if (p.has(s.option)) d.*s.field = float(p.get_double(s.option, -1e30, 1e30));
    if (p.has("--sigma-a")) { d.sigma_a = parse_rgb("--sigma-a", p.get("--sigma-a")); d.has_sigma_a = true; }
    if (p.has("--eumelanin")) { d.eumelanin = float(p.get_double("--eumelanin", -1e30, 1e30)); d.has_melanin = true; }
    if (p.has("--pheomelanin")) { d.pheomelanin = float(p.get_double("--pheomelanin", -1e30, 1e30)); d.has_melanin = true; }
    if (p.has("--color")) { d.color = parse_rgb("--color", p.get("--color")); d.has_color = true; }
    if (p.has("--kd")) d.kd = parse_rgb("--kd", p.get("--kd"));
    if (p.has("--ks")) d.ks = parse_rgb("--ks", p.get("--ks"));
    const std::vector<double> thetas = parse_list("--theta-deg", p.get("--theta-deg"));
    const int nh = p.get_int("--nh", 1, 64);
    if (!has_model) throw UsageError("fiber furnace: needs --model");
    for (double t : thetas)
        if (!(t >= -90 && t <= 90)) throw UsageError("fiber furnace: --theta-deg values must lie in [-90, 90]");
    if (!d.has_sigma_a && !d.has_melanin && !d.has_color) { d.has_sigma_a = true; d.sigma_a = {0, 0, 0}; }
    HtMaterial m;
    try {
        m = make_kernel_material(d);
    } catch (const SceneError& e) {
        throw UsageError(std::string("fiber furnace: ") + e.what());
    }
    json rows = json::array();
    if (!as_json) out << "# " << d.model << ": directional albedo = int value dwi, averaged over h (" << nh
                      << "-point Gauss-Legendre)\n# theta_o_deg      R          G          B\n";
    for (double t : thetas) {
        double a[3];
        for (int c = 0; c < 3; ++c) a[c] = furnace_albedo(m, t, nh, c);
        if (as_json) rows.push_back({{"theta_deg", t}, {"albedo", arr3(a[0], a[1], a[2])}});
        else {
            char buf[128];
            std::snprintf(buf, sizeof buf, "%12.2f %10.6f %10.6f %10.6f\n", t, a[0], a[1], a[2]);
            out << buf;
        }
    }
    if (as_json) out << json{{"model", d.model}, {"nh", nh}, {"rows", rows}}.dump() << '\n';
    return 0;
}

// ---------------------------------------------------------------- afs
void declare_afs(ArgParser& p) {
    p.option("--eta", "E", "index of refraction, in [1.0001, 3] (required)")
        .option("--sigma-a", "S", "absorption per unit radius, in [0, 100] (required)")
        .option("--theta-deg", "T", "incidence angle in degrees, in [0, 90]: print the values there")
        .flag("--json", "print one JSON object")
        .path("--csv", "FILE", "write the curves over theta to a CSV file", PathKind::Csv)
        .path("--png", "FILE", "plot the curves over theta (the paper's Fig. 4)", PathKind::Image);
}

int run_afs(const ArgParser& p, std::ostream& out) {
    if (!p.has("--eta") || !p.has("--sigma-a")) throw UsageError("fiber afs: needs --eta and --sigma-a");
    const double eta = p.get_double("--eta", 1.0001, 3.0), sa = p.get_double("--sigma-a", 0, 100);
    const double th = p.has("--theta-deg") ? p.get_double("--theta-deg", 0, 90) : NAN;
    const bool as_json = p.has("--json");
    const std::string csv = p.get("--csv"), png = p.get("--png");
    if (std::isnan(th) && csv.empty() && png.empty()) throw UsageError("fiber afs: needs --theta-deg (or --csv / --png)");
    if (!csv.empty() || !png.empty()) {
        auto rows = afs_curves(eta, sa, 89.0, 1.0);
        if (!csv.empty()) write_afs_csv(csv, rows);
        if (!png.empty()) write_afs_png(png, rows, eta, sa);
    }
    if (!std::isnan(th)) {
        AfsValues v = afs_reference(eta, sa, th * HT_PI / 180.0);
        if (as_json) {
            out << std::setprecision(10)
                << json{{"R", v.R}, {"TT", v.TT}, {"TRT", v.TRT}, {"TRT_glint", v.TRT_glint}, {"density", v.density}}.dump()
                << '\n';
        } else {
            char buf[256];
            std::snprintf(buf, sizeof buf, "R %.6f\nTT %.6f\nTRT %.6f\nTRT_glint %.6f\ndensity %.6f\n", v.R, v.TT, v.TRT,
                          v.TRT_glint, v.density);
            out << buf;
        }
    }
    return 0;
}

}  // namespace

namespace {

struct Subcommand {
    const char* name;
    const char* summary;
    void (*declare)(ArgParser&);
    int (*run)(const ArgParser&, std::istream& in, std::ostream& out);
};

void declare_queries(ArgParser& p) {
    p.option("--precision", "double|float", "double: the kernels' lines in double precision on the host; float: the OpenCL kernel on a device", "double")
        .option("--device", "I", "OpenCL device index for --precision float (default: first CPU/GPU)");
}

const Subcommand kSubcommands[] = {
    {"eval", "Evaluates the BCSDF for every JSON query line on stdin ({\"model\", \"wo\", \"wi\", \"h\", material keys}):\none JSON line out per query with value, pdf and the R/TT/TRT/residual lobes.",
     declare_queries, [](const ArgParser& p, std::istream& in, std::ostream& out) { return run_queries(p, false, in, out); }},
    {"sample", "Samples the BCSDF for every JSON query line on stdin (as eval, with \"u\":[u0,u1,u2,u3] instead of wi):\none JSON line out per query with wi, weight and pdf.",
     declare_queries, [](const ArgParser& p, std::istream& in, std::ostream& out) { return run_queries(p, true, in, out); }},
    {"furnace", "Directional albedo (the integral of the BCSDF over all outgoing directions, averaged over h) of a material\nat several incidence angles: 1 for a lossless fibre (white furnace test).",
     declare_furnace, [](const ArgParser& p, std::istream&, std::ostream& out) { return run_furnace(p, out); }},
    {"afs", "The paper's averaged forward scattering AFS^avg (R, TT, TRT, TRT with glints, ray density) of a fibre\nwith index eta and absorption sigma_a, at one angle or as curves (Zinke 2004 Fig. 4).",
     declare_afs, [](const ArgParser& p, std::istream&, std::ostream& out) { return run_afs(p, out); }},
};

int run_subcommand(const std::vector<std::string>& args, std::istream& in, std::ostream& out) {
    const std::string& name = args[0];
    std::vector<std::string> names;
    for (const Subcommand& sub : kSubcommands) {
        names.push_back(sub.name);
        if (name != sub.name) continue;
        ArgParser p(std::string("fiber ") + sub.name, sub.summary);
        sub.declare(p);
        p.parse(std::vector<std::string>(args.begin() + 1, args.end()));
        if (p.wants_help()) {
            out << p.help();
            return 0;
        }
        return sub.run(p, in, out);
    }
    throw UsageError("fiber: unknown subcommand '" + name + "'" + did_you_mean(name, names) +
                     "; hairtrace fiber --help lists them");
}

}  // namespace

int fiber_main(const std::vector<std::string>& args_in, std::istream& in, std::ostream& out, std::ostream& err) {
    std::vector<std::string> args = args_in;
    if (!args.empty() && args[0] == "fiber") args.erase(args.begin());
    try {
        if (args.empty()) throw UsageError("fiber: missing subcommand (eval, sample, furnace or afs)");
        if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
            out << kOverview;
            return 0;
        }
        return run_subcommand(args, in, out);
    } catch (const UsageError& e) {
        err << "hairtrace " << e.what() << '\n';
        return 2;
    } catch (const DeviceError& e) {
        err << "hairtrace fiber: " << e.what() << '\n';
        return 3;
    } catch (const std::exception& e) {
        err << "hairtrace fiber: " << e.what() << '\n';
        return 2;
    }
}

int fiber_main(const std::vector<std::string>& args) { return fiber_main(args, std::cin, std::cout, std::cerr); }

}  // namespace ht
