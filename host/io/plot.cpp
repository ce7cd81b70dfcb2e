#include "io/plot.h"

#include "io/image_io.h"

#include "core/image_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace ht {

namespace {
const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

struct Canvas {
    int w, h;
    std::vector<float> rgb;
    Canvas(int w_, int h_) : w(w_), h(h_), rgb(size_t(w_) * h_ * 3, 1.0f) {}
    void blend(int x, int y, const std::array<float, 3>& c, float a) {
        if (x < 0 || y < 0 || x >= w || y >= h || !(a > 0)) return;
        float* p = &rgb[3 * (size_t(y) * w + x)];
        for (int i = 0; i < 3; ++i) p[i] = p[i] * (1 - a) + c[i] * a;
    }
    // anti-aliased line of the given width: distance-to-segment coverage
    void line(double x0, double y0, double x1, double y1, const std::array<float, 3>& c, double width) {
        int xa = int(std::floor(std::min(x0, x1) - width - 1)), xb = int(std::ceil(std::max(x0, x1) + width + 1));
        int ya = int(std::floor(std::min(y0, y1) - width - 1)), yb = int(std::ceil(std::max(y0, y1) + width + 1));
        double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
        for (int y = std::max(ya, 0); y <= std::min(yb, h - 1); ++y)
            for (int x = std::max(xa, 0); x <= std::min(xb, w - 1); ++x) {
                double t = len2 > 0 ? std::clamp(((x - x0) * dx + (y - y0) * dy) / len2, 0.0, 1.0) : 0.0;
                double ex = x - (x0 + t * dx), ey = y - (y0 + t * dy);
                double d = std::sqrt(ex * ex + ey * ey);
                blend(x, y, c, float(std::clamp(width / 2 + 0.5 - d, 0.0, 1.0)));
            }
    }
    void disc(double cx, double cy, double r, const std::array<float, 3>& c) {
        for (int y = int(cy - r - 1); y <= int(cy + r + 1); ++y)
            for (int x = int(cx - r - 1); x <= int(cx + r + 1); ++x) {
                double d = std::hypot(x - cx, y - cy);
                blend(x, y, c, float(std::clamp(r + 0.5 - d, 0.0, 1.0)));
            }
    }
};

struct Axis {
    double lo, hi;
    bool log;
    double map(double v) const {
        if (log) return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
        return (v - lo) / (hi - lo);
    }
    std::vector<double> ticks() const {
        std::vector<double> t;
        if (log) {
            for (double e = std::floor(std::log10(lo)); e <= std::ceil(std::log10(hi)); e += 1) {
                double v = std::pow(10.0, e);
                if (v >= lo * 0.999 && v <= hi * 1.001) t.push_back(v);
            }
            if (t.size() < 2) t = {lo, hi};
            return t;
        }
        double span = hi - lo, step = std::pow(10.0, std::floor(std::log10(span / 5)));
        if (span / step > 10) step *= 2;
        if (span / step > 10) step *= 2.5;
        for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step)
            t.push_back(std::fabs(v) < 1e-9 * span ? 0.0 : v);  // no "-0" from accumulated rounding
        return t;
    }
};

Axis make_axis(const std::vector<PlotSeries>& s, bool use_x, bool log) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (auto& ser : s)
        for (double v : use_x ? ser.x : ser.y)
            if (std::isfinite(v) && (!log || v > 0)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!std::isfinite(lo)) lo = log ? 1 : 0, hi = log ? 10 : 1;
    if (log) {
        lo = std::pow(10.0, std::floor(std::log10(lo) * 4) / 4);
        hi = std::pow(10.0, std::ceil(std::log10(hi) * 4) / 4);
        if (hi <= lo) hi = lo * 10;
    } else {
        double pad = (hi - lo) * 0.05;
        if (pad == 0) pad = std::max(std::fabs(hi) * 0.1, 1e-3);
        lo -= pad, hi += pad;
    }
    return {lo, hi, log};
}

std::string tick_label(double v) {
    char b[32];
    if (v != 0 && (std::fabs(v) < 1e-2 || std::fabs(v) >= 1e4)) std::snprintf(b, sizeof b, "%.0e", v);
    else std::snprintf(b, sizeof b, "%g", v);
    return b;
}
}  // namespace

std::array<float, 3> plot_color(size_t i) {
    static const std::array<float, 3> k[] = {{0.12f, 0.47f, 0.71f}, {1.0f, 0.50f, 0.05f}, {0.17f, 0.63f, 0.17f},
                                             {0.84f, 0.15f, 0.16f}, {0.58f, 0.40f, 0.74f}, {0.55f, 0.34f, 0.29f},
                                             {0.89f, 0.47f, 0.76f}, {0.50f, 0.50f, 0.50f}, {0.74f, 0.74f, 0.13f},
                                             {0.09f, 0.75f, 0.81f}};
    return k[i % 10];
}

void write_plot_png(const std::string& path, const PlotSpec& spec) {
    const int W = spec.width, H = spec.height;
    size_t longest = 0;
    for (auto& ser : spec.series) longest = std::max(longest, ser.label.size());
    const int left = 90, right = std::max(220, 60 + 8 * int(longest)), top = 50, bottom = 70;
    Canvas c(W, H);
    Axis ax = make_axis(spec.series, true, spec.log_x), ay = make_axis(spec.series, false, spec.log_y);
    auto px = [&](double x) { return left + ax.map(x) * (W - left - right); };
    auto py = [&](double y) { return H - bottom - ay.map(y) * (H - top - bottom); };
    const std::array<float, 3> black{0, 0, 0}, grid{0.88f, 0.88f, 0.88f};
    std::vector<ImageTextLabel> labels;
    for (double t : ax.ticks()) {
        double x = px(t);
        c.line(x, top, x, H - bottom, grid, 1);
        c.line(x, H - bottom, x, H - bottom + 6, black, 1);
        labels.push_back({int(x) - 14, H - bottom + 22, tick_label(t), 14});
    }
    for (double t : ay.ticks()) {
        double y = py(t);
        c.line(left, y, W - right, y, grid, 1);
        c.line(left - 6, y, left, y, black, 1);
        labels.push_back({8, int(y) + 5, tick_label(t), 14});
    }
    c.line(left, top, left, H - bottom, black, 1.5);
    c.line(left, H - bottom, W - right, H - bottom, black, 1.5);
    for (size_t i = 0; i < spec.series.size(); ++i) {
        const PlotSeries& s = spec.series[i];
        bool have_prev = false;
        double x0 = 0, y0 = 0;
        for (size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
            bool ok = std::isfinite(s.x[k]) && std::isfinite(s.y[k]) && (!spec.log_x || s.x[k] > 0) &&
                      (!spec.log_y || s.y[k] > 0);
            if (!ok) { have_prev = false; continue; }
            double x = px(s.x[k]), y = py(s.y[k]);
            if (have_prev) c.line(x0, y0, x, y, s.color, 2.0);
            if (s.markers) c.disc(x, y, 3.0, s.color);
            x0 = x, y0 = y, have_prev = true;
        }
        int ly = top + 10 + int(i) * 22;
        c.line(W - right + 15, ly, W - right + 45, ly, s.color, 3);
        labels.push_back({W - right + 52, ly + 5, s.label, 13});
    }
    labels.push_back({left, 32, spec.title, 18});
    labels.push_back({left + (W - left - right) / 2 - 40, H - 20, spec.xlabel, 15});
    labels.push_back({8, top - 16, spec.ylabel, 15});

    std::vector<float> out = c.rgb;
    if (std::filesystem::exists(kFont)) image_files::render_text(out, W, H, labels, kFont);
    // reuse the image writer (8-bit sRGB, atomic rename) through a film of means
    Film film;
    film.width = W;
    film.height = H;
    film.rgba.resize(size_t(W) * H * 4);
    for (size_t i = 0; i < size_t(W) * H; ++i) {
        for (int k = 0; k < 3; ++k) {
            // the writer applies the sRGB curve: invert it so plot colours come out as chosen
            float v = std::clamp(out[3 * i + k], 0.0f, 1.0f);
            film.rgba[4 * i + k] = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
        }
        film.rgba[4 * i + 3] = 1.0f;
    }
    write_image(path, film, ImageMetadata{});
}

}  // namespace ht
