#include "fiber/furnace.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/fiber/bcsdf.h"

namespace ht {

void gauss_legendre(int n, double* x, double* w) {
    for (int i = 0; i < n; ++i) {
        double z = std::cos(HT_PI * (i + 0.75) / (n + 0.5)), pp = 1;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1, p2 = 0;
            for (int j = 1; j <= n; ++j) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1);
            double z1 = z;
            z = z1 - p1 / pp;
            if (std::fabs(z - z1) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * pp * pp);
    }
}

namespace {
void feature_widths(const HtMaterial& m, double& wth, double& wph) {
    switch (m.model) {
    case HT_MODEL_CHIANG: wth = std::sqrt((double)m.v[1]); wph = 2.0 * m.s; break;
    case HT_MODEL_MARSCHNER: wth = 2.0 * m.beta_tt; wph = std::min(0.05, (double)m.caustic_wc); break;
    case HT_MODEL_ZINKE: wth = 2.0 * m.beta_tt; wph = std::min((double)m.azim_sigma, (double)m.caustic_wc); break;
    default: wth = 1.0 / std::sqrt((double)m.ks_exponent); wph = 1.0; break;
    }
    wth = std::max(wth, 1e-3);
    wph = std::max(wph, 1e-3);
}
}  // namespace

double furnace_albedo_at(const HtMaterial& m, double x, double y, double z, double h, int c, double refine) {
    double wth, wph;
    feature_widths(m, wth, wph);
    int panels = std::min(4000, std::max(16, (int)std::ceil(HT_PI / (wth * 0.5) * refine)));
    int nph = std::min(20000, std::max(64, (int)std::ceil(2 * HT_PI / (wph * 0.25) * refine)));
    double gx[4], gw[4];
    gauss_legendre(4, gx, gw);
    real3 wo = make_real3(x, y, z);
    double sum = 0, dth = HT_PI / panels, dph = 2 * HT_PI / nph;
    std::vector<double> cph(nph), sph(nph);
    for (int j = 0; j < nph; ++j) {
        cph[j] = std::cos(-HT_PI + dph * (j + 0.5));
        sph[j] = std::sin(-HT_PI + dph * (j + 0.5));
    }
    for (int i = 0; i < panels; ++i)
        for (int g = 0; g < 4; ++g) {
            double th = -HT_PI / 2 + dth * (i + 0.5 + 0.5 * gx[g]);
            double st = std::sin(th), ct = std::cos(th);
            double row = 0;
            for (int j = 0; j < nph; ++j) {
                real3 v;
                real pdf;
                ht_bcsdf_eval(&m, wo, make_real3(st, ct * cph[j], ct * sph[j]), h, &v, &pdf);
                row += c == 0 ? v.x : (c == 1 ? v.y : v.z);
            }
            sum += 0.5 * dth * gw[g] * ct * row * dph;
        }
    return sum;
}

double furnace_albedo(const HtMaterial& m, double theta_o_deg, int nh, int c) {
    std::vector<double> x(nh), w(nh);
    gauss_legendre(nh, x.data(), w.data());
    double t = theta_o_deg * HT_PI / 180.0, s = 0;
    for (int i = 0; i < nh; ++i) s += 0.5 * w[i] * furnace_albedo_at(m, std::sin(t), 0.0, std::cos(t), x[i], c);
    return s;
}

}  // namespace ht
