// hairtrace converge end to end on a tiny scene: a CSV row per sample count with the sparkle share,
// points from another renderer's CSV drawn with --external (and refused with exit 2 when the CSV
// does not name its columns), the warm-up sample reported apart, --reference-noise subtracted.
#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifdef HT_BINARY
namespace {
using clitest::run, clitest::slurp, clitest::TempDir;
const std::string kBin = HT_BINARY;
const std::string kScene = "'builtin:strand?hairs=60&segments=8' --width 24 --height 24 --max-depth 2";

std::vector<std::vector<std::string>> csv_rows(const std::string& path) {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        std::string item;
        while (std::getline(ss, item, ',')) f.push_back(item);
        rows.push_back(f);
    }
    return rows;
}
}  // namespace

TEST(Converge, WritesSparklesDrawsExternalPointsAndKeepsTheWarmUpApart) {
    TempDir d("ht_converge_");
    ASSERT_EQ(run(kBin + " render " + kScene + " --spp 32 --seed 7 --quiet -o " + (d / "ref.exr")), 0);
    {
        std::ofstream ext(d / "other.csv");
        // CRLF line ends, as a spreadsheet saves them
        ext << "label,spp,seconds,extra,rmse\r\nother d2,4,0.5,x,0.1\r\nother d2,16,1.5,y,0.05\r\nother d5,16,2,z,0.2\r\n";
    }
    const std::string cmd = kBin + " converge " + kScene + " --reference " + (d / "ref.exr") +
                            " --configs 'depth=2;depth=1' --spp 1,4 --csv " + (d / "c.csv") + " --png " +
                            (d / "c.png") + " --external " + (d / "other.csv") + " 2>" + (d / "err.txt");
    ASSERT_EQ(run(cmd), 0) << slurp(d / "err.txt");
    const auto rows = csv_rows(d / "c.csv");
    ASSERT_EQ(rows.size(), 5u);
    EXPECT_EQ(rows[0][7], "sparkle_share");
    EXPECT_EQ(rows[0].back(), "cpu_seconds");
    for (size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 9u);
        EXPECT_GT(std::stod(rows[i][8]), 0.0);
        const double share = std::stod(rows[i][7]);
        EXPECT_GE(share, 0.0);
        EXPECT_LE(share, 1.0);
    }
    EXPECT_NE(slurp(d / "err.txt").find("warm-up sample (first launch, not counted)"), std::string::npos);
    // depth 2 takes the command line's --first-hit-splits auto: its pilot is timed and reported
    EXPECT_NE(slurp(d / "err.txt").find("depth=2                          first-hit splits: auto chose"),
              std::string::npos) << slurp(d / "err.txt");
    EXPECT_GT(std::filesystem::file_size(d / "c.png"), 1000u);
    // The same run with the reference's noise removed: every RMSE at most the plain one.
    ASSERT_EQ(run(kBin + " converge " + kScene + " --reference " + (d / "ref.exr") + " --configs depth=2 --spp 1,4" +
                  " --reference-noise 0.001 --quiet --csv " + (d / "n.csv") + " --png " + (d / "n.png")), 0);
    const auto noisy = csv_rows(d / "n.csv");
    ASSERT_EQ(noisy.size(), 3u);
    for (size_t i = 1; i < 3; ++i) {
        const double plain = std::stod(rows[i][3]), cleaned = std::stod(noisy[i][3]);
        EXPECT_NEAR(cleaned, std::sqrt(std::max(0.0, plain * plain - 1e-6)), 1e-4 * plain);
    }
    // --replot draws the external points too, without rendering
    ASSERT_EQ(run(kBin + " converge x --replot " + (d / "c.csv") + " --png " + (d / "r.png") + " --external " +
                  (d / "other.csv")), 0);
    // A CSV that does not name spp, seconds and rmse is refused with exit 2, naming the option
    {
        std::ofstream bad(d / "bad.csv");
        bad << "spp,time,rmse\n4,0.5,0.1\n";
    }
    ASSERT_EQ(run(kBin + " converge x --replot " + (d / "c.csv") + " --png " + (d / "r.png") + " --external " +
                  (d / "bad.csv") + " 2>" + (d / "bad.txt")), 2);
    EXPECT_NE(slurp(d / "bad.txt").find("--external"), std::string::npos) << slurp(d / "bad.txt");
}

TEST(Converge, RenderReferencePrintsTheSparkleShare) {
    TempDir d("ht_converge_");
    ASSERT_EQ(run(kBin + " render " + kScene + " --spp 16 --seed 7 --quiet -o " + (d / "ref.exr")), 0);
    ASSERT_EQ(run(kBin + " render " + kScene + " --spp 2 --seed 8 --quiet -o " + (d / "x.exr") + " --reference " +
                  (d / "ref.exr") + " >" + (d / "out.txt")), 0);
    EXPECT_NE(slurp(d / "out.txt").find("px > 10x local noise"), std::string::npos) << slurp(d / "out.txt");
}
#endif
