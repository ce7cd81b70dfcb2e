// What every output image says about how it was made (host/cli/render_command.cpp metadata_of,
// host/cli/merge_command.cpp, host/io/image_io.cpp write_image): read back with OpenImageIO from
// the PNG (text chunks), the JPEG (ImageDescription) and the EXR (typed attributes).
#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <OpenImageIO/imageio.h>

#include <string>

#ifdef HT_BINARY
namespace {
using clitest::run, clitest::TempDir;

OIIO::ImageSpec spec_of(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    return in ? in->spec() : OIIO::ImageSpec();
}

const char* const kTextKeys[] = {"hairtrace:command_line", "hairtrace:render_key", "hairtrace:identity",
                                 "hairtrace:fiber_model",  "hairtrace:indirect",   "hairtrace:features",
                                 "hairtrace:date",         "hairtrace:device",     "hairtrace:tonemap"};
}  // namespace

TEST(Metadata, EveryImageCarriesTheCommandLineIdentityAndSettings) {
    TempDir d("ht_meta_");
    const std::string cmd = std::string(HT_BINARY) + " render 'builtin:strand?hairs=40&segments=4' --width 16 " +
                            "--height 12 --spp 3 --seed 7 --indirect afs --model zinke --exposure 2.5 --quiet -o " +
                            (d / "a.png") + " -o " + (d / "a.jpg") + " -o " + (d / "a.exr");
    ASSERT_EQ(run(cmd), 0);

    const OIIO::ImageSpec png = spec_of(d / "a.png");
    for (const char* key : kTextKeys) EXPECT_FALSE(png.get_string_attribute(key).empty()) << key;
    EXPECT_EQ(png.get_string_attribute("hairtrace:command_line"),
              "hairtrace render 'builtin:strand?hairs=40&segments=4' --width 16 --height 12 --spp 3 --seed 7 "
              "--indirect afs --model zinke --exposure 2.5 --quiet -o " + (d / "a.png") + " -o " + (d / "a.jpg") +
                  " -o " + (d / "a.exr"));
    // PNG keeps text only: the numbers are written as text.
    EXPECT_EQ(png.get_string_attribute("hairtrace:spp"), "3");
    EXPECT_EQ(png.get_string_attribute("hairtrace:seed"), "7");
    EXPECT_EQ(png.get_string_attribute("hairtrace:exposure"), "2.5");
    EXPECT_EQ(png.get_string_attribute("hairtrace:indirect"), "afs");
    EXPECT_EQ(png.get_string_attribute("hairtrace:fiber_model"), "blond=zinke");
    EXPECT_EQ(png.get_string_attribute("hairtrace:tonemap"), "filmic");
    EXPECT_EQ(png.get_string_attribute("hairtrace:render_key").size(), 16u);
    EXPECT_NE(png.get_string_attribute("hairtrace:features").find("HT_FEATURE_MODEL_ZINKE"), std::string::npos);

    // JPEG keeps no custom attributes: everything is in ImageDescription, one "key: value" a line.
    const std::string jpg = spec_of(d / "a.jpg").get_string_attribute("ImageDescription");
    for (const char* key : kTextKeys) EXPECT_NE(jpg.find(std::string(key) + ": "), std::string::npos) << key;
    EXPECT_NE(jpg.find("hairtrace:spp: 3\n"), std::string::npos) << jpg;

    // EXR keeps them typed, and the same identity as the PNG.
    const OIIO::ImageSpec exr = spec_of(d / "a.exr");
    EXPECT_EQ(exr.get_int_attribute("hairtrace:spp"), 3);
    EXPECT_EQ(exr.get_int_attribute("hairtrace:seed"), 7);
    EXPECT_FLOAT_EQ(exr.get_float_attribute("hairtrace:exposure"), 2.5f);
    // the command line's defaults, auto resolved (the builtin strand has one light); the splits in
    // use: one, since with --indirect afs and no --max-depth no path goes on past its first vertex
    EXPECT_EQ(exr.get_int_attribute("hairtrace:first_hit_splits"), 1);
    EXPECT_EQ(exr.get_string_attribute("hairtrace:first_hit_splits_mode"), "auto");
    EXPECT_EQ(exr.get_int_attribute("hairtrace:first_hit_light_samples"), 1);
    for (const char* key : kTextKeys) {
        EXPECT_EQ(exr.get_string_attribute(key), png.get_string_attribute(key)) << key;
    }
}

// A merged render-farm image names its own command line and, in hairtrace:parts, each part's
// ("FILE: COMMAND LINE" a line, in the order the parts were given).
TEST(Metadata, MergedImageCarriesEveryPartsCommandLine) {
    TempDir d("ht_meta_merge_");
    // The words after the program's name, run by the binary and recorded after "hairtrace".
    const std::string render = " render 'builtin:strand?hairs=40&segments=4' --width 16 --height 12 --spp 4 "
                               "--chunk 2 --quiet";
    const std::string part0 = render + " --sample-range 0:2 -o " + (d / "p0.exr");
    const std::string part1 = render + " --sample-range 2:4 -o " + (d / "p1.exr");
    const std::string merge = " merge " + (d / "p1.exr") + " " + (d / "p0.exr") + " -o " + (d / "m.exr") + " -o " +
                              (d / "m.png") + " --quiet";
    for (const std::string& words : {part0, part1, merge}) ASSERT_EQ(run(HT_BINARY + words), 0) << words;
    const std::string parts =
        (d / "p1.exr") + ": hairtrace" + part1 + "\n" + (d / "p0.exr") + ": hairtrace" + part0;
    for (const char* image : {"m.exr", "m.png"}) {
        const OIIO::ImageSpec spec = spec_of(d / image);
        EXPECT_EQ(spec.get_string_attribute("hairtrace:parts"), parts) << image;
        EXPECT_EQ(spec.get_string_attribute("hairtrace:command_line"), "hairtrace" + merge) << image;
    }
}
#endif
