// Zinke 2004 averaged attenuation coefficients and the paper's "up to 17 %" statement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "fiber/afs_quadrature.h"
#include "kernels/fiber/afs.h"

using namespace ht;

TEST(FiberAfs, SeventeenPercentStatement) {
    // Zinke §5: sigma_a = 0.1 (relative to the radius), eta = 1.55, theta = 0: AFS_TT^avg = 0.70666 and
    // after 5 recursions 0.7067^5 = 17.6 % ("up to 17 %").  docs/MODEL.md §7 reference: 0.706660, 0.1762.
    AfsValues v = afs_reference(1.55, 0.1, 0.0);
    EXPECT_NEAR(v.TT, 0.706660, 1e-6);
    EXPECT_NEAR(std::pow(v.TT, 5), 0.1762, 5e-5);
    EXPECT_GT(std::pow(v.TT, 5), 0.165);  // "up to 17 %": a plot reading of 0.70 gives 16.8 %
    EXPECT_LT(std::pow(v.TT, 5), 0.18);
}

TEST(FiberAfs, ReferenceValuesFromNotes) {
    // docs/MODEL.md §7: AFS_R(0; 1.55) = 0.0228, TRT reading (a) 0.0049, reading (b) 0.148,
    // ray density factor pi/8.  Tolerances = the digits quoted.
    AfsValues v = afs_reference(1.55, 0.1, 0.0);
    EXPECT_NEAR(v.R, 0.0228, 5e-5);
    EXPECT_NEAR(v.TRT, 0.0049, 5e-5);
    EXPECT_NEAR(v.TRT_glint, 0.148, 5e-4);
    EXPECT_NEAR(v.density, HT_PI / 8, 1e-12);
    // without absorption the TT energy fraction times S' normalisation stays below 1 and R grows with theta
    AfsValues a = afs_reference(1.55, 0.0, 0.0), b = afs_reference(1.55, 0.0, 80 * HT_PI / 180);
    EXPECT_LT(a.TT, 1.0);
    EXPECT_GT(b.R, a.R);
}

TEST(FiberAfs, FastKernelVersionError) {
    // ht_afs_fast (16-point Gauss-Legendre per sub-interval) vs the adaptive reference, double precision:
    // measured R 1.2e-14, TT 6.1e-13, TRT 3.0e-10, glint 4.5e-11; thresholds with 10-100x margin.
    double emax[4] = {0, 0, 0, 0};
    for (double eta : {1.3, 1.55, 2.0})
        for (double sa : {0.0, 0.1, 1.0, 5.0})
            for (double th = 0; th <= 85; th += 5) {
                AfsValues v = afs_reference(eta, sa, th * HT_PI / 180);
                double ref[4] = {v.R, v.TT, v.TRT, v.TRT_glint - v.TRT};
                for (int p = 0; p < 4; ++p)
                    emax[p] = std::max(emax[p], std::fabs(ht_afs_fast(eta, sa, th * HT_PI / 180, p) - ref[p]));
            }
    std::printf("AFS fast max |error|: R %.2e TT %.2e TRT %.2e glint %.2e\n", emax[0], emax[1], emax[2], emax[3]);
    EXPECT_LT(emax[0], 1e-12);
    EXPECT_LT(emax[1], 1e-11);
    EXPECT_LT(emax[2], 1e-8);
    EXPECT_LT(emax[3], 1e-8);
}

TEST(FiberAfs, ThreeChannelTTEqualsOneChannelTT) {
    // ht_afs_tt3 (the --indirect afs shadow rays) shares the nodes, Fresnel and ray density of the
    // three channels: the same quadrature as ht_afs_fast per channel, up to double rounding.
    for (double eta : {1.3, 1.55, 2.0})
        for (double th = 0; th <= 89.5; th += 2.5) {
            const double t = th * HT_PI / 180;
            const real3 s = make_real3(0.0, 0.3, 5.0);
            const real3 v = ht_afs_tt3(eta, s, t);
            EXPECT_NEAR(v.x, ht_afs_fast(eta, 0.0, t, 1), 1e-14) << eta << " " << th;
            EXPECT_NEAR(v.y, ht_afs_fast(eta, 0.3, t, 1), 1e-14) << eta << " " << th;
            EXPECT_NEAR(v.z, ht_afs_fast(eta, 5.0, t, 1), 1e-14) << eta << " " << th;
        }
}

TEST(FiberAfs, AfsTableInterpolationError) {
    // The --indirect afs table (float nodes, linear in theta) against ht_afs_fast in double on a
    // grid that falls between the nodes.  Measured: < 7.2e-6 absolute (the worst, sigma_a = 0,
    // within the last degrees before grazing); bound 2e-5.  A shadow ray's transmittance is a
    // product of factors <= 1: 20 crossings at AFS_TT ~ 0.7 move it by < 6e-4 relative.
    const float materials[][3] = {{0.0f, 0.0f, 0.0f}, {0.06f, 0.1f, 0.2f}, {1.0f, 2.0f, 5.0f}, {8.0f, 10.0f, 12.0f}};
    for (double eta : {1.3, 1.55, 2.0})
        for (const auto& sa : materials) {
            const std::vector<float> table = ht::afs_tt_table(eta, sa);
            ASSERT_EQ(table.size(), size_t(4 * (HT_AFS_TT_TABLE_N + 1)));
            double worst = 0;
            for (int i = 0; i <= 2000; ++i) {
                const double t = HT_HALF_PI * (i + 0.37) / 2000.4;
                const real3 v = ht_afs_tt_lookup(table.data(), 0, t);
                worst = std::max({worst, std::fabs(v.x - ht_afs_fast(eta, sa[0], t, 1)),
                                  std::fabs(v.y - ht_afs_fast(eta, sa[1], t, 1)),
                                  std::fabs(v.z - ht_afs_fast(eta, sa[2], t, 1))});
            }
            EXPECT_LT(worst, 2e-5) << "eta " << eta << " sigma_a " << sa[0];
            std::printf("afs table eta %.2f sigma_a %.2f: max error %.2g\n", eta, sa[0], worst);
        }
}

TEST(FiberAfs, CurvesCsvAndPng) {
    auto rows = afs_curves(1.55, 0.1, 89.0, 1.0);
    ASSERT_EQ(rows.size(), 90u);
    EXPECT_NEAR(rows[0].v.TT, 0.706660, 1e-6);
    std::string dir = ::testing::TempDir();
    write_afs_csv(dir + "/afs.csv", rows);
    write_afs_png(dir + "/afs.png", rows, 1.55, 0.1);
    std::ifstream f(dir + "/afs.csv");
    std::string header;
    std::getline(f, header);
    EXPECT_EQ(header, "theta_deg,R,TT,TRT,TRT_glint,density");
    std::ifstream p(dir + "/afs.png", std::ios::binary);
    char sig[8] = {};
    p.read(sig, 8);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG");
}
