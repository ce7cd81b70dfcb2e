#include "bench/rays_file.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace ht {

namespace {
std::vector<char> read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot open");
    return std::vector<char>((std::istreambuf_iterator<char>(f)), {});
}
template <typename T> T get(const std::vector<char>& b, size_t off) {
    T v;
    std::memcpy(&v, b.data() + off, sizeof(T));
    return v;
}
}  // namespace

std::string RaysFile::set_name() const {
    return set == 0 ? "primary" : set == 1 ? "incoherent" : set == 2 ? "shadow" : "set" + std::to_string(set);
}

RaysFile read_rays_file(const std::string& path) {
    const std::vector<char> b = read_all(path);
    if (b.size() < 64 || std::memcmp(b.data(), "HRAY", 4) != 0)
        throw std::runtime_error(path + ": not a .rays file (magic HRAY missing)");
    if (get<uint32_t>(b, 4) != 1) throw std::runtime_error(path + ": unsupported .rays version");
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
    r.scene.assign(b.data() + 56, strnlen(b.data() + 56, 8));
    std::memcpy(r.header.data(), b.data(), r.header.size());
    if (ray_bytes != 32 || (r.kind == 0 && res_bytes != 28) || (r.kind == 1 && res_bytes != 4) ||
        r.kind > 1)
        throw std::runtime_error(path + ": unexpected record sizes / kind");
    const size_t need = 64 + (size_t)n * (32 + res_bytes);
    if (b.size() != need)
        throw std::runtime_error(path + ": size " + std::to_string(b.size()) + " != expected " +
                                 std::to_string(need));
    r.rays.resize(n);
    std::memcpy(r.rays.data(), b.data() + 64, (size_t)n * 32);
    if (r.kind == 0) {
        r.hits.resize(n);
        std::memcpy(r.hits.data(), b.data() + 64 + (size_t)n * 32, (size_t)n * 28);
    } else {
        r.occluded.resize(n);
        std::memcpy(r.occluded.data(), b.data() + 64 + (size_t)n * 32, (size_t)n * 4);
    }
    return r;
}

void write_rays_file_answers(const RaysFile& source, const std::string& path, const std::vector<EmbreeHit>& hits,
                             const std::vector<uint32_t>& occluded) {
    const size_t n = source.rays.size(), answers = source.kind == 0 ? hits.size() : occluded.size();
    if (answers != n)
        throw std::runtime_error(path + ": " + std::to_string(answers) + " answers for " + std::to_string(n) + " rays");
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f.write(source.header.data(), std::streamsize(source.header.size()));
    f.write(reinterpret_cast<const char*>(source.rays.data()), std::streamsize(n * sizeof(HtRay)));
    if (source.kind == 0) f.write(reinterpret_cast<const char*>(hits.data()), std::streamsize(n * sizeof(EmbreeHit)));
    else f.write(reinterpret_cast<const char*>(occluded.data()), std::streamsize(n * sizeof(uint32_t)));
    if (!f) throw std::runtime_error(path + ": write failed");
}

Strands bench_read_hair_file(const std::string& path) {
    const std::vector<char> b = read_all(path);
    if (b.size() < 128 || std::memcmp(b.data(), "HAIR", 4) != 0)
        throw std::runtime_error(path + ": not a .hair file (signature HAIR missing)");
    const uint32_t hairs = get<uint32_t>(b, 4), npts = get<uint32_t>(b, 8);
    const uint32_t bits = get<uint32_t>(b, 12), def_segs = get<uint32_t>(b, 16);
    const float def_thick = get<float>(b, 20);
    size_t off = 128;
    auto need = [&](size_t bytes) {
        if (off + bytes > b.size()) throw std::runtime_error(path + ": truncated");
    };
    Strands s;
    s.first_point.reserve(hairs + 1);
    s.first_point.push_back(0);
    std::vector<uint16_t> segs;
    if (bits & 1) {
        need(2ull * hairs);
        segs.resize(hairs);
        std::memcpy(segs.data(), b.data() + off, 2ull * hairs);
        off += 2ull * hairs;
    }
    uint64_t total = 0;
    for (uint32_t h = 0; h < hairs; ++h) {
        total += (bits & 1 ? segs[h] : def_segs) + 1u;
        if (total > npts) throw std::runtime_error(path + ": segment counts exceed point count");
        s.first_point.push_back((uint32_t)total);
    }
    if (!(bits & 2)) throw std::runtime_error(path + ": no points array");
    need(12ull * npts);
    s.points.resize(npts);
    std::memcpy(s.points.data(), b.data() + off, 12ull * npts);
    off += 12ull * npts;
    s.radius.assign(npts, def_thick);
    if (bits & 4) {
        need(4ull * npts);
        std::memcpy(s.radius.data(), b.data() + off, 4ull * npts);
    }
    s.points.resize(total);
    s.radius.resize(total);
    s.material.assign(hairs, 0);
    return s;
}

}  // namespace ht
