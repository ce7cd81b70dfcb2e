#include "io/rays_file.h"

#include "core/errors.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace ht {

namespace {
std::vector<char> read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw SceneError(path + ": cannot open");
    return std::vector<char>((std::istreambuf_iterator<char>(f)), {});
}
template <typename T> T get(const char* b, size_t off) {
    T v;
    std::memcpy(&v, b + off, sizeof(T));
    return v;
}
constexpr uint32_t kRayBytes = 32, kHitBytes = 28, kOccludedBytes = 4;
}  // namespace

std::string RaysFile::set_name() const {
    return set == 0 ? "primary" : set == 1 ? "incoherent" : set == 2 ? "shadow" : "set" + std::to_string(set);
}

RaysFile read_rays_file(const std::string& path) {
    const std::vector<char> buf = read_all(path);
    const char* b = buf.data();
    if (buf.size() < 64 || std::memcmp(b, "HRAY", 4) != 0)
        throw SceneError(path + ": not a .rays file (magic HRAY missing)");
    if (get<uint32_t>(b, 4) != 1) throw SceneError(path + ": unsupported .rays version");
    RaysFile r;
    r.path = path;
    r.kind = get<uint32_t>(b, 8);
    r.set = get<uint32_t>(b, 12);
    const uint32_t n = get<uint32_t>(b, 16);
    const uint32_t ray_bytes = get<uint32_t>(b, 20), res_bytes = get<uint32_t>(b, 24);
    r.segments = get<uint32_t>(b, 28);
    r.strands = get<uint32_t>(b, 32);
    r.width = get<uint32_t>(b, 36);
    r.height = get<uint32_t>(b, 40);
    r.curve = get<uint32_t>(b, 44);
    r.scene_hash = get<uint64_t>(b, 48);
    r.scene.assign(b + 56, strnlen(b + 56, 8));
    std::memcpy(r.header.data(), b, r.header.size());
    if (ray_bytes != kRayBytes || (r.kind == 0 && res_bytes != kHitBytes) ||
        (r.kind == 1 && res_bytes != kOccludedBytes) || r.kind > 1)
        throw SceneError(path + ": unexpected record sizes / kind");
    const size_t need = 64 + (size_t)n * (kRayBytes + res_bytes);
    if (buf.size() != need)
        throw SceneError(path + ": size " + std::to_string(buf.size()) + " != expected " + std::to_string(need));
    r.rays.resize(n);
    std::memcpy(r.rays.data(), b + 64, (size_t)n * kRayBytes);
    if (r.kind == 0) {
        r.hits.resize(n);
        std::memcpy(r.hits.data(), b + 64 + (size_t)n * kRayBytes, (size_t)n * kHitBytes);
    } else {
        r.occluded.resize(n);
        std::memcpy(r.occluded.data(), b + 64 + (size_t)n * kRayBytes, (size_t)n * kOccludedBytes);
    }
    return r;
}

RaysHeader make_rays_header(uint32_t kind, uint32_t set, uint32_t count, uint32_t segments, uint32_t strands,
                            uint64_t scene_hash, const std::string& scene) {
    RaysHeader h{};
    auto put = [&](size_t off, uint32_t v) { std::memcpy(h.data() + off, &v, 4); };
    std::memcpy(h.data(), "HRAY", 4);
    put(4, 1);  // version
    put(8, kind);
    put(12, set);
    put(16, count);
    put(20, kRayBytes);
    put(24, kind == 0 ? kHitBytes : kOccludedBytes);
    put(28, segments);
    put(32, strands);
    std::memcpy(h.data() + 48, &scene_hash, 8);
    std::memcpy(h.data() + 56, scene.data(), std::min<size_t>(scene.size(), 8));
    return h;
}

void write_rays_file(const std::string& path, const RaysHeader& header, const std::vector<HtRay>& rays,
                     const std::vector<EmbreeHit>& hits, const std::vector<uint32_t>& occluded) {
    const uint32_t kind = get<uint32_t>(header.data(), 8), count = get<uint32_t>(header.data(), 16);
    const size_t n = rays.size(), answers = kind == 0 ? hits.size() : occluded.size();
    if (count != n)
        throw std::runtime_error(path + ": the header says " + std::to_string(count) + " rays, " + std::to_string(n) +
                                 " given");
    if (answers != n)
        throw std::runtime_error(path + ": " + std::to_string(answers) + " answers for " + std::to_string(n) + " rays");
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f.write(header.data(), std::streamsize(header.size()));
    f.write(reinterpret_cast<const char*>(rays.data()), std::streamsize(n * sizeof(HtRay)));
    if (kind == 0) f.write(reinterpret_cast<const char*>(hits.data()), std::streamsize(n * sizeof(EmbreeHit)));
    else f.write(reinterpret_cast<const char*>(occluded.data()), std::streamsize(n * sizeof(uint32_t)));
    if (!f) throw std::runtime_error(path + ": write failed");
}

}  // namespace ht
