#include "split/distributed.h"

#include "core/errors.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#ifdef HT_HAVE_MPI
#include <mpi.h>
#endif
#ifdef __linux__
#include <sched.h>
#include <unistd.h>
#endif

namespace ht {

namespace {
// Environment variables the common launchers set for every rank they start.
int launcher_world_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS", "SLURM_NTASKS"}) {
        // SLURM_NTASKS is set for plain sbatch scripts too; only trust it under srun (SLURM_STEP_ID).
        if (std::strcmp(v, "SLURM_NTASKS") == 0 && !std::getenv("SLURM_STEP_ID")) continue;
        if (const char* s = std::getenv(v)) return std::atoi(s);
    }
    return std::getenv("PMIX_RANK") ? 1 : 0;  // PMIx without a size: initialise, the size comes from MPI
}
}  // namespace

std::string cpu_binding_warning(int local_ranks) {
#ifdef __linux__
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return "";
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    const int allowed = CPU_COUNT(&set);
    if (online <= 0 || local_ranks < 1 || allowed * long(local_ranks) >= online) return "";
    return "this rank may use " + std::to_string(allowed) + " of the node's " + std::to_string(online) +
           " CPUs (the launcher's CPU binding) and " + std::to_string(local_ranks) +
           " rank(s) run on this node, so " + std::to_string(online - allowed * long(local_ranks)) +
           " CPUs stay idle; with one rank per node run `mpirun --bind-to none` (Slurm: --cpu-bind=none)";
#else
    (void)local_ranks;
    return "";
#endif
}

int local_rank_count() {
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "SLURM_NTASKS_PER_NODE"})
        if (const char* s = std::getenv(v)) {
            const int n = std::atoi(s);
            if (n > 0) return n;
        }
    return 1;
}

SampleRange rank_range(const SampleRange& range, const ChunkGrid& grid, int rank, int ranks) {
    const int c0 = grid.chunk_of(range.first);
    const int c1 = grid.chunk_of(range.end - 1) + 1;  // chunks [c0, c1)
    const long n = c1 - c0;
    const int a = c0 + int(n * rank / ranks), b = c0 + int(n * (rank + 1) / ranks);
    SampleRange r{std::max(range.first, grid.begin(a)), std::min(range.end, grid.begin(b))};
    if (a == b) r = {range.end, range.end};  // more ranks than chunks: this rank idles
    return r;
}

#ifdef HT_HAVE_MPI

DistContext dist_init() {
    DistContext d;
    if (launcher_world_size() < 1) return d;
    int provided = 0;
    // Only the calling thread talks MPI; device threads never do.
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &d.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &d.ranks);
    d.mpi = true;
    return d;
}

void dist_finalize(const DistContext& d) {
    if (d.mpi) MPI_Finalize();
}

void dist_abort(const DistContext& d, int code) {
    if (d.mpi) MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
}

namespace {
constexpr int kTagCount = 17, kTagHeader = 18, kTagFilm = 19, kTagAovs = 20;

double payload(const std::vector<FilmSegment>& segs) {
    double b = 0;
    for (auto& s : segs) b += double(s.film.rgba.size() + s.film.aov.size()) * sizeof(float);
    return b;
}

// Every rank runs the same command line, so sender and receiver agree on the AOV sums per pixel
// (the accumulator's): only the floats travel.
double send_segments(const std::vector<FilmSegment>& segs, int to) {
    int n = int(segs.size());
    MPI_Send(&n, 1, MPI_INT, to, kTagCount, MPI_COMM_WORLD);
    for (auto& s : segs) {
        int h[2] = {s.first, s.count};
        MPI_Send(h, 2, MPI_INT, to, kTagHeader, MPI_COMM_WORLD);
        MPI_Send(s.film.rgba.data(), int(s.film.rgba.size()), MPI_FLOAT, to, kTagFilm, MPI_COMM_WORLD);
        if (!s.film.aov.empty())
            MPI_Send(s.film.aov.data(), int(s.film.aov.size()), MPI_FLOAT, to, kTagAovs, MPI_COMM_WORLD);
    }
    return payload(segs);
}

std::vector<FilmSegment> recv_segments(int from, const SampleAccumulator& acc) {
    const size_t pixels = size_t(acc.width()) * size_t(acc.height());
    int n = 0;
    MPI_Recv(&n, 1, MPI_INT, from, kTagCount, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    std::vector<FilmSegment> out(size_t(std::max(n, 0)));
    for (auto& s : out) {
        int h[2];
        MPI_Recv(h, 2, MPI_INT, from, kTagHeader, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        s.first = h[0];
        s.count = h[1];
        s.film.width = acc.width();
        s.film.height = acc.height();
        s.film.rgba.resize(4 * pixels);
        MPI_Recv(s.film.rgba.data(), int(s.film.rgba.size()), MPI_FLOAT, from, kTagFilm, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        s.film.aov.resize(size_t(acc.aov_sums()) * pixels);
        if (!s.film.aov.empty())
            MPI_Recv(s.film.aov.data(), int(s.film.aov.size()), MPI_FLOAT, from, kTagAovs, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
    }
    return out;
}
}  // namespace

void reduce_to_rank0(const DistContext& d, SampleAccumulator& acc, RankReport* report) {
    if (d.ranks == 1) return;
    // Wait for the slowest rank first, so the time returned is the reduction alone and not the
    // load imbalance of the render (which the caller sees in its own render time).
    MPI_Barrier(MPI_COMM_WORLD);
    const auto t0 = std::chrono::steady_clock::now();
    // A chain rather than a tree: folding chunk films onto a prefix is only exact in sample
    // order, so rank r can add its chunks only after ranks 0..r-1 have added theirs.  Each rank
    // still sends a single film when the render starts at sample 0 (its prefix), and the
    // rendering itself ran fully in parallel before this.
    double sent = 0, received = 0;
    if (d.rank == 0) {
        sent = send_segments(acc.segments(), 1);
        SampleAccumulator all(acc.grid(), acc.width(), acc.height(), acc.aov_sums());
        auto in = recv_segments(d.ranks - 1, acc);
        received = payload(in);
        for (auto& s : in) all.add(std::move(s));
        acc = std::move(all);
    } else {
        SampleAccumulator merged(acc.grid(), acc.width(), acc.height(), acc.aov_sums());
        auto in = recv_segments(d.rank - 1, acc);
        received = payload(in);
        for (auto& s : in) merged.add(std::move(s));
        for (auto& s : acc.release()) merged.add(std::move(s));
        sent = send_segments(merged.segments(), d.rank + 1 == d.ranks ? 0 : d.rank + 1);
        acc = std::move(merged);
    }
    if (report) {
        report->reduce_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        report->bytes_sent = sent;
        report->bytes_received = received;
    }
}

std::vector<RankReport> gather_reports(const DistContext& d, const RankReport& mine) {
    if (d.ranks == 1) return {mine};
    const double v[5] = {mine.samples, mine.render_seconds, mine.reduce_seconds, mine.bytes_sent, mine.bytes_received};
    std::vector<double> all(d.rank == 0 ? 5 * size_t(d.ranks) : 0);
    MPI_Gather(v, 5, MPI_DOUBLE, all.data(), 5, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    std::vector<RankReport> out;
    for (size_t r = 0; r < all.size() / 5; ++r)
        out.push_back({all[5 * r], all[5 * r + 1], all[5 * r + 2], all[5 * r + 3], all[5 * r + 4]});
    return out;
}

#else  // no MPI in this build

DistContext dist_init() {
    if (launcher_world_size() > 1)
        throw UsageError("this hairtrace was built without MPI, but it was started as one of several MPI ranks; "
                         "rebuild with -DHT_MPI=ON (needs libopenmpi-dev) or run a single process");
    return DistContext{};
}
void dist_finalize(const DistContext&) {}
void dist_abort(const DistContext&, int code) { std::exit(code); }
void reduce_to_rank0(const DistContext&, SampleAccumulator&, RankReport*) {}
std::vector<RankReport> gather_reports(const DistContext&, const RankReport& mine) { return {mine}; }

#endif

}  // namespace ht
