// The command line as a user meets it: help for every command, misspelt options, bad values and
// bad paths refused with exit 2 before any work, and progress that reads well in a log.
#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#ifdef HT_BINARY
namespace {
namespace fs = std::filesystem;
using clitest::run, clitest::slurp, clitest::TempDir;
const std::string kBin = HT_BINARY;
// Minutes of work if it ever started: a mistake found first must make these return at once.
const std::string kLongRender = kBin + " render builtin:ball --width 2048 --height 2048 --spp 4096 --quiet";

double seconds_of(const std::string& cmd, int* code) {
    const auto t0 = std::chrono::steady_clock::now();
    *code = run(cmd);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

TEST(Cli, EveryCommandPrintsItsHelpWithExit0) {
    TempDir d("ht_cli_");
    for (const std::string c : {"render --help", "merge --help", "info --help", "devices --help", "bench --help",
                                "converge --help", "tonemap --help", "fiber --help", "fiber eval --help", "fiber sample -h",
                                "fiber furnace -h", "fiber afs -h", "render -h", "bench -h"}) {
        EXPECT_EQ(run(kBin + " " + c + " >" + (d / "help.txt") + " 2>&1"), 0) << c;
        EXPECT_NE(slurp(d / "help.txt").find("usage: hairtrace " + c.substr(0, c.find(' '))), std::string::npos)
            << c << ": " << slurp(d / "help.txt");
    }
    EXPECT_EQ(run(kBin + " help bench >/dev/null"), 0);
    EXPECT_EQ(run(kBin + " help bogus 2>" + (d / "err.txt")), 2);
    EXPECT_EQ(run(kBin + " rendr 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("did you mean render?"), std::string::npos) << slurp(d / "err.txt");
}

TEST(Cli, RenderHelpIsGroupedByTopic) {
    TempDir d("ht_cli_");
    ASSERT_EQ(run(kBin + " render --help >" + (d / "help.txt")), 0);
    const std::string help = slurp(d / "help.txt");
    size_t last = 0;
    for (const char* g : {"\noutput:\n", "\nsampling:\n", "\nlight transport:\n", "\nscene overrides:\n",
                          "\nlong renders:\n", "\ndevices:\n"}) {
        const size_t at = help.find(g);
        ASSERT_NE(at, std::string::npos) << g << help;
        EXPECT_GT(at, last) << g;
        last = at;
    }
}

TEST(Cli, MisspeltOptionsNameTheClosestOne) {
    TempDir d("ht_cli_");
    EXPECT_EQ(run(kLongRender + " --sp 4 -o " + (d / "x.png") + " 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("unknown option --sp (did you mean --spp?)"), std::string::npos)
        << slurp(d / "err.txt");
    EXPECT_EQ(run(kBin + " bench --repz 2 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("did you mean --reps?"), std::string::npos) << slurp(d / "err.txt");
    EXPECT_EQ(run(kBin + " fiber afs --eta 1.5 --sigma 0.1 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("did you mean --sigma-a?"), std::string::npos) << slurp(d / "err.txt");
}

TEST(Cli, BadValuesExit2NamingTheOption) {
    TempDir d("ht_cli_");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {" bench --res abc", "--res"},
        {" bench --reps 0", "--reps"},
        {" bench --cisect x", "--cisect"},
        {" bench --rays a.rays", "--rays"},
        {" bench --obb 0 --obb-split 1", "--obb-split"},
        {" render builtin:strand -o " + (d / "x.png") + " --bvh-oriented off --bvh-oriented-splits 1", "--bvh-oriented-splits"},
        {" fiber eval --precision half", "--precision"},
        {" fiber furnace --model chiang --nh many", "--nh"},
        {" render builtin:strand -o " + (d / "x.png") + " --max-depth deep", "--max-depth"},
        {" render builtin:strand -o " + (d / "x.png") + " --features most", "--features"},
        {" converge builtin:strand --reference " + (d / "x.exr") + " --width 0", "--reference"},
        {" merge " + (d / "missing.exr") + " -o " + (d / "x.exr"), "missing.exr"},
        // converge's --configs keys mean the render options and are checked before any work
        {" converge builtin:strand --reference " + (d / "ref.exr") + " --configs modle=zinke", "did you mean model?"},
        {" converge builtin:strand --reference " + (d / "ref.exr") + " --configs depth=0", "--configs depth"},
        {" converge builtin:strand --reference " + (d / "ref.exr") + " --device 0,1", "--device"},
    };
    std::ofstream(d / "ref.exr") << "never read: every case fails first";
    for (const auto& [args, option] : cases) {
        EXPECT_EQ(run(kBin + args + " 2>" + (d / "err.txt")), 2) << args;
        EXPECT_NE(slurp(d / "err.txt").find(option), std::string::npos) << args << ": " << slurp(d / "err.txt");
    }
}

TEST(Cli, OutputPathMistakesExit2BeforeRendering) {
    TempDir d("ht_cli_");
    const std::string missing = "/nonexistent_ht_folder/";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {kLongRender + " -o " + (d / "x.foo"), "-o"},
        {kLongRender + " -o ./noext", "no file extension"},
        {kLongRender + " -o " + missing + "a.png", "does not exist"},
        {kLongRender + " -o /proc/a.png", "cannot write"},
        {kLongRender + " -o " + (d / "ok.png") + " --checkpoint " + missing + "c.ckpt", "--checkpoint"},
        {kLongRender + " -o " + (d / "ok.png") + " -o " + (d / "b.jpeg2"), "'.jpeg2'"},
        {kBin + " converge builtin:ball --reference " + (d / "ref.exr") + " --csv " + (d / "rows.txt"), "--csv"},
        {kBin + " converge builtin:ball --reference " + (d / "ref.exr") + " --png " + missing + "p.png", "--png"},
        {kBin + " fiber afs --eta 1.55 --sigma-a 0.1 --png " + (d / "plot.xyz"), "--png"},
        {kBin + " fiber afs --eta 1.55 --sigma-a 0.1 --csv " + missing + "a.csv", "--csv"},
    };
    std::ofstream(d / "ref.exr") << "not read: the csv is refused first";
    for (const auto& [cmd, what] : cases) {
        int code = 0;
        const double seconds = seconds_of(cmd + " 2>" + (d / "err.txt"), &code);
        EXPECT_EQ(code, 2) << cmd;
        // The render would take hours; a loaded machine takes seconds to start any binary.
        EXPECT_LT(seconds, 60.0) << cmd << ": the mistake must be found before loading and rendering";
        EXPECT_NE(slurp(d / "err.txt").find(what), std::string::npos) << cmd << ": " << slurp(d / "err.txt");
    }
    EXPECT_FALSE(fs::exists(d / "ok.png"));
    EXPECT_FALSE(fs::exists(d / "x.foo"));
}

TEST(Cli, MissingInputsExit2) {
    TempDir d("ht_cli_");
    const std::string small = kBin + " render 'builtin:strand?hairs=20&segments=4' --width 8 --height 8 --spp 1 --quiet -o " +
                              (d / "x.exr");
    EXPECT_EQ(run(small + " --reference " + (d / "missing.exr") + " 2>/dev/null"), 2);
    std::ofstream(d / "junk.exr") << "not an image";
    EXPECT_EQ(run(small + " --reference " + (d / "junk.exr") + " 2>/dev/null"), 2) << "unreadable input is bad input";
    EXPECT_EQ(run(small + " --environment " + (d / "missing.hdr") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(small + " --resume " + (d / "missing.ckpt") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(kBin + " render " + (d / "missing.hair") + " -o " + (d / "x.exr") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(kBin + " bench --hair " + (d / "missing.hair") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(kBin + " tonemap " + (d / "missing.exr") + " -o " + (d / "x.png") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(kBin + " tonemap " + (d / "junk.exr") + " -o " + (d / "x.png") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(small + " --tonemap aces 2>/dev/null"), 2);
    EXPECT_FALSE(fs::exists(d / "x.exr"));
    EXPECT_FALSE(fs::exists(d / "x.png"));
}

// In a log, progress is whole lines (a terminal gets \r updates instead).
TEST(Cli, ProgressInALogIsOneLinePerUpdate) {
    TempDir d("ht_cli_");
    ASSERT_EQ(run(kBin + " render 'builtin:strand?hairs=40&segments=6' --width 16 --height 16 --spp 3 --max-depth 1 -o " +
                  (d / "x.exr") + " 2>" + (d / "log.txt")),
              0);
    const std::string log = slurp(d / "log.txt");
    EXPECT_EQ(log.find('\r'), std::string::npos) << log;
    EXPECT_EQ(log.find("rendering: "), log.find("\nrendering: ") + 1) << "each update starts a line: " << log;
    EXPECT_NE(log.find("\nrendering: 3/3 spp"), std::string::npos) << log;
    EXPECT_NE(log.find("\ndone: 3 spp"), std::string::npos) << log;
    ASSERT_EQ(run(kBin + " render 'builtin:strand?hairs=40&segments=6' --width 16 --height 16 --spp 3 --max-depth 1 "
                         "--quiet -o " + (d / "x.exr") + " 2>" + (d / "quiet.txt")),
              0);
    EXPECT_EQ(slurp(d / "quiet.txt"), "");
}
// On a terminal (a pseudo-terminal from script(1) here) the line is rewritten in place.
TEST(Cli, ProgressOnATerminalIsRewrittenInPlace) {
    if (run("command -v script >/dev/null") != 0) GTEST_SKIP() << "script(1) is not installed";
    TempDir d("ht_cli_");
    const std::string render = kBin + " render 'builtin:strand?hairs=40&segments=6' --width 16 --height 16 --spp 3 "
                                      "--max-depth 1 -o " + (d / "x.exr");
    ASSERT_EQ(run("script -qec \"" + render + "\" /dev/null >" + (d / "tty.txt") + " 2>&1"), 0) << slurp(d / "tty.txt");
    EXPECT_NE(slurp(d / "tty.txt").find("\rrendering: 3/3 spp"), std::string::npos) << slurp(d / "tty.txt");
}
#endif
