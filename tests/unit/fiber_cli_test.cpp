// `hairtrace fiber ...` through fiber_main with string streams.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "cli/fiber_command.h"

namespace {
int run(const std::vector<std::string>& args, const std::string& in, std::string& out, std::string& err) {
    std::istringstream i(in);
    std::ostringstream o, e;
    int rc = ht::fiber_main(args, i, o, e);
    out = o.str();
    err = e.str();
    return rc;
}
std::vector<nlohmann::json> lines(const std::string& s) {
    std::vector<nlohmann::json> v;
    std::istringstream in(s);
    std::string l;
    while (std::getline(in, l)) v.push_back(nlohmann::json::parse(l));
    return v;
}
const char* kQuery =
    "{\"model\":\"chiang\",\"wo\":[0.3,0,0.9539392014169456],\"wi\":[-0.2,0.5,-0.8426149773176358],\"h\":0.1,"
    "\"eta\":1.55,\"sigma_a\":[0.2,0.4,0.8],\"beta_m\":0.3,\"beta_n\":0.3,\"alpha_deg\":2}\n";
}  // namespace

TEST(FiberCli, EvalWritesValuePdfLobesAndErrorsForBadLines) {
    std::string out, err;
    std::string in = std::string(kQuery) + "{\"model\":\"chiang\",\"wo\":[1,1,0],\"wi\":[0,0,1]}\nnot json\n" + kQuery;
    int rc = run({"fiber", "eval"}, in, out, err);
    EXPECT_EQ(rc, 2);
    auto v = lines(out);
    ASSERT_EQ(v.size(), 4u);
    EXPECT_EQ(v[0]["value"].size(), 3u);
    EXPECT_TRUE(v[0]["pdf"].is_number());
    for (const char* k : {"R", "TT", "TRT", "residual"}) EXPECT_EQ(v[0]["lobes"][k].size(), 3u);
    double sum = 0;
    for (const char* k : {"R", "TT", "TRT", "residual"}) sum += v[0]["lobes"][k][0].get<double>();
    EXPECT_NEAR(sum, v[0]["value"][0].get<double>(), 1e-12);
    EXPECT_TRUE(v[1].contains("error"));
    EXPECT_NE(v[1]["error"].get<std::string>().find("unit vector"), std::string::npos);
    EXPECT_TRUE(v[2].contains("error"));
    EXPECT_EQ(v[3], v[0]);
}

TEST(FiberCli, SampleFurnaceAfs) {
    std::string out, err;
    std::string q = kQuery;
    q.replace(q.find(",\"wi\":[-0.2,0.5,-0.8426149773176358]"), std::string(",\"wi\":[-0.2,0.5,-0.8426149773176358]").size(),
              ",\"u\":[0.1,0.5,0.3,0.7]");
    ASSERT_EQ(run({"sample"}, q, out, err), 0) << err;
    auto s = lines(out);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0]["wi"].size(), 3u);
    EXPECT_GT(s[0]["pdf"].get<double>(), 0);
    ASSERT_EQ(run({"furnace", "--model", "chiang", "--alpha-deg", "0", "--theta-deg", "0,60", "--nh", "4", "--json"}, "", out, err), 0) << err;
    auto f = nlohmann::json::parse(out);
    ASSERT_EQ(f["rows"].size(), 2u);
    EXPECT_NEAR(f["rows"][1]["albedo"][0].get<double>(), 1.0, 1e-3);
    ASSERT_EQ(run({"afs", "--eta", "1.55", "--sigma-a", "0.1", "--theta-deg", "0", "--json"}, "", out, err), 0) << err;
    auto a = nlohmann::json::parse(out);
    EXPECT_NEAR(a["TT"].get<double>(), 0.70666, 1e-5);
    EXPECT_EQ(run({"afs", "--eta", "0.5", "--sigma-a", "0.1", "--theta-deg", "0"}, "", out, err), 2);
    EXPECT_NE(err.find("--eta"), std::string::npos);
    EXPECT_EQ(run({"furnace", "--model", "chiang", "--beta-m", "7"}, "", out, err), 2);
    EXPECT_NE(err.find("beta_m"), std::string::npos);
    EXPECT_EQ(run({"bogus"}, "", out, err), 2);
}

TEST(FiberCli, HelpForEverySubcommandAndBadValuesNamed) {
    std::string out, err;
    EXPECT_EQ(run({"--help"}, "", out, err), 0);
    EXPECT_NE(out.find("furnace"), std::string::npos) << out;
    for (const char* sub : {"eval", "sample", "furnace", "afs"}) {
        EXPECT_EQ(run({sub, "--help"}, "", out, err), 0) << sub << ": " << err;
        EXPECT_NE(out.find(std::string("usage: hairtrace fiber ") + sub), std::string::npos) << out;
    }
    EXPECT_EQ(run({"eval", "--precision", "half"}, "", out, err), 2);
    EXPECT_NE(err.find("--precision must be double or float, got 'half'"), std::string::npos) << err;
    EXPECT_EQ(run({"furnace", "--model", "chiang", "--nh", "many"}, "", out, err), 2);
    EXPECT_NE(err.find("--nh expects an integer"), std::string::npos) << err;
    EXPECT_EQ(run({"afs", "--eta", "1.5", "--sigma-a", "0.1", "--theta", "0"}, "", out, err), 2);
    EXPECT_NE(err.find("did you mean --theta-deg?"), std::string::npos) << err;
    EXPECT_EQ(run({"evl"}, "", out, err), 2);
    EXPECT_NE(err.find("did you mean eval?"), std::string::npos) << err;
}
