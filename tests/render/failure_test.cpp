// Faults a user meets in practice: broken kernels, devices too small, full disks.  Every one must
// end in a clear message and a meaningful exit code, never a crash, and lose nothing.
#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#ifdef HT_BINARY
namespace fs = std::filesystem;
using clitest::TempDir;
using clitest::run;
using clitest::slurp;

namespace {
const std::string kBin = HT_BINARY;
const std::string kSmall = " render 'builtin:strand?hairs=60&segments=8' --width 24 --height 24 --spp 1 --max-depth 1 --quiet";
}  // namespace

TEST(Failure, KernelBuildErrorPrintsTheLogWithTheFileAndExits3) {
    TempDir d("ht_fail_");
    fs::copy(fs::path(HT_SOURCE_DIR) / "kernels", d.path / "kernels", fs::copy_options::recursive);
    {
        std::ofstream f(d / "kernels/stages/shade.cl", std::ios::app);
        f << "\nthis is not OpenCL C;\n";
    }
    std::string cmd = "HAIRTRACE_CACHE_DIR=off HAIRTRACE_KERNEL_DIR=" + (d / "kernels") + " " + kBin + kSmall +
                      " -o " + (d / "x.png") + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("kernels/stages/shade.cl:"), std::string::npos) << err;
    EXPECT_NE(err.find("failed"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(d / "x.png"));
}

TEST(Failure, FilmLargerThanTheDeviceAllocationIsRefusedBeforeAllocating) {
    // The device's largest allocation is capped (HAIRTRACE_MAX_ALLOC, host/cl/device.cpp) below
    // the 4096^2 film's 256 MiB: a CPU device's own limit depends on the machine's memory (8 GiB
    // on a 24 GiB guest, where an uncapped 16384^2 film fits and renders for minutes).
    TempDir d("ht_fail_");
    std::string cmd = "HAIRTRACE_MAX_ALLOC=128M " + kBin +
                      " render 'builtin:strand?hairs=60&segments=8' --width 4096 --height 4096 --spp 1 --quiet -o " +
                      (d / "x.exr") + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("largest allocation"), std::string::npos) << err;
}

TEST(Failure, MaxMemoryRefusesLargeInputsWithTheSize) {
    TempDir d("ht_fail_");
    std::string cmd = kBin + " render builtin:strand --max-memory 1M --spp 1 --quiet -o " + (d / "x.exr") + " 2>" +
                      (d / "err.txt");
    EXPECT_EQ(run(cmd), 2);
    std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("limit"), std::string::npos) << err;
    EXPECT_EQ(run(kBin + kSmall + " --max-memory banana -o " + (d / "y.exr") + " 2>/dev/null"), 2);
}

// A scene whose texture image is missing: exit 2 with the scene file, the image and the
// problem on one line, before any device work.
TEST(Failure, MissingTextureImageExits2NamingTheFiles) {
    TempDir d("ht_fail_");
    std::string scene = slurp(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_checker_floor.gltf");
    const size_t uri = scene.find("\"data:image/png;base64,");
    ASSERT_NE(uri, std::string::npos);
    scene.replace(uri, scene.find('"', uri + 1) + 1 - uri, "\"floor%20tiles.png\"");
    std::ofstream(d / "floor.gltf") << scene;
    std::string cmd = kBin + " render " + (d / "floor.gltf") + " --width 8 --height 8 --spp 1 --quiet -o " +
                      (d / "x.exr") + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 2);
    const std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find(d / "floor.gltf"), std::string::npos) << err;
    EXPECT_NE(err.find("floor tiles.png"), std::string::npos) << err;
    EXPECT_NE(err.find("does not exist"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(d / "x.exr"));
}

// A tmpfs of `bytes` mounted on `path` for the scope (root only: mounted() is false otherwise).
struct SmallDisk {
    fs::path path;
    bool mounted = false;
    SmallDisk(fs::path p, const std::string& size) : path(std::move(p)) {
        fs::create_directories(path);
        mounted = ::mount("tmpfs", path.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
    }
    ~SmallDisk() {
        if (mounted) ::umount(path.c_str());
    }
};

TEST(Failure, FullDiskKeepsThePreviousImage) {
    TempDir d("ht_fail_");
    SmallDisk disk(d.path / "small_fs", "96k");
    if (!disk.mounted) GTEST_SKIP() << "cannot mount a tmpfs here (not root?)";
    const fs::path& mnt = disk.path;
    // a previous, small image
    ASSERT_EQ(run(kBin + kSmall + " -o " + (mnt / "img.exr").string()), 0);
    std::string before = slurp((mnt / "img.exr").string());
    ASSERT_FALSE(before.empty());
    // fill the disk, leaving a few KiB
    {
        std::ofstream filler(mnt / "filler", std::ios::binary);
        std::string block(4096, 'x');
        while (filler.write(block.data(), block.size()) && fs::space(mnt).available > 8192) {
        }
    }
    std::string cmd = kBin + " render 'builtin:strand?hairs=60&segments=8' --width 256 --height 256 --spp 1 --max-depth 1 --quiet -o " +
                      (mnt / "img.exr").string() + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    EXPECT_EQ(slurp((mnt / "img.exr").string()), before) << "the previous image must survive a failed write";
    EXPECT_NE(slurp(d / "err.txt").find("img.exr"), std::string::npos) << slurp(d / "err.txt");
    for (auto& e : fs::directory_iterator(mnt))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left a temporary file: " << e.path();
}

// The final checkpoint is written after the images: a checkpoint that cannot be written (a full
// disk the start-up check cannot foresee) fails the run but keeps the images.
TEST(Failure, ImagesSurviveACheckpointThatCannotBeWritten) {
    TempDir d("ht_fail_");
    SmallDisk disk(d.path / "small_fs", "16k");
    if (!disk.mounted) GTEST_SKIP() << "cannot mount a tmpfs here (not root?)";
    const std::string cmd = kBin + " render 'builtin:strand?hairs=60&segments=8' --width 64 --height 64 --spp 1 --quiet -o " +
                            (d / "x.exr") + " -o " + (d / "x.png") + " --checkpoint " + (disk.path / "c.ckpt").string() +
                            " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    EXPECT_NE(slurp(d / "err.txt").find("c.ckpt"), std::string::npos) << slurp(d / "err.txt");
    EXPECT_TRUE(fs::exists(d / "x.exr"));
    EXPECT_TRUE(fs::exists(d / "x.png"));
}
#endif

#ifdef HT_BINARY
// Driver failures that real devices produce only under pressure, injected at the device layer:
// each must end in a one-line message and exit 3, with nothing written.
TEST(Failure, DeviceOutOfResourcesAtLaunchExits3) {
    TempDir d("ht_fail_");
    std::string cmd = "HAIRTRACE_INJECT_FAULT=launch " + kBin + kSmall + " -o " + (d / "x.exr") + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("CL_OUT_OF_RESOURCES"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(d / "x.exr"));
}

TEST(Failure, DeviceAllocationFailureExits3) {
    TempDir d("ht_fail_");
    std::string cmd = "HAIRTRACE_INJECT_FAULT=alloc " + kBin + kSmall + " -o " + (d / "x.exr") + " 2>" + (d / "err.txt");
    EXPECT_EQ(run(cmd), 3);
    std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("CL_MEM_OBJECT_ALLOCATION_FAILURE"), std::string::npos) << err;
}
#endif
