#include "split/checkpoint.h"

#include "core/errors.h"
#include "core/hash.h"
#include "kernels/aovs.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace ht {

namespace {
constexpr char kMagic[4] = {'H', 'T', 'C', 'K'};
// 2: a list of film segments (chunked accumulation) instead of one film.  Version 1 files held
// the plain sequential sum, which is not the chunked order once a render exceeds one chunk.
// 3: the render identity's five part digests instead of one key that left out the materials.
// 4: the lights digest hashes the environment as loaded (header and texels), not its file.
// 5: the AOV sums of render --aovs after each segment's film, and a sixth identity digest (the
// AOV list).
// 6: the even half films of render --target-error after each segment's AOV sums (4 floats per
// pixel when the header's even_sums says so), and --target-error in the settings digest.
constexpr uint32_t kVersion = 6;
constexpr uint32_t kMaxSegments = 1u << 20;

struct Header {
    char magic[4];
    uint32_t version, width, height, seed, max_depth, samples_done, spp_target;
    uint32_t chunk, range_first, range_end, rank, ranks, segment_count;
    uint32_t aov_sums, even_sums;  // per pixel; two fields keep the digests 8-byte aligned
    uint64_t identity[RenderIdentity::kPartCount], payload_hash;
};

struct SegmentHeader {
    uint32_t first, count;
};

// The payload checksum continued over one segment: its header, then its film's floats in file
// order, the (r, g, b, n) sums, the AOV sums and the even half.
uint64_t hash_segment(uint64_t hash, const SegmentHeader& sh, const Film& film) {
    hash = fnv1a(&sh, sizeof sh, hash);
    return fnv1a(film.even, fnv1a(film.aov, fnv1a(film.rgba, hash)));
}

bool write_floats(const std::vector<float>& v, FILE* f) {
    // an empty vector's data() may be null, which fwrite must not be given even for no items
    return v.empty() || std::fwrite(v.data(), sizeof(float), v.size(), f) == v.size();
}

bool read_floats(std::vector<float>& v, size_t count, std::ifstream& f) {
    v.resize(count);
    return count == 0 || f.read(reinterpret_cast<char*>(v.data()), std::streamsize(count * sizeof(float)));
}
}  // namespace

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
    h.chunk = c.chunk;
    h.range_first = c.range_first;
    h.range_end = c.range_end;
    h.rank = c.rank;
    h.ranks = c.ranks;
    h.segment_count = uint32_t(c.segments.size());
    h.aov_sums = c.aov_sums;
    h.even_sums = c.even_sums;
    for (int p = 0; p < RenderIdentity::kPartCount; ++p) h.identity[p] = c.identity.digests[p];
    const size_t pixels = size_t(c.width) * c.height;
    uint64_t hash = fnv1a(nullptr, 0);
    for (auto& s : c.segments) {
        if (s.film.rgba.size() != 4 * pixels || s.film.aov.size() != c.aov_sums * pixels ||
            s.film.even.size() != c.even_sums * pixels)
            throw std::invalid_argument("checkpoint segment film does not match the image size and AOV sums");
        hash = hash_segment(hash, SegmentHeader{uint32_t(s.first), uint32_t(s.count)}, s.film);
    }
    h.payload_hash = hash;
    std::string tmp = path + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw ImageError(path + ": cannot write checkpoint: " + std::strerror(errno));
    bool ok = std::fwrite(&h, sizeof h, 1, f) == 1;
    for (auto& s : c.segments) {
        SegmentHeader sh{uint32_t(s.first), uint32_t(s.count)};
        ok = ok && std::fwrite(&sh, sizeof sh, 1, f) == 1 && write_floats(s.film.rgba, f) &&
             write_floats(s.film.aov, f) && write_floats(s.film.even, f);
    }
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
    if (!f.read(reinterpret_cast<char*>(&h), 8)) throw SceneError(path + ": truncated checkpoint header");
    if (std::memcmp(h.magic, kMagic, 4) != 0) throw SceneError(path + ": not a hairtrace checkpoint");
    if (h.version != kVersion)
        throw SceneError(path + ": checkpoint version " + std::to_string(h.version) +
                         " is not supported (this build reads version " + std::to_string(kVersion) +
                         "): it was written by " + (h.version < kVersion ? "an older" : "a newer") +
                         " hairtrace; start the render again without --resume");
    if (!f.read(reinterpret_cast<char*>(&h) + 8, sizeof h - 8)) throw SceneError(path + ": truncated checkpoint header");
    if (h.width == 0 || h.height == 0 || h.width > 65536 || h.height > 65536)
        throw SceneError(path + ": checkpoint has an impossible image size");
    if (h.chunk == 0 || h.segment_count > kMaxSegments || h.ranks == 0 || h.rank >= h.ranks ||
        (h.aov_sums != 0 && h.aov_sums != HT_AOV_OUT) || (h.even_sums != 0 && h.even_sums != 4))
        throw SceneError(path + ": checkpoint header is corrupt");
    Checkpoint c;
    c.width = h.width;
    c.height = h.height;
    c.seed = h.seed;
    c.max_depth = h.max_depth;
    c.samples_done = h.samples_done;
    c.spp_target = h.spp_target;
    c.chunk = h.chunk;
    c.range_first = h.range_first;
    c.range_end = h.range_end;
    c.rank = h.rank;
    c.ranks = h.ranks;
    c.aov_sums = h.aov_sums;
    c.even_sums = h.even_sums;
    for (int p = 0; p < RenderIdentity::kPartCount; ++p) c.identity.digests[p] = h.identity[p];
    uint64_t hash = fnv1a(nullptr, 0);
    const size_t pixels = size_t(h.width) * h.height;
    for (uint32_t i = 0; i < h.segment_count; ++i) {
        SegmentHeader sh{};
        if (!f.read(reinterpret_cast<char*>(&sh), sizeof sh))
            throw SceneError(path + ": truncated checkpoint (segment " + std::to_string(i) + " missing)");
        FilmSegment s;
        s.first = int(sh.first);
        s.count = int(sh.count);
        s.film.width = int(h.width);
        s.film.height = int(h.height);
        if (!read_floats(s.film.rgba, 4 * pixels, f) || !read_floats(s.film.aov, h.aov_sums * pixels, f) ||
            !read_floats(s.film.even, h.even_sums * pixels, f))
            throw SceneError(path + ": truncated checkpoint (film data missing)");
        hash = hash_segment(hash, sh, s.film);
        c.segments.push_back(std::move(s));
    }
    if (hash != h.payload_hash) throw SceneError(path + ": checkpoint is corrupt (film checksum mismatch)");
    return c;
}

}  // namespace ht
