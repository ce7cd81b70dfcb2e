// Checkpoints of a progressive render: the raw float films (sums, not means; with --aovs the AOV
// sums too) of the samples done so far, in the canonical chunked order of split/accumulation.h,
// plus what is needed to continue.
// Because every sample's random numbers are a pure function of (seed, pixel, sample), continuing
// from a checkpoint gives the same bits as never stopping.
#pragma once

#include "render/render_identity.h"
#include "split/accumulation.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

struct Checkpoint {
    uint32_t width = 0, height = 0, seed = 0, max_depth = 0;
    uint32_t samples_done = 0, spp_target = 0;  // samples held in `segments`; --spp of the render
    uint32_t chunk = 0;                          // K of the chunk grid
    uint32_t range_first = 0, range_end = 0;     // the samples this process was asked for
    uint32_t rank = 0, ranks = 1;                // MPI: which rank wrote it, out of how many
    uint32_t aov_sums = 0;                       // per pixel in every segment's film (--aovs), or 0
    uint32_t even_sums = 0;                      // 4 with --target-error (Film::even), or 0
    RenderIdentity identity;  // everything else that shapes the image (scene, options)
    std::vector<FilmSegment> segments;  // sorted, disjoint; see SampleAccumulator
};

// Writes to PATH.tmp, flushes, then renames over PATH: a crash or full disk mid-write never
// leaves a corrupt checkpoint, and the previous one survives.  Throws ImageError on failure.
void save_checkpoint(const std::string& path, const Checkpoint& c);

// Throws SceneError (bad input, exit 2) when the file is missing, truncated, corrupt or written
// by a build with another checkpoint version.
Checkpoint load_checkpoint(const std::string& path);

}  // namespace ht
