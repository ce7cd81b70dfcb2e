#include "fiber/dual_scattering.h"

#include <algorithm>
#include <cmath>

#include "kernels/fiber/dual.h"

namespace ht {

namespace {

// A_p(h) and Phi(p, h) of every lobe and channel at the midpoint nodes h_k = sin u_k of [0, pi/2),
// weighted by du cos u: the one sampling every average below is a sum over.
struct Samples {
    int nodes = 0;
    std::vector<double> weight;  // du cos u_k
    std::vector<double> phi;     // [p * nodes + k]
    std::vector<double> a;       // [(p * 3 + c) * nodes + k]
};

Samples sample_lobes(const HtMaterial& m, double theta_i, int nodes) {
    Samples s;
    s.nodes = nodes;
    s.weight.resize(nodes);
    s.phi.resize(HT_DUAL_LOBES * nodes);
    s.a.resize(HT_DUAL_LOBES * 3 * nodes);
    const double st = std::sin(std::fabs(theta_i)), ct = std::cos(theta_i);
    const double du = HT_HALF_PI / nodes;
    for (int k = 0; k < nodes; ++k) {
        const double u = (k + 0.5) * du;
        const double h = std::sin(u);
        s.weight[k] = du * std::cos(u);
        for (int p = 0; p < HT_DUAL_LOBES; ++p)
            for (int c = 0; c < 3; ++c) {
                double phi = 0;
                s.a[(p * 3 + c) * nodes + k] = ht_dual_attenuation(&m, p, st, ct, m.sigma_a[c], h, &phi);
                s.phi[p * nodes + k] = phi;
            }
    }
    // the midpoint rule gives int_0^1 dh = 1 + O(du^2): rescaled to exactly 1, so that a white
    // chiang fibre (whose lobes add up to 1 at every h) gets a_f + a_b = 1 to rounding
    double total = 0;
    for (double w : s.weight) total += w;
    for (double& w : s.weight) w /= total;
    return s;
}

// Share of lobe p's exit at node k that lies within pi/2 of azimuth `centre` (residual: half).
double within_quarter(const Samples& s, int p, int k, double centre) {
    if (p == 3) return 0.5;
    return std::fabs(ht_wrap_pi(s.phi[p * s.nodes + k] - centre)) < HT_HALF_PI ? 1.0 : 0.0;
}

DualValues values_from(const HtMaterial& m, const Samples& s) {
    DualValues v;
    for (int c = 0; c < 3; ++c) {
        double af = 0, ab = 0, alf = 0, alb = 0, bf = 0, bb = 0;
        for (int p = 0; p < HT_DUAL_LOBES; ++p) {
            double alpha = 0, beta2 = 0;
            ht_dual_lobe_shape(&m, p, &alpha, &beta2);
            double back = 0, all = 0;
            for (int k = 0; k < s.nodes; ++k) {
                const double e = s.a[(p * 3 + c) * s.nodes + k] * s.weight[k];
                all += e;
                back += e * within_quarter(s, p, k, 0.0);
            }
            const double fwd = all - back;
            af += fwd;
            ab += back;
            alf += fwd * alpha;
            alb += back * alpha;
            bf += fwd * beta2;
            bb += back * beta2;
        }
        v.a_f[c] = af;
        v.a_b[c] = ab;
        v.alpha_f[c] = af > 0 ? alf / af : 0.0;
        v.alpha_b[c] = ab > 0 ? alb / ab : 0.0;
        v.beta_f2[c] = af > 0 ? bf / af : 0.0;
        v.beta_b2[c] = ab > 0 ? bb / ab : 0.0;
        dual_back_scattering(v, c);
    }
    return v;
}

double ng_from(const Samples& s, int p, int c, double phi) {
    // N^G_p(phi) = 1/(2 pi) int_0^1 A_p(h) ([|Phi - phi| < pi/2] + [|Phi + phi| < pi/2]) dh:
    // lobe p's azimuthal density averaged over incoming azimuths within pi/2 of the light's
    double sum = 0;
    for (int k = 0; k < s.nodes; ++k)
        sum += s.a[(p * 3 + c) * s.nodes + k] * s.weight[k] * (within_quarter(s, p, k, phi) + within_quarter(s, p, k, -phi));
    return sum / (2.0 * HT_PI);
}

}  // namespace

void dual_back_scattering(DualValues& v, int c) {
    // Zinke et al. 2008's sums over back-scattering paths of one and of three backward events
    // through a_f-attenuated forward chains.  1 - a_f^2 is floored: a_f -> 1 forces a_b -> 0,
    // and the limits of A_1, A_3 are finite (1/2, 1/8 as a_b = 1 - a_f -> 0).
    const double af = v.a_f[c], ab = v.a_b[c];
    const double af2 = af * af, ab2 = ab * ab;
    const double q = std::max(1.0 - af2, 1e-12);
    v.A_b[c] = ab * af2 / q + ab2 * ab * af2 / (q * q * q);
    v.delta_b[c] = v.alpha_b[c] * (1.0 - 2.0 * ab2 / (q * q)) +
                   v.alpha_f[c] * (2.0 * q * q + 4.0 * af2 * ab2) / (q * q * q);
    const double bf2 = v.beta_f2[c], bb2 = v.beta_b2[c];
    const double num = ab * std::sqrt(2.0 * bf2 + bb2) + ab2 * ab * std::sqrt(2.0 * bf2 + 3.0 * bb2);
    // The paper's denominator a_b + a_b^3 (2 beta_f + 3 beta_b) mixes widths into a weight; the
    // weights of its numerator's two terms (a_b, a_b^3) are meant, as its derivation shows.
    const double den = ab + ab2 * ab;
    const double sigma = den > 1e-300 ? (1.0 + HT_DUAL_DB * af2) * num / den
                                      : (1.0 + HT_DUAL_DB * af2) * std::sqrt(2.0 * bf2 + bb2);
    v.sigma_b2[c] = sigma * sigma;
}

DualValues dual_values(const HtMaterial& m, double theta_i, int nodes) {
    return values_from(m, sample_lobes(m, theta_i, nodes));
}

double dual_ng(const HtMaterial& m, int p, double theta_i, double phi, int channel, int nodes) {
    return ng_from(sample_lobes(m, theta_i, nodes), p, channel, phi);
}

std::vector<float> dual_table(const HtMaterial& m) {
    std::vector<float> t(4 * size_t(HT_DUAL_MATERIAL_ROWS), 0.0f);
    for (int p = 0; p < HT_DUAL_LOBES; ++p) {
        double alpha = 0, beta2 = 0;
        ht_dual_lobe_shape(&m, p, &alpha, &beta2);
        t[4 * p] = float(alpha);
        t[4 * p + 1] = float(beta2);
    }
    for (int i = 0; i <= HT_DUAL_THETA_N; ++i) {
        const double theta = HT_HALF_PI * i / HT_DUAL_THETA_N;
        const Samples s = sample_lobes(m, theta, kDualQuadratureNodes);
        const DualValues v = values_from(m, s);
        float* node = t.data() + 4 * (HT_DUAL_HEAD_ROWS + size_t(i) * HT_DUAL_NODE_ROWS);
        for (int c = 0; c < 3; ++c) {
            node[4 * HT_DUAL_ROW_AF + c] = float(v.a_f[c]);
            node[4 * HT_DUAL_ROW_BETA_F2 + c] = float(v.beta_f2[c]);
            node[4 * HT_DUAL_ROW_AB + c] = float(v.A_b[c]);
            node[4 * HT_DUAL_ROW_DELTA_B + c] = float(v.delta_b[c]);
            node[4 * HT_DUAL_ROW_SIGMA_B2 + c] = float(v.sigma_b2[c]);
            for (int p = 0; p < HT_DUAL_LOBES; ++p)
                for (int j = 0; j <= HT_DUAL_PHI_N; ++j)
                    node[4 * (HT_DUAL_ROW_NG + p * (HT_DUAL_PHI_N + 1) + j) + c] =
                        float(ng_from(s, p, c, HT_PI * j / HT_DUAL_PHI_N));
        }
    }
    return t;
}

}  // namespace ht
