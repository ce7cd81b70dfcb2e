// The canonical summation order that makes split renders exact.
//
// Floating-point addition is not associative, so "the same samples" summed in a different
// grouping gives different bits.  hairtrace therefore fixes ONE grouping for every render, and
// every way of executing it (one device, several devices, MPI ranks, render-farm parts merged
// later, checkpoint + resume) reproduces it exactly:
//
//   * the samples [0, spp) are cut into chunks of K samples (the last one may be shorter):
//     chunk j = [jK, min((j+1)K, spp));
//   * chunk j's film c_j is summed on one device, sample by sample in sample order, starting
//     from a zero film (what Renderer does with render_sample after upload_film(zeros));
//   * the image's film is the left fold of the chunk films in chunk order, in float32:
//         F = ((c_0 + c_1) + c_2) + ...      (per pixel and channel)
//
// Whatever executes a chunk, c_j has the same bits (random numbers are a pure function of
// (seed, pixel, sample, dimension)), and the fold is done here on the host in one fixed order.
// With K >= spp there is one chunk and the film is the plain sequential sum of earlier versions.
//
// A FilmSegment is either one chunk (possibly unfinished: the first `count` samples of it) or a
// "prefix": the fold of the complete chunks [0, jK).  Only a prefix may span several chunks,
// because only a fold that starts at chunk 0 can be continued by folding later chunks onto it;
// a range that starts elsewhere must keep its chunks apart until the merge.
#pragma once

#include "core/film.h"

#include <algorithm>

#include <string>
#include <utility>
#include <vector>

namespace ht {

struct ChunkGrid {
    int spp = 1;    // samples per pixel of the whole render
    int chunk = 1;  // K, samples per chunk

    int chunk_count() const { return (spp + chunk - 1) / chunk; }
    int chunk_of(int sample) const { return sample / chunk; }
    int begin(int j) const { return j * chunk; }
    int end(int j) const { return std::min((j + 1) * chunk, spp); }
    // True for the sample indices where a part of the render may start or end.
    bool boundary(int sample) const { return sample == spp || sample % chunk == 0; }
};

// Samples [first, end).
struct SampleRange {
    int first = 0, end = 0;
    int count() const { return end - first; }
};

// Parses "A:B" and checks 0 <= A < B <= spp and that A and B lie on the chunk grid; throws
// UsageError naming the option and the problem.
SampleRange parse_sample_range(const std::string& text, const ChunkGrid& grid);

struct FilmSegment {
    int first = 0, count = 0;  // samples [first, first + count)
    Film film;                 // raw sums (r, g, b, n; AOVs) of those samples in the canonical order
};

// Elementwise a += b: the one addition the canonical fold is made of.
void add_film(Film& a, const Film& b);

// The completed and unfinished work of one render (or of one part of it), kept in the
// canonical order.  Complete chunks that continue a prefix are folded into it as they arrive,
// so a render that starts at sample 0 holds one film plus the chunks that finished out of order.
class SampleAccumulator {
public:
    // aov_sums: the AOV sums per pixel every segment's film carries (HT_AOV_OUT with --aovs, else
    // 0), fixed for the render so that films with and without them are never mixed.
    SampleAccumulator(ChunkGrid grid, int width, int height, int aov_sums = 0);

    const ChunkGrid& grid() const { return grid_; }
    int width() const { return width_; }
    int height() const { return height_; }
    int aov_sums() const { return aov_sums_; }
    // Adds a chunk (complete or not) or a prefix.  Throws std::invalid_argument for a segment
    // off the grid, of the wrong size or AOV sums, or overlapping one already held.
    void add(FilmSegment s);
    const std::vector<FilmSegment>& segments() const { return segments_; }
    // Hands the segments over (sorted), leaving the accumulator empty.
    std::vector<FilmSegment> release() { return std::exchange(segments_, {}); }
    int samples() const;
    // True when the chunk is entirely inside a held segment.
    bool chunk_done(int j) const;
    // The unfinished segment of chunk j, or nullptr.
    const FilmSegment* unfinished(int j) const;
    // Removes and returns the unfinished segment of chunk j (to continue rendering it).
    FilmSegment take_unfinished(int j);
    // The chunks of `range` that are not done, in order.
    std::vector<int> pending_chunks(const SampleRange& range) const;
    // The fold of every held segment in sample order: the image (exact when the segments cover
    // [0, spp) completely; otherwise an unbiased estimate from the samples present).
    Film compose() const;
    // The fold of the segments that end at or before sample `end` (render --target-error decides
    // the next chunk from the chunks before it, render/adaptive.h).
    Film compose_before(int end) const;

private:
    void fold_prefix();
    bool complete(const FilmSegment& s) const;
    ChunkGrid grid_;
    int width_, height_, aov_sums_;
    std::vector<FilmSegment> segments_;  // sorted by first, disjoint
};

}  // namespace ht
