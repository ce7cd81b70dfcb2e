// Replays the fuzzing corpora through the scene loaders with the normal build: every file in
// tests/fuzz/regressions/<target>/ (crash reproducers found by tools/fuzz) and in
// tests/fuzz/corpus/<target>/ (the seeds) must either load a scene that honours the scene contract
// (tests/fuzz/scene_contract.h) or throw ht::SceneError.  Anything else (another exception, a
// crash, a sanitizer report in the HT_SANITIZE build) fails its own test case: one case per file,
// so gtest_discover_tests runs each in its own process and one crash does not hide the others.
//
// Inputs go through ht::load_scene exactly as the fuzz targets send them (tests/fuzz/fuzz_*.cpp):
// the file is copied to a scratch name whose extension picks the loader (.hair, .data, .ply, .obj, .pbrt; .glb when
// it starts with the GLB magic, else .gltf), and a builtin spec is "builtin:" + the file's text.
//
// The deep-nesting glTF reproducers are generated here instead of being stored (they are large
// but trivially regular): see DeepGltf below.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "tests/fuzz/fiber_contract.h"
#include "tests/fuzz/scene_contract.h"

namespace fs = std::filesystem;

namespace {

struct Case {
    std::string target;  // fuzz_hair_file, fuzz_usc_data, fuzz_gltf, fuzz_{ply,obj,pbrt}_file, fuzz_scene_builtin, fuzz_fiber_json
    fs::path file;
    std::string name;  // gtest-safe
};

// gtest prints the parameter of a failing case: the file, not a byte dump of the struct.
void PrintTo(const Case& c, std::ostream* os) { *os << c.file.string(); }

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<Case> collect_cases() {
    const fs::path root = fs::path(HT_SOURCE_DIR) / "tests" / "fuzz";
    std::vector<Case> cases;
    for (const char* kind : {"regressions", "corpus"}) {
        for (const char* target :
             {"fuzz_hair_file", "fuzz_usc_data", "fuzz_gltf", "fuzz_ply_file", "fuzz_obj_file", "fuzz_pbrt_file",
              "fuzz_scene_builtin", "fuzz_fiber_json"}) {
            const fs::path dir = root / kind / target;
            std::error_code ec;
            if (!fs::is_directory(dir, ec)) continue;
            for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
                if (!e.is_regular_file() || e.path().filename().string()[0] == '.') continue;
                std::string name = std::string(kind) + "_" + target + "_" + e.path().filename().string();
                for (char& c : name)
                    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                cases.push_back({target, e.path(), name});
            }
        }
    }
    std::sort(cases.begin(), cases.end(), [](const Case& a, const Case& b) { return a.name < b.name; });
    return cases;
}

// A scratch directory per test process (gtest_discover_tests runs cases in parallel processes),
// removed when the process ends: every run of the suite used to leave one per case in /tmp.
struct ScratchDir {
    fs::path path = fs::temp_directory_path() / ("hairtrace-fuzz-regressions-" + std::to_string(::getpid()));
    ScratchDir() { fs::create_directories(path); }
    ~ScratchDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};
fs::path scratch_dir() {
    static const ScratchDir dir;
    return dir.path;
}

// What load_scene did with the input: "" when it loaded a contract-honouring scene or threw
// SceneError, otherwise what went wrong.
std::string judge(const std::string& path) {
    try {
        const ht::Scene scene = ht::load_scene(path, ht_fuzz::fuzz_load_options());
        const std::string violation = ht_fuzz::scene_contract_violation(scene);
        return violation.empty() ? "" : "loaded a scene that breaks the contract: " + violation;
    } catch (const ht::SceneError&) {
        return "";
    } catch (const std::exception& e) {
        return std::string("threw a non-SceneError exception: ") + e.what();
    } catch (...) {
        return "threw a non-std exception";
    }
}

std::string write_scratch(const std::string& file_name, const std::string& bytes) {
    const fs::path p = scratch_dir() / file_name;
    std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), bytes.size());
    return p.string();
}

// Loads `bytes` as the fuzz target `target` would.
std::string judge_as_target(const std::string& target, const std::string& bytes) {
    if (target == "fuzz_scene_builtin") return judge("builtin:" + bytes);
    if (target == "fuzz_fiber_json")
        return ht_fuzz::judge_fiber_query(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    std::string name = "input.hair";
    if (target == "fuzz_usc_data") name = "input.data";
    if (target == "fuzz_ply_file") name = "input.ply";
    if (target == "fuzz_obj_file") name = "input.obj";
    if (target == "fuzz_pbrt_file") name = "input.pbrt";
    if (target == "fuzz_gltf")
        name = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0 ? "input.glb" : "input.gltf";
    return judge(write_scratch(name, bytes));
}

class FuzzRegression : public ::testing::TestWithParam<Case> {};

TEST_P(FuzzRegression, LoadsOrThrowsSceneError) {
    const Case& c = GetParam();
    const std::string problem = judge_as_target(c.target, read_bytes(c.file));
    EXPECT_EQ(problem, "") << c.file;
}

INSTANTIATE_TEST_SUITE_P(Corpus, FuzzRegression, ::testing::ValuesIn(collect_cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });
// The corpus directories always hold seeds; without them the suite above would silently be empty.
TEST(FuzzRegressionCorpus, IsNotEmpty) { EXPECT_GT(collect_cases().size(), 20u); }

// glTF nesting far deeper than any real file: the loader must refuse it with a SceneError (or
// load it) instead of overflowing the stack.  Measured with an 8 MiB stack and g++ -O2 before any
// fix: the node chain crashed from ~7,000 levels (a 130 KB file), the nested extras from ~17,500
// (35 KB); 100,000 leaves a wide margin for leaner frames and is still quick to parse.
constexpr int kDeep = 100000;

// Three points on a LINE_STRIP: the smallest valid hair, so nothing else stops the load early.
const char* kMinimalHairJsonTail =
    R"("meshes":[{"primitives":[{"mode":3,"attributes":{"POSITION":0}}]}],)"
    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
    R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
    R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
    R"(AAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAEAAAIA/"}]})";

// Finding: a node hierarchy thousands of levels deep (a chain, legal glTF) overflowed the stack in
// GltfSceneBuilder::visit (host/scene/gltf.cpp), which recurses once per level.
TEST(DeepGltf, NodeChainDoesNotOverflowTheStack) {
    std::string json = R"({"asset":{"version":"2.0"},"nodes":[)";
    for (int i = 0; i < kDeep; ++i) json += R"({"children":[)" + std::to_string(i + 1) + "]},";
    json += R"({"mesh":0}],)";
    json += kMinimalHairJsonTail;
    EXPECT_EQ(judge(write_scratch("deep_nodes.gltf", json)), "");
}

// Finding: extras nested some 20,000 arrays deep overflowed the stack in tinygltf's recursive
// ParseJsonAsValue (tiny_gltf.h 2.7.0), called by load_gltf for every extras/extensions value.
TEST(DeepGltf, NestedExtrasDoNotOverflowTheStack) {
    std::string json = R"({"asset":{"version":"2.0"},"nodes":[{"mesh":0}],"extras":)";
    json += std::string(kDeep, '[') + "1" + std::string(kDeep, ']') + ",";
    json += kMinimalHairJsonTail;
    EXPECT_EQ(judge(write_scratch("deep_extras.gltf", json)), "");
}

}  // namespace

namespace {

// A directory named like a scene is not a file: every loader must say so with a SceneError.
// Finding: BinaryFile and tinygltf take the size of a directory from seekg/tellg, which reports
// LLONG_MAX on Linux, so the .hair/.data loaders fail later with a misleading "read error ... was
// the file changed while loading?", load_glb with "GLB files of 4 GiB or more", and tinygltf's
// ReadWholeFile asks for a 9.2e18-byte buffer (std::bad_alloc, turned into a SceneError by
// load_gltf; under ASan the allocation itself aborts the process).
TEST(FuzzRegressionPaths, DirectoryNamedLikeASceneThrowsSceneError) {
    for (const char* name : {"dir.hair", "dir.data", "dir.gltf", "dir.glb"}) {
        const fs::path p = scratch_dir() / name;
        fs::create_directories(p);
        EXPECT_EQ(judge(p.string()), "") << name;
        EXPECT_THROW(ht::load_scene(p.string()), ht::SceneError) << name;
    }
}

}  // namespace
