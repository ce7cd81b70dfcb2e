// The image module (host/core/image_files.h): OpenImageIO is loaded only by the commands that read
// or write an image, and a binary without its module says so and exits 3.
#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <filesystem>
#include <fstream>
#include <string>

#ifdef HT_BINARY
namespace {
namespace fs = std::filesystem;
using clitest::run, clitest::slurp, clitest::TempDir;
const std::string kBin = HT_BINARY;
const std::string kTinyRender =
    " render 'builtin:strand?hairs=10&segments=4' --width 8 --height 8 --spp 1 --max-depth 1 --quiet";

// How many of the shared objects the dynamic loader opened for `cmd` (LD_DEBUG=files, on its
// stderr) name OpenImageIO.
int openimageio_loads(const TempDir& d, const std::string& cmd) {
    const std::string log = d / "ld.txt";
    run("LD_DEBUG=files LD_DEBUG_OUTPUT=" + log + " " + cmd + " >/dev/null 2>&1");
    int n = 0;
    for (const auto& entry : fs::directory_iterator(d.path))
        if (entry.path().filename().string().rfind("ld.txt", 0) == 0) {
            const std::string text = slurp(entry.path().string());
            for (size_t at = text.find("file=libOpenImageIO.so"); at != std::string::npos;
                 at = text.find("file=libOpenImageIO.so", at + 1))
                ++n;
            fs::remove(entry.path());
        }
    return n;
}
}  // namespace

TEST(ImageModule, OnlyCommandsWithImagesLoadOpenImageIO) {
    TempDir d("ht_image_module_");
    EXPECT_EQ(openimageio_loads(d, kBin + " --help"), 0);
    EXPECT_EQ(openimageio_loads(d, kBin + " render --help"), 0);
    EXPECT_EQ(openimageio_loads(d, kBin + " devices"), 0);
    // the same count where an image is written: the loader's log does show the library
    EXPECT_GT(openimageio_loads(d, kBin + kTinyRender + " -o " + (d / "a.exr")), 0);
    EXPECT_TRUE(fs::exists(d / "a.exr"));
}

TEST(ImageModule, RenderChecksItsOutputsAgainstTheKeptListOfFormats) {
    TempDir d("ht_image_module_");
    const std::string env = "HAIRTRACE_CACHE_DIR=" + (d / "cache") + " ";
    ASSERT_EQ(run(env + kBin + kTinyRender + " -o " + (d / "a.exr") + " -o " + (d / "a.png")), 0);
    // the module's list, kept under the module file's stamp
    std::vector<fs::path> kept;
    for (const auto& entry : fs::directory_iterator(d.path / "cache"))
        if (entry.path().filename().string().rfind("image_formats_", 0) == 0) kept.push_back(entry.path());
    ASSERT_EQ(kept.size(), 1u);
    const std::string list = slurp(kept[0].string());
    EXPECT_NE(list.find("exr\n"), std::string::npos) << list;
    EXPECT_NE(list.find("png\n"), std::string::npos) << list;
    // an extension the list lacks is looked up in the module: still refused before any work
    const std::string err = d / "err.txt";
    EXPECT_EQ(run(env + kBin + kTinyRender + " -o " + (d / "b.foo") + " 2>" + err), 2);
    EXPECT_NE(slurp(err).find("'.foo' is not an image format this build can write"), std::string::npos) << slurp(err);
    // a list naming a format the module cannot write: the outputs before it are written, then a
    // clear error
    std::ofstream(kept[0]) << "exr\nfoo\npng\n";
    EXPECT_EQ(run(env + kBin + kTinyRender + " -o " + (d / "c.exr") + " -o " + (d / "c.foo") + " 2>" + err), 3);
    EXPECT_NE(slurp(err).find("no image format for extension '.foo'"), std::string::npos) << slurp(err);
    EXPECT_TRUE(fs::exists(d / "c.exr"));
    EXPECT_FALSE(fs::exists(d / "c.foo"));
}

TEST(ImageModule, ABinaryWithoutItsModuleExits3NamingIt) {
    TempDir d("ht_image_module_");
    fs::create_directories(d.path / "bin");
    fs::copy_file(kBin, d / "bin/hairtrace");
    fs::permissions(d / "bin/hairtrace", fs::perms::owner_exec, fs::perm_options::add);
    const std::string bin = "HAIRTRACE_CACHE_DIR=off " + d / "bin/hairtrace";  // nothing kept, nothing left behind
    EXPECT_EQ(run(bin + " --help >/dev/null 2>&1"), 0);
    const std::string err = d / "err.txt";
    EXPECT_EQ(run(bin + kTinyRender + " -o " + (d / "a.png") + " 2>" + err), 3);
    EXPECT_NE(slurp(err).find("cannot load the image module"), std::string::npos) << slurp(err);
    EXPECT_NE(slurp(err).find(d / "bin/libhairtrace_image.so"), std::string::npos) << slurp(err);
    EXPECT_FALSE(fs::exists(d / "a.png"));
    // the installed layout: bin/ beside lib/hairtrace/
    fs::create_directories(d.path / "lib/hairtrace");
    fs::copy_file(fs::path(kBin).parent_path() / "libhairtrace_image.so", d.path / "lib/hairtrace/libhairtrace_image.so");
    EXPECT_EQ(run(bin + kTinyRender + " -o " + (d / "a.png")), 0);
    EXPECT_TRUE(fs::exists(d / "a.png"));
}
#endif
