// Reference AFS^avg quadrature (Zinke 2004 §5, Appendix 2; docs/MODEL.md §7), double precision.
#pragma once

#include <string>
#include <vector>

namespace ht {

struct AfsValues {
    double R = 0, TT = 0, TRT = 0;  // TRT: caustic removal, no glint (docs/MODEL.md §7 reading (a))
    double TRT_glint = 0;           // TRT with removal + glint (reading (b))
    double density = 0;             // "averaged ray density factor" = int_0^1 S'_R dh = pi/8
};

// Adaptive Gauss-Kronrod (7/15) in u = asin h, split at the TRT caustic, |abs error| < ~1e-12.
// theta in radians; sigma_a relative to the radius; eta > 1.
AfsValues afs_reference(double eta, double sigma_a, double theta);

// AFS_TT^avg(theta) for --indirect afs: HT_AFS_TT_TABLE_N + 1 nodes in theta over [0, pi/2],
// (r, g, b, 0) each, for one material (kernels/fiber/afs.h ht_afs_tt_lookup).
std::vector<float> afs_tt_table(double eta, const float sigma_a[3]);

// Fig. 4 curves: rows over theta = 0..theta_max_deg in steps (degrees).
struct AfsRow {
    double theta_deg;
    AfsValues v;
};
std::vector<AfsRow> afs_curves(double eta, double sigma_a, double theta_max_deg = 89.0, double step_deg = 1.0);

void write_afs_csv(const std::string& path, const std::vector<AfsRow>& rows);
// Plot the curves into a PNG (OpenImageIO); throws std::runtime_error on write failure.
void write_afs_png(const std::string& path, const std::vector<AfsRow>& rows, double eta, double sigma_a);

}  // namespace ht
