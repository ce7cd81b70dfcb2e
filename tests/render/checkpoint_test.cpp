// Long renders: checkpoints, resume, interrupts.  Driven through the CLI like a user would.
#include "io/image_io.h"
#include "kernels/aovs.h"
#include "split/checkpoint.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#ifdef HT_BINARY
namespace fs = std::filesystem;
using namespace ht;
using clitest::TempDir;
using clitest::run;
using clitest::slurp;
using clitest::image;

namespace {
const std::string kRender = std::string(HT_BINARY) +
    " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3 --seed 5 --quiet";

}  // namespace

TEST(Checkpoint, ResumedRenderEqualsUninterruptedBitForBit) {
    TempDir d("ht_ckpt_");
    ASSERT_EQ(run(kRender + " --spp 6 -o " + (d / "full.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 2 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "part.exr")), 0);
    Checkpoint c = load_checkpoint(d / "c.ckpt");
    EXPECT_EQ(c.samples_done, 2u);
    ASSERT_EQ(run(kRender + " --spp 6 --resume " + (d / "c.ckpt") + " -o " + (d / "resumed.exr")), 0);
    EXPECT_EQ(image(d / "full.exr"), image(d / "resumed.exr"));
}

// With --aovs every channel keeps its bits: a checkpoint that ends inside a chunk (6 of 8 samples,
// chunks of 4: the continued chunk gets its AOV sums back on the device) and one that a time
// limit cut wherever it fell (possibly before the first sample).
TEST(Checkpoint, ResumedAovsEqualUninterruptedBitForBit) {
    TempDir d("ht_ckpt_");
    const std::string aovs = kRender + clitest::kEveryAov + " --chunk 4";
    ASSERT_EQ(run(aovs + " --spp 8 -o " + (d / "full.exr")), 0);
    ASSERT_EQ(run(aovs + " --spp 6 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "part.exr")), 0);
    const Checkpoint c = load_checkpoint(d / "c.ckpt");
    EXPECT_EQ(c.samples_done, 6u);
    EXPECT_EQ(c.aov_sums, uint32_t(HT_AOV_OUT));
    ASSERT_EQ(c.segments.size(), 2u);  // the prefix [0, 4) and the short chunk [4, 6)
    EXPECT_EQ(c.segments[1].film.aov.size(), size_t(HT_AOV_OUT) * 40 * 32);
    ASSERT_EQ(run(aovs + " --spp 8 --resume " + (d / "c.ckpt") + " -o " + (d / "resumed.exr")), 0);
    clitest::expect_same_channel_bits(d / "full.exr", d / "resumed.exr");

    ASSERT_EQ(run(aovs + " --spp 8 --time-limit 0.001 --checkpoint " + (d / "t.ckpt") + " -o " + (d / "early.exr")), 0);
    ASSERT_EQ(run(aovs + " --spp 8 --resume " + (d / "t.ckpt") + " -o " + (d / "resumed_t.exr")), 0);
    clitest::expect_same_channel_bits(d / "full.exr", d / "resumed_t.exr");
}

TEST(Checkpoint, ResumeOfADifferentRenderIsRefused) {
    TempDir d("ht_ckpt_");
    ASSERT_EQ(run(kRender + " --spp 1 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "a.exr")), 0);
    std::string other = std::string(HT_BINARY) +
        " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3 --seed 6 --quiet";
    EXPECT_EQ(run(other + " --spp 2 --resume " + (d / "c.ckpt") + " -o " + (d / "b.exr") + " 2>/dev/null"), 2);
}

TEST(Checkpoint, CorruptOrTruncatedCheckpointIsBadInput) {
    TempDir d("ht_ckpt_");
    ASSERT_EQ(run(kRender + " --spp 1 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "a.exr")), 0);
    auto size = fs::file_size(d / "c.ckpt");
    {
        std::fstream f(d / "c.ckpt", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size - 7));
        f.put('\x55');
    }
    EXPECT_THROW(load_checkpoint(d / "c.ckpt"), SceneError);
    EXPECT_EQ(run(kRender + " --spp 2 --resume " + (d / "c.ckpt") + " -o " + (d / "b.exr") + " 2>/dev/null"), 2);
    fs::resize_file(d / "c.ckpt", size / 2);
    EXPECT_THROW(load_checkpoint(d / "c.ckpt"), SceneError);
}

TEST(Checkpoint, SigtermLeavesCheckpointAndValidImage) {
    TempDir d("ht_ckpt_");
    std::string cmd = kRender + " --spp 100000 --checkpoint-every 0.01 --checkpoint " + (d / "c.ckpt") + " -o " +
                      (d / "i.exr");
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), (char*)nullptr);
        _exit(127);
    }
    // wait until the render has produced a sample (its first periodic checkpoint)
    for (int i = 0; i < 1200 && !fs::exists(d / "c.ckpt"); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!fs::exists(d / "c.ckpt")) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
        FAIL() << "the render wrote no checkpoint within 60 s";
    }
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
    Checkpoint c = load_checkpoint(d / "c.ckpt");
    EXPECT_GT(c.samples_done, 0u);
    auto img = image(d / "i.exr");
    EXPECT_EQ(img.size(), size_t(40 * 32 * 3));
    EXPECT_FALSE(fs::exists(d / "c.ckpt.tmp"));
}
#endif
