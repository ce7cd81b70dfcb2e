// The start-node files `render --dump-rays` writes beside its closest-hit ray sets and `bench --rays`
// reads (bvh/start_nodes.h): a round trip, every lie a file can tell refused with exit 2 naming the
// file, and a file of another tree set aside; the node of every leaf entry.
#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "bvh/start_nodes.h"
#include "core/errors.h"
#include "random_strands.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;

struct StartNodes : ::testing::Test {
    fs::path dir = fs::temp_directory_path() / ("ht_starts_" + std::to_string(::getpid()));
    ht::SceneGeometry g = ht::build_geometry(httest::random_strands(5, 200, 10, 0.1, 0.01), {});
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
    std::string path(const char* name) const { return (dir / name).string(); }
    // The message of the SceneError that reading `file` throws ("" if none).
    std::string refusal(const std::string& file, size_t rays) const {
        try {
            ht::read_start_nodes(file, g, rays, nullptr);
        } catch (const ht::SceneError& e) {
            return e.what();
        }
        return "";
    }
};

// Every leaf entry is named by the one node whose leaf slot holds it, with and without oriented
// nodes (whose references carry HT_NODE_ORIENTED).
TEST_F(StartNodes, LeafEntryNodesNameTheNodeHoldingEachEntry) {
    ht::BvhOptions oriented;
    oriented.obb_ratio = 0.9f;
    for (const ht::BvhOptions& opt : {ht::BvhOptions{}, oriented}) {
        const ht::SceneGeometry t = ht::build_geometry(httest::random_strands(7, 300, 10, 0.1, 0.01), opt);
        const std::vector<uint32_t> node_of = ht::leaf_entry_nodes(t);
        ASSERT_EQ(node_of.size(), t.segments.size());
        std::vector<int> held(t.segments.size(), 0);
        size_t oriented_refs = 0;
        for (uint32_t ref : ht::start_node_refs(t)) {
            oriented_refs += (ref & HT_NODE_ORIENTED) != 0u;
            const HtBvhNode& n = t.nodes[ref & ~HT_NODE_ORIENTED];
            for (int k = 0; k < HT_BVH_WIDTH; ++k)
                for (uint32_t e = n.child[k]; n.count[k] > 0u && e < n.child[k] + n.count[k]; ++e) {
                    EXPECT_EQ(node_of[e], ref);
                    ++held[e];
                }
        }
        for (int h : held) EXPECT_EQ(h, 1);
        if (opt.obb_ratio > 0) {
            EXPECT_GT(oriented_refs, 0u);
        }
    }
}

TEST_F(StartNodes, RoundTripAndAbsentFile) {
    EXPECT_EQ(ht::start_nodes_path("d/strand.b2.closest.rays"), "d/strand.b2.closest.starts");
    const std::vector<uint32_t> refs = ht::start_node_refs(g);
    ASSERT_GT(refs.size(), 10u);
    std::vector<uint32_t> starts;
    for (size_t i = 0; i < 1000; ++i) starts.push_back(refs[(i * 7919) % refs.size()]);
    ht::write_start_nodes(path("a.starts"), g, starts);
    EXPECT_EQ(ht::read_start_nodes(path("a.starts"), g, starts.size(), nullptr), starts);
    EXPECT_TRUE(ht::read_start_nodes(path("absent.starts"), g, 5, nullptr).empty());
}

TEST_F(StartNodes, LiesAreRefusedNamingTheFile) {
    const std::vector<uint32_t> refs = ht::start_node_refs(g);
    const std::vector<uint32_t> starts(100, refs.back());
    ht::write_start_nodes(path("ok.starts"), g, starts);
    std::ifstream in(path("ok.starts"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto write = [&](const char* name, const std::string& b) {
        std::ofstream(path(name), std::ios::binary) << b;
        return path(name);
    };
    // the ray file has another count
    EXPECT_NE(refusal(path("ok.starts"), 99).find("100 start nodes for a ray file of 99"), std::string::npos);
    // truncated, and not one at all
    const std::string cut = write("cut.starts", bytes.substr(0, bytes.size() - 6));
    EXPECT_NE(refusal(cut, 100).find("cut.starts"), std::string::npos);
    EXPECT_NE(refusal(write("junk.starts", "HTSX0000000000000000000000000"), 100).find("no HTST header"),
              std::string::npos);
    // written for another tree: not used, and said why (a bench with other BVH options than the render's)
    const ht::SceneGeometry other = ht::build_geometry(httest::random_strands(6, 200, 10, 0.1, 0.01), {});
    ht::write_start_nodes(path("other.starts"), other, std::vector<uint32_t>(100, 0u));
    std::string why;
    EXPECT_TRUE(ht::read_start_nodes(path("other.starts"), g, 100, &why).empty());
    EXPECT_NE(why.find("another tree"), std::string::npos);
    // a reference that is no inner node (a leaf's first entry, an index past the array)
    std::string bad = bytes;
    const uint32_t no_node = uint32_t(g.nodes.size() + 5);
    std::memcpy(&bad[24 + 4 * 17], &no_node, 4);
    EXPECT_NE(refusal(write("bad.starts", bad), 100).find("ray 17 starts at"), std::string::npos);
}

}  // namespace
