// Rendering across processes with MPI (optional at build time: -DHT_MPI=ON defines
// HT_HAVE_MPI).  `mpirun -np N hairtrace render ...` gives each rank a contiguous block of the
// render's chunks; afterwards the films travel once along the ranks in order (0 -> 1 -> ... ->
// N-1 -> 0), each rank folding its chunks onto the prefix it received.  That is the canonical
// chunk order of split/accumulation.h, so the image equals the one-process render bit for bit,
// and each rank sends one film (16 B per pixel; 120 B with --aovs, whose sums travel with it)
// when the render starts at sample 0.
#pragma once

#include "split/accumulation.h"

#include <string>
#include <vector>

namespace ht {

struct DistContext {
    int rank = 0, ranks = 1;
    bool mpi = false;  // MPI_Init was called (and MPI_Finalize is due)
};

// Initialises MPI when this process was started by an MPI launcher (mpirun, srun with PMI).
// In a build without MPI, a launch as one of several ranks is refused (UsageError) rather than
// letting every rank render and write the whole image.
DistContext dist_init();

// Ranks on this node, from the launcher's environment (1 when it does not say).
int local_rank_count();

// A warning when CPU binding leaves cores of this node idle: the CPUs this process may run on,
// times the ranks on the node, are fewer than the node has (Open MPI binds a rank to one core
// when it starts at most two, so `mpirun -np 1` renders on one core of many).  "" when fine.
std::string cpu_binding_warning(int local_ranks);
void dist_finalize(const DistContext& d);

// Ends every rank with `code` after an error on one of them (a rank that stops talking would
// leave the others waiting forever in the reduction).
[[noreturn]] void dist_abort(const DistContext& d, int code);

// The part of `range` (whole chunks, contiguous, in rank order) that rank `rank` renders.
SampleRange rank_range(const SampleRange& range, const ChunkGrid& grid, int rank, int ranks);

// What one rank did, for the cost model of docs/SCALING.md (tools/scaling-bench reads it).
struct RankReport {
    double samples = 0, render_seconds = 0, reduce_seconds = 0;
    double bytes_sent = 0, bytes_received = 0;  // film payload of the reduction (headers left out)
};

// Chain reduction in rank order.  On return rank 0's acc holds every rank's segments, folded in
// the canonical order; rank r's holds ranks 0..r.  Fills report->reduce_seconds with the time
// spent in the chain itself (after a barrier that absorbs the ranks' different render times)
// and the bytes this rank sent and received.
void reduce_to_rank0(const DistContext& d, SampleAccumulator& acc, RankReport* report);

// Every rank's report, on rank 0 (in rank order); other ranks get an empty list.
std::vector<RankReport> gather_reports(const DistContext& d, const RankReport& mine);

}  // namespace ht
