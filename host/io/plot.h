// Line plots to PNG (convergence curves, the paper's Fig. 4): axes with ticks, linear or log
// scales, a legend.  Text uses DejaVu Sans when installed (fonts-dejavu-core) and is left out
// otherwise; the curves never depend on it.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace ht {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;
    std::array<float, 3> color{0.1f, 0.3f, 0.8f};
    bool markers = true;
};

struct PlotSpec {
    std::string title, xlabel, ylabel;
    bool log_x = false, log_y = false;
    int width = 960, height = 640;
    std::vector<PlotSeries> series;
};

// A distinct colour for series i.
std::array<float, 3> plot_color(size_t i);

// Throws ImageError naming the file when it cannot be written.
void write_plot_png(const std::string& path, const PlotSpec& spec);

}  // namespace ht
