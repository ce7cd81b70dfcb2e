#include "fiber/fiber_cli.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cl/device.h"
#include "core/errors.h"
#include "fiber/afs_quadrature.h"
#include "fiber/furnace.h"
#include "fiber/material.h"
#include "fiber/query_json.h"
#include "kernels/fiber/bcsdf.h"
#include "kernels/fiber/query.h"

namespace ht {

namespace {

using nlohmann::json;

const char* kUsage =
    "usage: hairtrace fiber eval   [--precision double|float] [--device N]   < JSON lines\n"
    "       hairtrace fiber sample [--precision double|float] [--device N]   < JSON lines (+ \"u\":[u0,u1,u2,u3])\n"
    "       hairtrace fiber furnace --model M [--eta E] [--beta-m B] [--beta-n B] [--alpha-deg A]\n"
    "                 [--sigma-a S|r,g,b | --eumelanin C --pheomelanin C | --color r,g,b]\n"
    "                 [--alpha-r-deg A] [--beta-r-deg B] [--caustic-wc-deg W] [--caustic-kg K]\n"
    "                 [--caustic-deta D] [--caustic-dhm H] [--eccentricity E] [--kd r,g,b] [--ks r,g,b]\n"
    "                 [--ks-exponent P] [--theta-deg t1,t2,..] [--nh N] [--json]\n"
    "       hairtrace fiber afs --eta E --sigma-a S --theta-deg T [--json] [--csv FILE] [--png FILE]\n";

double parse_number(const std::string& opt, const std::string& s) {
    try {
        size_t n = 0;
        double v = std::stod(s, &n);
        if (n != s.size() || !std::isfinite(v)) throw std::invalid_argument("x");
        return v;
    } catch (...) {
        throw UsageError(opt + ": '" + s + "' is not a number");
    }
}
std::vector<double> parse_list(const std::string& opt, const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(parse_number(opt, item));
    if (v.empty()) throw UsageError(opt + ": empty list");
    return v;
}
Vec3f vec3_opt(const std::string& opt, const std::string& s) {
    auto v = parse_list(opt, s);
    if (v.size() == 1) return {(float)v[0], (float)v[0], (float)v[0]};
    if (v.size() != 3) throw UsageError(opt + ": expected 1 or 3 comma-separated numbers");
    return {(float)v[0], (float)v[1], (float)v[2]};
}

json arr3(double a, double b, double c) { return json::array({a, b, c}); }
json arr3(real3 v) { return arr3(v.x, v.y, v.z); }

// The double-precision path uses the query's exact inputs; the float path their float copies.
int run_queries(const std::vector<std::string>& args, bool sample, std::istream& in, std::ostream& out,
                std::ostream& err) {
    std::string precision = "double";
    int device = -1;
    for (size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--precision" && i + 1 < args.size()) precision = args[++i];
        else if (args[i] == "--device" && i + 1 < args.size()) device = (int)parse_number("--device", args[++i]);
        else throw UsageError("unknown option '" + args[i] + "'");
    }
    if (precision != "double" && precision != "float")
        throw UsageError("--precision must be double or float");
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
                cl::Kernel k(prog, sample ? "fiber_sample" : "fiber_eval");
                cl::Buffer bm(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, mats.size() * sizeof(HtMaterial), mats.data());
                cl::Buffer bq(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, qv.size() * sizeof(HtFiberQuery), qv.data());
                cl::Buffer bo(ctx.context(), CL_MEM_WRITE_ONLY, qv.size() * sizeof(HtFiberResult));
                cl_uint n = (cl_uint)qv.size();
                k.setArg(0, bm); k.setArg(1, bq); k.setArg(2, bo); k.setArg(3, n);
                ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
                std::vector<HtFiberResult> out_r(n);
                ctx.queue().enqueueReadBuffer(bo, CL_TRUE, 0, n * sizeof(HtFiberResult), out_r.data());
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
int run_furnace(const std::vector<std::string>& args, std::ostream& out) {
    HairMaterialDesc d;
    d.name = "furnace";
    bool has_model = false, as_json = false;
    std::vector<double> thetas = {0, 15, 30, 45, 60, 75, 85};
    int nh = 8;
    auto need = [&](size_t& i) -> const std::string& {
        if (i + 1 >= args.size()) throw UsageError(args[i] + " needs a value");
        return args[++i];
    };
    for (size_t i = 1; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--model") { d.model = need(i); has_model = true; }
        else if (a == "--json") as_json = true;
        else if (a == "--eta") d.eta = (float)parse_number(a, need(i));
        else if (a == "--beta-m") d.beta_m = (float)parse_number(a, need(i));
        else if (a == "--beta-n") d.beta_n = (float)parse_number(a, need(i));
        else if (a == "--alpha-deg") d.alpha_deg = (float)parse_number(a, need(i));
        else if (a == "--sigma-a") { d.sigma_a = vec3_opt(a, need(i)); d.has_sigma_a = true; }
        else if (a == "--eumelanin") { d.eumelanin = (float)parse_number(a, need(i)); d.has_melanin = true; }
        else if (a == "--pheomelanin") { d.pheomelanin = (float)parse_number(a, need(i)); d.has_melanin = true; }
        else if (a == "--color") { d.color = vec3_opt(a, need(i)); d.has_color = true; }
        else if (a == "--alpha-r-deg") d.alpha_r_deg = (float)parse_number(a, need(i));
        else if (a == "--beta-r-deg") d.beta_r_deg = (float)parse_number(a, need(i));
        else if (a == "--caustic-wc-deg") d.caustic_wc_deg = (float)parse_number(a, need(i));
        else if (a == "--caustic-kg") d.caustic_kg = (float)parse_number(a, need(i));
        else if (a == "--caustic-deta") d.caustic_deta = (float)parse_number(a, need(i));
        else if (a == "--caustic-dhm") d.caustic_dhm = (float)parse_number(a, need(i));
        else if (a == "--eccentricity") d.eccentricity = (float)parse_number(a, need(i));
        else if (a == "--kd") d.kd = vec3_opt(a, need(i));
        else if (a == "--ks") d.ks = vec3_opt(a, need(i));
        else if (a == "--ks-exponent") d.ks_exponent = (float)parse_number(a, need(i));
        else if (a == "--theta-deg") thetas = parse_list(a, need(i));
        else if (a == "--nh") nh = (int)parse_number(a, need(i));
        else throw UsageError("unknown option '" + a + "'");
    }
    if (!has_model) throw UsageError("furnace needs --model");
    if (nh < 1 || nh > 64) throw UsageError("--nh must be in [1, 64]");
    for (double t : thetas)
        if (!(t >= -90 && t <= 90)) throw UsageError("--theta-deg values must lie in [-90, 90]");
    if (!d.has_sigma_a && !d.has_melanin && !d.has_color) { d.has_sigma_a = true; d.sigma_a = {0, 0, 0}; }
    HtMaterial m;
    try {
        m = make_kernel_material(d);
    } catch (const SceneError& e) {
        throw UsageError(e.what());
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
int run_afs(const std::vector<std::string>& args, std::ostream& out) {
    double eta = NAN, sa = NAN, th = NAN;
    bool as_json = false;
    std::string csv, png;
    for (size_t i = 1; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto val = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
            return args[++i];
        };
        if (a == "--eta") eta = parse_number(a, val());
        else if (a == "--sigma-a") sa = parse_number(a, val());
        else if (a == "--theta-deg") th = parse_number(a, val());
        else if (a == "--json") as_json = true;
        else if (a == "--csv") csv = val();
        else if (a == "--png") png = val();
        else throw UsageError("unknown option '" + a + "'");
    }
    if (std::isnan(eta) || std::isnan(sa)) throw UsageError("afs needs --eta and --sigma-a");
    if (!(eta >= 1.0001 && eta <= 3.0)) throw UsageError("--eta must lie in [1.0001, 3]");
    if (!(sa >= 0 && sa <= 100)) throw UsageError("--sigma-a must lie in [0, 100]");
    if (std::isnan(th) && csv.empty() && png.empty()) throw UsageError("afs needs --theta-deg (or --csv / --png)");
    if (!std::isnan(th) && !(th >= 0 && th <= 90)) throw UsageError("--theta-deg must lie in [0, 90]");
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

int fiber_main(const std::vector<std::string>& args_in, std::istream& in, std::ostream& out, std::ostream& err) {
    std::vector<std::string> args = args_in;
    if (!args.empty() && args[0] == "fiber") args.erase(args.begin());
    try {
        if (args.empty()) throw UsageError("missing subcommand");
        const std::string& cmd = args[0];
        if (cmd == "eval") return run_queries(args, false, in, out, err);
        if (cmd == "sample") return run_queries(args, true, in, out, err);
        if (cmd == "furnace") return run_furnace(args, out);
        if (cmd == "afs") return run_afs(args, out);
        if (cmd == "--help" || cmd == "-h" || cmd == "help") { out << kUsage; return 0; }
        throw UsageError("unknown subcommand '" + cmd + "'");
    } catch (const UsageError& e) {
        err << "hairtrace fiber: " << e.what() << '\n' << kUsage;
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
