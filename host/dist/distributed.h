// Rendering across processes with MPI (optional at build time: -DHT_MPI=ON defines
// HT_HAVE_MPI).  `mpirun -np N hairtrace render ...` gives each rank a contiguous block of the
// render's chunks; afterwards the films travel once along the ranks in order (0 -> 1 -> ... ->
// N-1 -> 0), each rank folding its chunks onto the prefix it received.  That is the canonical
// chunk order of dist/accumulation.h, so the image equals the one-process render bit for bit,
// and each rank sends one film (16 B per pixel) when the render starts at sample 0.
#pragma once

#include "dist/accumulation.h"

#include <string>

namespace ht {

struct DistContext {
    int rank = 0, ranks = 1;
    bool mpi = false;  // MPI_Init was called (and MPI_Finalize is due)
};

// Initialises MPI when this process was started by an MPI launcher (mpirun, srun with PMI).
// In a build without MPI, a launch as one of several ranks is refused (UsageError) rather than
// letting every rank render and write the whole image.
DistContext dist_init();
void dist_finalize(const DistContext& d);

// Ends every rank with `code` after an error on one of them (a rank that stops talking would
// leave the others waiting forever in the reduction).
[[noreturn]] void dist_abort(const DistContext& d, int code);

// The part of `range` (whole chunks, contiguous, in rank order) that rank `rank` renders.
SampleRange rank_range(const SampleRange& range, const ChunkGrid& grid, int rank, int ranks);

// Chain reduction in rank order.  On return rank 0's acc holds every rank's segments, folded in
// the canonical order; rank r's holds ranks 0..r.  Returns the seconds spent in
// the chain itself (after a barrier that absorbs the ranks' different render times).
double reduce_to_rank0(const DistContext& d, SampleAccumulator& acc);

}  // namespace ht
