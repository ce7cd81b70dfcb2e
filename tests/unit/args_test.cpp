// The command-line parser every command uses: help, misspelt options, bad values and bad paths
// are all usage errors that name the option.
#include <gtest/gtest.h>

#include "cli/args.h"
#include "cli/path_checks.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

using ht::ArgParser;
using ht::PathKind;
using ht::UsageError;

namespace {

ArgParser sample_parser() {
    ArgParser p("render", "renders");
    p.positional("SCENE", "scene");
    p.group("sampling").option("--spp", "N", "samples", "64").option("--seed", "S", "seed", "1");
    p.group("output").path("-o", "OUT", "image", PathKind::Image, "", true).flag("--quiet", "silence");
    p.group("light transport").option("--indirect", "exact|afs|none", "hair-to-hair light", "exact");
    p.option("--max-depth", "D|auto", "depth", "auto");
    return p;
}

// The message of the UsageError `parse` throws, or "" when it throws none.
std::string usage_error(const std::vector<std::string>& args) {
    ArgParser p = sample_parser();
    try {
        p.parse(args);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

std::string temp_folder() {
    const auto d = std::filesystem::temp_directory_path() / ("ht_args_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}

}  // namespace

TEST(Args, MisspeltOptionsNameTheClosestValidOne) {
    EXPECT_NE(usage_error({"s", "--sp", "4"}).find("unknown option --sp (did you mean --spp?)"), std::string::npos)
        << usage_error({"s", "--sp", "4"});
    EXPECT_NE(usage_error({"s", "-spp", "4"}).find("did you mean --spp?"), std::string::npos);
    EXPECT_NE(usage_error({"s", "--quite"}).find("did you mean --quiet?"), std::string::npos);
    EXPECT_NE(usage_error({"s", "--max-dept", "2"}).find("did you mean --max-depth?"), std::string::npos);
    const std::string far = usage_error({"s", "--bogus"});
    EXPECT_NE(far.find("unknown option --bogus"), std::string::npos) << far;
    EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
    EXPECT_EQ(ht::did_you_mean("rendr", {"render", "merge", "info"}), " (did you mean render?)");
}

TEST(Args, HelpIsAlwaysAcceptedAndGroupsOptionsByTopic) {
    for (const char* h : {"--help", "-h"}) {
        ArgParser p = sample_parser();
        p.parse({h, "--spp", "nonsense"});  // no check runs when help is asked for
        EXPECT_TRUE(p.wants_help());
    }
    const std::string help = sample_parser().help();
    const auto sampling = help.find("\nsampling:\n"), output = help.find("\noutput:\n"),
               transport = help.find("\nlight transport:\n");
    ASSERT_NE(sampling, std::string::npos) << help;
    ASSERT_NE(output, std::string::npos) << help;
    ASSERT_NE(transport, std::string::npos) << help;
    EXPECT_LT(sampling, output);
    EXPECT_LT(help.find("--seed"), output) << "an option is listed under its own group";
    EXPECT_GT(help.find("--max-depth"), transport);
    EXPECT_NE(help.find("(default: 64)"), std::string::npos);
}

TEST(Args, BadValuesNameTheOptionAndTheExpectedForm) {
    ArgParser p = sample_parser();
    p.parse({"s", "--spp", "abc", "--indirect", "exakt", "--max-depth", "deep", "--seed", "7"});
    try {
        p.get_int("--spp", 1, 100);
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "render: --spp expects an integer, got 'abc'");
    }
    try {
        p.get_choice("--indirect", {"exact", "afs", "none"});
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "render: --indirect must be exact, afs or none, got 'exakt' (did you mean exact?)");
    }
    try {
        p.get_int_or("--max-depth", "auto", 1, 1000);
        FAIL();
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "render: --max-depth must be auto or an integer in [1, 1000], got 'deep'");
    }
    EXPECT_EQ(p.get_int("--seed", 0, 10), 7);
    EXPECT_THROW(p.get_int("--seed", 0, 5), UsageError);
    EXPECT_NE(usage_error({"s", "--spp"}).find("--spp needs a value N"), std::string::npos);
    EXPECT_NE(usage_error({"s", "--spp", "1", "--spp", "2"}).find("--spp is given twice"), std::string::npos);
    EXPECT_NE(usage_error({}).find("missing argument SCENE"), std::string::npos);
    EXPECT_NE(usage_error({"a", "b"}).find("unexpected argument 'b'"), std::string::npos);
}

TEST(Args, RepeatedOptionsAndPositionalsKeepTheirOrder) {
    const std::string d = temp_folder();
    ArgParser p("merge");
    p.positional("PART", "parts", ht::Arity::Many).path("-o", "OUT", "image", PathKind::Image, "", true);
    p.parse({"a.exr", "-o", d + "/x.exr", "b.exr", "-o=" + d + "/x.png"});
    EXPECT_EQ(p.all("PART"), (std::vector<std::string>{"a.exr", "b.exr"}));
    EXPECT_EQ(p.all("-o"), (std::vector<std::string>{d + "/x.exr", d + "/x.png"}));
    ASSERT_EQ(p.given().size(), 2u);
    EXPECT_EQ(p.given()[1].second, d + "/x.png");
    std::filesystem::remove_all(d);
}

TEST(Args, OutputPathsAreCheckedForFormatAndFolderBeforeAnyWork) {
    const std::string d = temp_folder();
    auto problem = [](const std::string& path, PathKind kind) -> std::string {
        try {
            ht::check_path("render: -o", path, kind);
        } catch (const UsageError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(problem(d + "/a.png", PathKind::Image), "");
    EXPECT_EQ(problem(d + "/a.EXR", PathKind::Image), "");
    EXPECT_EQ(problem(d + "/a.tif", PathKind::Image), "");
    EXPECT_NE(problem(d + "/x.foo", PathKind::Image).find("'.foo' is not an image format"), std::string::npos);
    EXPECT_NE(problem("./noext", PathKind::Image).find("no file extension"), std::string::npos);
    EXPECT_NE(problem("/nonexistent/dir/a.png", PathKind::Image).find("the folder /nonexistent/dir does not exist"),
              std::string::npos);
    // /proc refuses new files even to root, where permission bits would not.
    EXPECT_NE(problem("/proc/a.png", PathKind::Image).find("cannot write in the folder /proc"), std::string::npos)
        << problem("/proc/a.png", PathKind::Image);
    EXPECT_NE(problem(d, PathKind::AnyOutput).find("is a folder"), std::string::npos);
    EXPECT_EQ(problem(d + "/c.ckpt", PathKind::AnyOutput), "");
    EXPECT_NE(problem(d + "/rows.txt", PathKind::Csv).find(".csv"), std::string::npos);
    EXPECT_NE(problem(d + "/missing.exr", PathKind::Input).find("does not exist"), std::string::npos);
    for (const auto& e : std::filesystem::directory_iterator(d))
        ADD_FAILURE() << "the check left a file behind: " << e.path();
    ArgParser p = sample_parser();
    EXPECT_THROW(p.parse({"s", "-o", d + "/x.foo"}), UsageError) << "parse() checks the declared paths";
    std::filesystem::remove_all(d);
}
