#include "fiber/afs_quadrature.h"

#if __has_include(<OpenImageIO/imageoutput.h>)
#include <OpenImageIO/imageoutput.h>
#else
#include <OpenImageIO/imageio.h>  // OIIO 2.x declares ImageOutput here
#endif

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

namespace {
struct Canvas {
    int w, h;
    std::vector<float> px;
    Canvas(int w_, int h_) : w(w_), h(h_), px((size_t)w_ * h_ * 3, 1.0f) {}
    void dot(int x, int y, const float* c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        float* p = &px[((size_t)y * w + x) * 3];
        p[0] = c[0]; p[1] = c[1]; p[2] = c[2];
    }
    void line(double x0, double y0, double x1, double y1, const float* c, int thick = 1) {
        int n = (int)std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0))) + 1;
        for (int i = 0; i <= n; ++i) {
            double t = (double)i / n;
            int x = (int)std::lround(x0 + (x1 - x0) * t), y = (int)std::lround(y0 + (y1 - y0) * t);
            for (int dx = -thick / 2; dx <= thick / 2; ++dx)
                for (int dy = -thick / 2; dy <= thick / 2; ++dy) dot(x + dx, y + dy, c);
        }
    }
};
}  // namespace

void write_afs_png(const std::string& path, const std::vector<AfsRow>& rows, double eta, double sigma_a) {
    const int W = 800, H = 500, L = 60, Rm = 20, T = 20, B = 50;
    Canvas cv(W, H);
    double tmax = rows.empty() ? 90.0 : std::max(1.0, rows.back().theta_deg);
    double ymax = 1.0;  // AFS values lie in [0, 1]
    auto X = [&](double t) { return L + (W - L - Rm) * t / tmax; };
    auto Y = [&](double v) { return H - B - (H - B - T) * std::min(v, ymax) / ymax; };
    const float black[3] = {0, 0, 0}, grey[3] = {0.85f, 0.85f, 0.85f};
    // grid every 10 degrees and 0.1, axes, ticks
    for (double t = 0; t <= tmax + 1e-9; t += 10) {
        cv.line(X(t), Y(0), X(t), Y(ymax), grey);
        cv.line(X(t), Y(0), X(t), Y(0) + 8, black);
    }
    for (double v = 0; v <= ymax + 1e-9; v += 0.1) {
        cv.line(X(0), Y(v), X(tmax), Y(v), grey);
        cv.line(X(0) - 8, Y(v), X(0), Y(v), black);
    }
    cv.line(X(0), Y(0), X(tmax), Y(0), black, 2);
    cv.line(X(0), Y(0), X(0), Y(ymax), black, 2);
    // curves: R red, TT green, TRT blue, TRT with glint light blue, ray density magenta (Fig. 4 colours)
    const float cols[5][3] = {{0.85f, 0.1f, 0.1f}, {0.1f, 0.6f, 0.1f}, {0.1f, 0.1f, 0.9f}, {0.4f, 0.7f, 1.0f}, {0.8f, 0.1f, 0.8f}};
    for (size_t i = 1; i < rows.size(); ++i) {
        const AfsValues &a = rows[i - 1].v, &b = rows[i].v;
        double va[5] = {a.R, a.TT, a.TRT, a.TRT_glint, a.density}, vb[5] = {b.R, b.TT, b.TRT, b.TRT_glint, b.density};
        for (int k : {3, 0, 1, 2, 4})  // TRT over TRT+glint where they coincide
            cv.line(X(rows[i - 1].theta_deg), Y(va[k]), X(rows[i].theta_deg), Y(vb[k]), cols[k], 3);
    }
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error("cannot create an image writer for " + path);
    OIIO::ImageSpec spec(W, H, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("ImageDescription", "AFS^avg (Zinke 2004 Fig. 4): eta=" + std::to_string(eta) +
                                           " sigma_a=" + std::to_string(sigma_a) +
                                           "; x: theta 0..90 deg (ticks 10 deg), y: 0..1 (ticks 0.1); "
                                           "red R, green TT, blue TRT, light blue TRT+glint, magenta density");
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, cv.px.data()) || !out->close())
        throw std::runtime_error("cannot write " + path + ": " + out->geterror());
}

}  // namespace ht
