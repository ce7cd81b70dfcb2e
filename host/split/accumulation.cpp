#include "split/accumulation.h"

#include "core/errors.h"

#include <algorithm>
#include <stdexcept>

namespace ht {

SampleRange parse_sample_range(const std::string& text, const ChunkGrid& grid) {
    auto colon = text.find(':');
    auto number = [&](const std::string& t) {
        if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos || t.size() > 9)
            throw UsageError("--sample-range must be A:B with whole numbers, got '" + text + "'");
        return std::stoi(t);
    };
    if (colon == std::string::npos) throw UsageError("--sample-range must be A:B (samples A to B-1), got '" + text + "'");
    SampleRange r{number(text.substr(0, colon)), number(text.substr(colon + 1))};
    if (r.first >= r.end)
        throw UsageError("--sample-range " + text + ": A must be less than B (the range is [A, B))");
    if (r.end > grid.spp)
        throw UsageError("--sample-range " + text + ": B exceeds --spp " + std::to_string(grid.spp));
    for (int s : {r.first, r.end})
        if (!grid.boundary(s))
            throw UsageError("--sample-range " + text + ": " + std::to_string(s) + " is not a multiple of --chunk " +
                             std::to_string(grid.chunk) +
                             " (parts must consist of whole chunks for the merge to be exact)");
    return r;
}

namespace {
void add_sums(std::vector<float>& a, const std::vector<float>& b, const char* mismatch) {
    if (b.empty()) return;
    if (a.empty()) a.assign(b.size(), 0.0f);
    if (a.size() != b.size()) throw std::invalid_argument(mismatch);
    for (size_t i = 0; i < a.size(); ++i) a[i] += b[i];
}
}  // namespace

void add_film(Film& a, const Film& b) {
    if (a.rgba.size() != b.rgba.size()) throw std::invalid_argument("films of different sizes");
    // One IEEE float addition per element; no reassociation happens across elements.
    for (size_t i = 0; i < a.rgba.size(); ++i) a.rgba[i] += b.rgba[i];
    // AOV sums (render --aovs) and even halves (--target-error) the same way; a film without
    // them counts as zeros
    add_sums(a.aov, b.aov, "films with different AOVs");
    add_sums(a.even, b.even, "films with and without even halves");
}

SampleAccumulator::SampleAccumulator(ChunkGrid grid, int width, int height, int aov_sums)
    : grid_(grid), width_(width), height_(height), aov_sums_(aov_sums) {
    if (grid.chunk < 1 || grid.spp < 1) throw std::invalid_argument("chunk grid needs spp >= 1 and chunk >= 1");
}

bool SampleAccumulator::complete(const FilmSegment& s) const { return grid_.boundary(s.first + s.count); }

int SampleAccumulator::samples() const {
    int n = 0;
    for (auto& s : segments_) n += s.count;
    return n;
}

void SampleAccumulator::add(FilmSegment s) {
    const int K = grid_.chunk;
    if (s.count < 1 || s.first < 0 || s.first + s.count > grid_.spp)
        throw std::invalid_argument("segment [" + std::to_string(s.first) + ", " + std::to_string(s.first + s.count) +
                                    ") lies outside [0, " + std::to_string(grid_.spp) + ")");
    if (s.first % K != 0)
        throw std::invalid_argument("segment starting at sample " + std::to_string(s.first) +
                                    " is not on the chunk grid (chunk " + std::to_string(K) + ")");
    if (s.count > K && (s.first != 0 || s.count % K != 0))
        throw std::invalid_argument("segment [" + std::to_string(s.first) + ", " + std::to_string(s.first + s.count) +
                                    ") spans several chunks but is not a prefix of whole chunks");
    const size_t pixels = size_t(width_) * size_t(height_);
    if (s.film.width != width_ || s.film.height != height_ || s.film.rgba.size() != 4 * pixels)
        throw std::invalid_argument("segment film size does not match the image");
    if (s.film.aov.size() != size_t(aov_sums_) * pixels)
        throw std::invalid_argument("segment film has " + std::to_string(s.film.aov.size() / pixels) +
                                    " AOV sums per pixel, the render " + std::to_string(aov_sums_));
    auto it = std::lower_bound(segments_.begin(), segments_.end(), s.first,
                               [](const FilmSegment& a, int f) { return a.first < f; });
    if ((it != segments_.end() && it->first < s.first + s.count) ||
        (it != segments_.begin() && std::prev(it)->first + std::prev(it)->count > s.first))
        throw std::invalid_argument("segment [" + std::to_string(s.first) + ", " + std::to_string(s.first + s.count) +
                                    ") overlaps samples already accumulated");
    segments_.insert(it, std::move(s));
    fold_prefix();
}

// Folds full chunks onto a prefix that starts at sample 0.  A chunk cut short by the end of the
// render (spp not a multiple of K) stays separate: a later resume with a larger --spp continues
// that chunk, which would be impossible once it is folded in.
void SampleAccumulator::fold_prefix() {
    const int K = grid_.chunk;
    while (segments_.size() >= 2) {
        FilmSegment& p = segments_[0];
        FilmSegment& c = segments_[1];
        if (p.first != 0 || p.count % K != 0 || c.first != p.count || c.count != K) return;
        add_film(p.film, c.film);
        p.count += c.count;
        segments_.erase(segments_.begin() + 1);
    }
}

bool SampleAccumulator::chunk_done(int j) const {
    for (auto& s : segments_)
        if (s.first <= grid_.begin(j) && s.first + s.count >= grid_.end(j)) return true;
    return false;
}

const FilmSegment* SampleAccumulator::unfinished(int j) const {
    for (auto& s : segments_)
        if (s.first == grid_.begin(j) && s.first + s.count < grid_.end(j)) return &s;
    return nullptr;
}

FilmSegment SampleAccumulator::take_unfinished(int j) {
    for (auto it = segments_.begin(); it != segments_.end(); ++it)
        if (it->first == grid_.begin(j) && it->first + it->count < grid_.end(j)) {
            FilmSegment s = std::move(*it);
            segments_.erase(it);
            return s;
        }
    throw std::invalid_argument("chunk " + std::to_string(j) + " has no unfinished segment");
}

std::vector<int> SampleAccumulator::pending_chunks(const SampleRange& range) const {
    std::vector<int> out;
    if (range.count() <= 0) return out;
    for (int j = grid_.chunk_of(range.first); j <= grid_.chunk_of(range.end - 1); ++j)
        if (!chunk_done(j)) out.push_back(j);
    return out;
}

Film SampleAccumulator::compose() const { return compose_before(grid_.spp); }

Film SampleAccumulator::compose_before(int end) const {
    Film f;
    f.width = width_;
    f.height = height_;
    f.rgba.assign(4 * size_t(width_) * size_t(height_), 0.0f);
    f.aov.assign(size_t(aov_sums_) * size_t(width_) * size_t(height_), 0.0f);
    bool first = true;
    for (const FilmSegment& s : segments_) {
        if (s.first + s.count > end) continue;
        // the first segment is copied, not added to zeros, so that the fold keeps its bits
        if (first) f = s.film;
        else add_film(f, s.film);
        first = false;
    }
    return f;
}

}  // namespace ht
