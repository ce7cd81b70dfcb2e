// Helpers for the scene tests: a self-deleting temp directory and writers for .hair, USC .data
// and glTF test files built byte by byte (so malformed variants are easy to make).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace ht::test {

using Bytes = std::vector<unsigned char>;

class TempDir {
public:
    TempDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "ht_scene_XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

inline void write_file(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
}

inline void write_text(const std::string& path, const std::string& text) {
    write_file(path, Bytes(text.begin(), text.end()));
}

template <typename T>
void append(Bytes& b, const T& value) {
    const unsigned char* p = reinterpret_cast<const unsigned char*>(&value);
    b.insert(b.end(), p, p + sizeof(T));
}

// A .hair file of given strands (each a list of points) with any array flags; arrays whose flag
// is clear are left out and the header defaults are used instead.
struct HairSpec {
    std::vector<std::vector<Vec3f>> strands;
    uint32_t flags = 1 | 2 | 4;
    uint32_t default_segments = 0;
    float default_thickness = 0.1f;
    float thickness = 0.25f;               // written per point when flag 4 is set
    int64_t hair_count_override = -1;      // lie in the header
    int64_t point_count_override = -1;
};

inline Bytes make_hair_bytes(const HairSpec& spec) {
    uint32_t points = 0;
    for (const auto& s : spec.strands) points += static_cast<uint32_t>(s.size());
    Bytes b;
    b.insert(b.end(), {'H', 'A', 'I', 'R'});
    append(b, spec.hair_count_override >= 0 ? uint32_t(spec.hair_count_override)
                                            : uint32_t(spec.strands.size()));
    append(b, spec.point_count_override >= 0 ? uint32_t(spec.point_count_override) : points);
    append(b, spec.flags);
    append(b, spec.default_segments);
    append(b, spec.default_thickness);
    append(b, 0.0f);  // default transparency
    append(b, 0.9f), append(b, 0.75f), append(b, 0.5f);
    b.resize(128, 0);  // info
    if (spec.flags & 1)
        for (const auto& s : spec.strands) append(b, uint16_t(s.size() - 1));
    if (spec.flags & 2)
        for (const auto& s : spec.strands)
            for (const Vec3f& p : s) append(b, p);
    if (spec.flags & 4)
        for (uint32_t i = 0; i < points; ++i) append(b, spec.thickness + 0.001f * float(i));
    if (spec.flags & 8)
        for (uint32_t i = 0; i < points; ++i) append(b, 0.5f);
    if (spec.flags & 16)
        for (uint32_t i = 0; i < points; ++i) append(b, Vec3f{0.1f, 0.2f, 0.3f});
    return b;
}

inline Bytes make_usc_bytes(const std::vector<std::vector<Vec3f>>& strands) {
    Bytes b;
    append(b, int32_t(strands.size()));
    for (const auto& s : strands) {
        append(b, int32_t(s.size()));
        for (const Vec3f& p : s) append(b, p);
    }
    return b;
}

// Three small strands used across tests.
inline std::vector<std::vector<Vec3f>> three_strands() {
    return {{{0, 0, 0}, {0, 1, 0}, {0, 2, 0}},
            {{1, 0, 0}, {1, 1, 0}, {1, 2, 0}, {1, 3, 0}},
            {{2, 0, 0}, {2, -1, 0}}};
}

// Builds a glTF document with one binary buffer; accessors are appended as float / index data.
class GltfBuilder {
public:
    GltfBuilder() {
        doc["asset"] = {{"version", "2.0"}};
        doc["buffers"] = nlohmann::json::array();
        doc["bufferViews"] = nlohmann::json::array();
        doc["accessors"] = nlohmann::json::array();
        doc["meshes"] = nlohmann::json::array();
        doc["nodes"] = nlohmann::json::array();
        doc["scenes"] = {{{"nodes", nlohmann::json::array()}}};
        doc["scene"] = 0;
    }

    int add_vec3(const std::vector<Vec3f>& v) {
        Bytes bytes;
        for (const Vec3f& p : v) append(bytes, p);
        return add_accessor(bytes, "VEC3", 5126, v.size());
    }
    int add_scalar(const std::vector<float>& v) {
        Bytes bytes;
        for (float f : v) append(bytes, f);
        return add_accessor(bytes, "SCALAR", 5126, v.size());
    }
    int add_indices(const std::vector<uint16_t>& v) {
        Bytes bytes;
        for (uint16_t i : v) append(bytes, i);
        return add_accessor(bytes, "SCALAR", 5123, v.size());
    }
    int add_accessor(const Bytes& bytes, const char* type, int component, size_t count) {
        while (bin.size() % 4) bin.push_back(0);
        const size_t offset = bin.size();
        bin.insert(bin.end(), bytes.begin(), bytes.end());
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size()}});
        doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                    {"componentType", component}, {"count", count}, {"type", type}});
        return static_cast<int>(doc["accessors"].size() - 1);
    }
    // A mesh with one primitive; returns the mesh index.
    int add_mesh(int mode, int position, int radius = -1, int indices = -1, int material = -1) {
        nlohmann::json prim = {{"mode", mode}, {"attributes", {{"POSITION", position}}}};
        if (radius >= 0) prim["attributes"]["_RADIUS"] = radius;
        if (indices >= 0) prim["indices"] = indices;
        if (material >= 0) prim["material"] = material;
        doc["meshes"].push_back({{"primitives", {prim}}});
        return static_cast<int>(doc["meshes"].size() - 1);
    }
    // Adds a node (root of scene 0 unless it is made someone's child); returns its index.
    int add_node(nlohmann::json node, bool root = true) {
        doc["nodes"].push_back(std::move(node));
        const int index = static_cast<int>(doc["nodes"].size() - 1);
        if (root) doc["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    static std::string base64(const Bytes& data) {
        static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::string out;
        size_t i = 0;
        for (; i + 2 < data.size(); i += 3) {
            const uint32_t v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
            out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
        }
        if (i + 1 == data.size()) {
            const uint32_t v = data[i] << 16;
            out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
        } else if (i + 2 == data.size()) {
            const uint32_t v = (data[i] << 16) | (data[i + 1] << 8);
            out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
        }
        return out;
    }

    // .gltf with the buffer embedded as a data URI.
    std::string gltf_text() const {
        nlohmann::json d = doc;
        if (!bin.empty())
            d["buffers"] = {{{"byteLength", bin.size()},
                             {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
        return d.dump(1);
    }

    Bytes glb_bytes() const {
        nlohmann::json d = doc;
        Bytes padded_bin = bin;
        while (padded_bin.size() % 4) padded_bin.push_back(0);
        if (!bin.empty()) d["buffers"] = {{{"byteLength", bin.size()}}};
        std::string json = d.dump();
        while (json.size() % 4) json += ' ';
        Bytes b;
        b.insert(b.end(), {'g', 'l', 'T', 'F'});
        append(b, uint32_t(2));
        const uint32_t total = uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + padded_bin.size()));
        append(b, total);
        append(b, uint32_t(json.size()));
        append(b, uint32_t(0x4E4F534A));
        b.insert(b.end(), json.begin(), json.end());
        if (!bin.empty()) {
            append(b, uint32_t(padded_bin.size()));
            append(b, uint32_t(0x004E4942));
            b.insert(b.end(), padded_bin.begin(), padded_bin.end());
        }
        return b;
    }

    nlohmann::json doc;
    Bytes bin;
};

// Every SceneError must be a single line starting with the file name.
inline void expect_one_line_naming(const std::string& message, const std::string& file) {
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
}

// Runs f, expects a SceneError and returns its message ("" and a failure otherwise).
template <typename F>
std::string scene_error_of(F&& f) {
    try {
        f();
    } catch (const SceneError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected SceneError, got another exception: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected SceneError, nothing was thrown";
    return "";
}

inline bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

inline bool any_warning_contains(const Scene& s, const std::string& needle) {
    for (const std::string& w : s.warnings)
        if (contains(w, needle)) return true;
    return false;
}

// Writes `text` as the file `name` of a fresh temporary directory and loads it.
inline Scene load_text_scene(const std::string& name, const std::string& text, const LoadOptions& opt = {}) {
    TempDir dir;
    const std::string path = dir.file(name);
    write_text(path, text);
    return load_scene(path, opt);
}

// The file at `path`, holding `points` points, is refused under a 4 KiB memory limit (its counts
// checked before the strands are allocated) and loads without it.
inline void expect_refused_only_under_small_limit(const std::string& path, size_t points) {
    LoadOptions small;
    small.max_bytes = 4096;
    EXPECT_TRUE(contains(scene_error_of([&] { load_scene(path, small); }), "more than the limit")) << path;
    EXPECT_EQ(load_scene(path).strands.point_count(), points);
}

}  // namespace ht::test
