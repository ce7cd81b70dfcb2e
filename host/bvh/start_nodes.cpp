#include "bvh/start_nodes.h"

#include "core/errors.h"
#include "core/hash.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <unordered_set>

namespace ht {

namespace {
constexpr char kMagic[4] = {'H', 'T', 'S', 'T'};
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = 24;
}  // namespace

std::vector<uint32_t> leaf_entry_nodes(const SceneGeometry& geometry) {
    std::vector<uint32_t> node(geometry.segments.size(), 0u);
    if (geometry.nodes.empty()) return node;
    std::vector<uint32_t> todo{0u};  // references still to visit
    while (!todo.empty()) {
        const uint32_t ref = todo.back();
        todo.pop_back();
        const HtBvhNode& n = geometry.nodes[ref & ~HT_NODE_ORIENTED];
        for (int k = 0; k < HT_BVH_WIDTH; ++k) {
            if (n.count[k] > 0u)
                std::fill(node.begin() + n.child[k], node.begin() + n.child[k] + n.count[k], ref);
            else if (n.child[k] != 0u)
                todo.push_back(n.child[k]);
        }
    }
    return node;
}

std::vector<uint32_t> start_node_refs(const SceneGeometry& geometry) {
    std::vector<uint32_t> refs{0u};
    for (const HtBvhNode& n : geometry.nodes)
        for (int k = 0; k < HT_BVH_WIDTH; ++k)
            if (n.count[k] == 0u && n.child[k] != 0u) refs.push_back(n.child[k]);
    return refs;
}

std::string start_nodes_path(const std::string& rays_path) {
    std::filesystem::path p(rays_path);
    return p.replace_extension(".starts").string();
}

uint64_t tree_hash(const SceneGeometry& geometry) { return fnv1a(geometry.nodes); }

void write_start_nodes(const std::string& path, const SceneGeometry& geometry, const std::vector<uint32_t>& starts) {
    unsigned char head[kHeaderBytes] = {};
    const uint32_t words[3] = {kVersion, uint32_t(starts.size()), uint32_t(geometry.nodes.size())};
    const uint64_t hash = tree_hash(geometry);
    std::memcpy(head, kMagic, 4);
    std::memcpy(head + 4, words, sizeof words);
    std::memcpy(head + 16, &hash, 8);
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("--dump-rays: cannot write " + path);
    f.write(reinterpret_cast<const char*>(head), sizeof head);
    f.write(reinterpret_cast<const char*>(starts.data()), std::streamsize(starts.size() * sizeof(uint32_t)));
    if (!f) throw std::runtime_error("--dump-rays: write failed: " + path);
}

std::vector<uint32_t> read_start_nodes(const std::string& path, const SceneGeometry& geometry, size_t rays,
                                       std::string* other_tree) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return {};
    const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto bad = [&](const std::string& why) { return SceneError(path + ": " + why); };
    if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, 4) != 0)
        throw bad("not a start-node file (no HTST header)");
    uint32_t words[3];
    uint64_t hash;
    std::memcpy(words, bytes.data() + 4, sizeof words);
    std::memcpy(&hash, bytes.data() + 16, 8);
    if (words[0] != kVersion) throw bad("version " + std::to_string(words[0]) + ", this build reads 1");
    if (words[1] != rays)
        throw bad("holds " + std::to_string(words[1]) + " start nodes for a ray file of " + std::to_string(rays) + " rays");
    if (bytes.size() != kHeaderBytes + size_t(words[1]) * sizeof(uint32_t))
        throw bad("is " + std::to_string(bytes.size()) + " bytes, its header says " +
                  std::to_string(kHeaderBytes + size_t(words[1]) * sizeof(uint32_t)));
    if (words[2] != geometry.nodes.size() || hash != tree_hash(geometry)) {
        if (other_tree)
            *other_tree = path + " was written for another tree (" + std::to_string(words[2]) +
                          " node records, this one has " + std::to_string(geometry.nodes.size()) +
                          "): the render's BVH options give its tree";
        return {};
    }
    std::vector<uint32_t> starts(rays);
    std::memcpy(starts.data(), bytes.data() + kHeaderBytes, rays * sizeof(uint32_t));
    const std::vector<uint32_t> refs = start_node_refs(geometry);
    const std::unordered_set<uint32_t> inner(refs.begin(), refs.end());
    for (size_t i = 0; i < rays; ++i)
        if (!inner.count(starts[i]))
            throw bad("ray " + std::to_string(i) + " starts at " + std::to_string(starts[i]) +
                      ", which is no inner node of this tree");
    return starts;
}

}  // namespace ht
