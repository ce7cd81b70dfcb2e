#include "render/checkpoint.h"

#include "io/image_io.h"
#include "scene/scene.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <unistd.h>

namespace ht {

namespace {
constexpr char kMagic[4] = {'H', 'T', 'C', 'K'};
constexpr uint32_t kVersion = 1;

uint64_t fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ull) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) { h ^= p[i]; h *= 1099511628211ull; }
    return h;
}

struct Header {
    char magic[4];
    uint32_t version, width, height, seed, max_depth, samples_done, spp_target;
    uint64_t render_key, payload_hash;
};
}  // namespace

uint64_t hash_text(const std::string& s) { return fnv1a(s.data(), s.size()); }

void save_checkpoint(const std::string& path, const Checkpoint& c) {
    Header h{};
    std::memcpy(h.magic, kMagic, 4);
    h.version = kVersion;
    h.width = c.width;
    h.height = c.height;
    h.seed = c.seed;
    h.max_depth = c.max_depth;
    h.samples_done = c.samples_done;
    h.spp_target = c.spp_target;
    h.render_key = c.render_key;
    h.payload_hash = fnv1a(c.film.rgba.data(), c.film.rgba.size() * sizeof(float));
    std::string tmp = path + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw ImageError(path + ": cannot write checkpoint: " + std::strerror(errno));
    bool ok = std::fwrite(&h, sizeof h, 1, f) == 1 &&
              std::fwrite(c.film.rgba.data(), sizeof(float), c.film.rgba.size(), f) == c.film.rgba.size();
    ok = std::fflush(f) == 0 && ok;
    ok = ::fsync(fileno(f)) == 0 && ok;
    int err = errno;
    ok = std::fclose(f) == 0 && ok;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw ImageError(path + ": checkpoint write failed (" + std::strerror(err ? err : errno) +
                         "); the previous checkpoint, if any, is intact");
    }
}

Checkpoint load_checkpoint(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw SceneError(path + ": cannot open checkpoint");
    Header h{};
    if (!f.read(reinterpret_cast<char*>(&h), sizeof h)) throw SceneError(path + ": truncated checkpoint header");
    if (std::memcmp(h.magic, kMagic, 4) != 0) throw SceneError(path + ": not a hairtrace checkpoint");
    if (h.version != kVersion)
        throw SceneError(path + ": checkpoint version " + std::to_string(h.version) + " is not supported");
    if (h.width == 0 || h.height == 0 || h.width > 65536 || h.height > 65536)
        throw SceneError(path + ": checkpoint has an impossible image size");
    Checkpoint c;
    c.width = h.width;
    c.height = h.height;
    c.seed = h.seed;
    c.max_depth = h.max_depth;
    c.samples_done = h.samples_done;
    c.spp_target = h.spp_target;
    c.render_key = h.render_key;
    c.film.width = int(h.width);
    c.film.height = int(h.height);
    c.film.rgba.resize(4 * size_t(h.width) * h.height);
    if (!f.read(reinterpret_cast<char*>(c.film.rgba.data()), c.film.rgba.size() * sizeof(float)))
        throw SceneError(path + ": truncated checkpoint (film data missing)");
    if (fnv1a(c.film.rgba.data(), c.film.rgba.size() * sizeof(float)) != h.payload_hash)
        throw SceneError(path + ": checkpoint is corrupt (film checksum mismatch)");
    return c;
}

}  // namespace ht
