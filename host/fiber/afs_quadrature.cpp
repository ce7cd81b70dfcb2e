#include "fiber/afs_quadrature.h"

#include "io/plot.h"

#include <array>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "kernels/fiber/afs.h"

namespace ht {

namespace {

// Gauss-Kronrod 7/15 nodes and weights on [-1, 1].
const double kXgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                        0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                        0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                        0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
const double kWgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                        0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                        0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                        0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
const double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                       0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

void gk15(const std::function<double(double)>& f, double a, double b, double& res, double& err) {
    double c = 0.5 * (a + b), r = 0.5 * (b - a);
    double fc = f(c);
    double k = fc * kWgk[7], g = fc * kWg[3];
    for (int j = 0; j < 7; ++j) {
        double x = r * kXgk[j];
        double f1 = f(c - x), f2 = f(c + x);
        k += kWgk[j] * (f1 + f2);
        if (j % 2 == 1) g += kWg[j / 2] * (f1 + f2);
    }
    res = k * r;
    err = std::fabs((k - g) * r);
}

double adaptive(const std::function<double(double)>& f, double a, double b, double tol, int depth) {
    double res, err;
    gk15(f, a, b, res, err);
    if (err <= tol || depth > 40 || b - a < 1e-14) return res;
    double m = 0.5 * (a + b);
    return adaptive(f, a, m, 0.5 * tol, depth + 1) + adaptive(f, m, b, 0.5 * tol, depth + 1);
}

double afs_one(const HtAfsParams& a, int p) {
    auto f = [&](double u) {
        double h = std::min(1.0, std::max(0.0, std::sin(u)));
        return ht_afs_integrand(&a, p, h) * std::cos(u);
    };
    double uc = ht_afs_split(&a);
    double s = adaptive(f, 0.0, uc, 1e-13, 0);
    if (uc < HT_HALF_PI) s += adaptive(f, uc, HT_HALF_PI, 1e-13, 0);
    return s;
}

}  // namespace

AfsValues afs_reference(double eta, double sigma_a, double theta) {
    HtAfsParams a;
    ht_afs_params(&a, eta, sigma_a, theta);
    AfsValues v;
    v.R = afs_one(a, 0);
    v.TT = afs_one(a, 1);
    v.TRT = afs_one(a, 2);
    v.TRT_glint = v.TRT + afs_one(a, 3);
    v.density = adaptive([](double u) { return 0.5 * std::cos(u) * std::cos(u); }, 0.0, HT_HALF_PI, 1e-14, 0);
    return v;
}

std::vector<float> afs_tt_table(double eta, const float sigma_a[3]) {
    std::vector<float> t;
    t.reserve(4 * (HT_AFS_TT_TABLE_N + 1));
    const real3 s = make_real3(sigma_a[0], sigma_a[1], sigma_a[2]);
    for (int i = 0; i <= HT_AFS_TT_TABLE_N; ++i) {
        const real3 v = ht_afs_tt3(eta, s, HT_HALF_PI * i / HT_AFS_TT_TABLE_N);
        t.insert(t.end(), {float(v.x), float(v.y), float(v.z), 0.0f});
    }
    return t;
}

std::vector<AfsRow> afs_curves(double eta, double sigma_a, double theta_max_deg, double step_deg) {
    std::vector<AfsRow> rows;
    for (double t = 0; t <= theta_max_deg + 1e-9; t += step_deg)
        rows.push_back({t, afs_reference(eta, sigma_a, t * HT_PI / 180.0)});
    return rows;
}

void write_afs_csv(const std::string& path, const std::vector<AfsRow>& rows) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error("cannot write " + path);
    f << "theta_deg,R,TT,TRT,TRT_glint,density\n";
    f.precision(10);
    for (auto& r : rows)
        f << r.theta_deg << ',' << r.v.R << ',' << r.v.TT << ',' << r.v.TRT << ',' << r.v.TRT_glint << ','
          << r.v.density << '\n';
    if (!f) throw std::runtime_error("error writing " + path);
}

void write_afs_png(const std::string& path, const std::vector<AfsRow>& rows, double eta, double sigma_a) {
    // Fig. 4's colours: R red, TT green, TRT blue (removal only), TRT with glints light blue,
    // the averaged ray density factor magenta.
    const char* names[5] = {"R", "TT", "TRT (caustic removed)", "TRT + glint", "ray density pi/8"};
    const std::array<float, 3> colors[5] = {{0.85f, 0.1f, 0.1f}, {0.1f, 0.6f, 0.1f}, {0.1f, 0.1f, 0.9f},
                                            {0.4f, 0.7f, 1.0f}, {0.8f, 0.1f, 0.8f}};
    PlotSpec plot;
    char title[128];
    std::snprintf(title, sizeof title, "AFS^avg (Zinke 2004 Fig. 4), eta = %.3g, sigma_a = %.3g per radius", eta, sigma_a);
    plot.title = title;
    plot.xlabel = "theta (degrees)";
    plot.ylabel = "AFS^avg";
    for (int k = 0; k < 5; ++k) {
        PlotSeries s;
        s.label = names[k];
        s.color = colors[k];
        s.markers = false;
        for (const AfsRow& r : rows) {
            const double v[5] = {r.v.R, r.v.TT, r.v.TRT, r.v.TRT_glint, r.v.density};
            s.x.push_back(r.theta_deg);
            s.y.push_back(v[k]);
        }
        plot.series.push_back(s);
    }
    write_plot_png(path, plot);
}

}  // namespace ht
