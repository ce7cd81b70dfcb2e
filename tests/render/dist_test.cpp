// Splitting a render: chunked accumulation, render-farm parts + merge, several devices, MPI.
// The promise under test is bit-for-bit equality with the one-process render of the same
// --spp, --chunk and --seed, whatever the split.
#include "split/accumulation.h"
#include "split/distributed.h"
#include "io/image_io.h"
#include "cli/args.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace ht;
using clitest::TempDir;
using clitest::run;
using clitest::slurp;
using clitest::image;

namespace {
Film random_film(std::mt19937& rng, int w, int h, int samples) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Film f;
    f.width = w;
    f.height = h;
    f.rgba.resize(4 * size_t(w) * h);
    for (size_t i = 0; i < f.rgba.size(); ++i) f.rgba[i] = (i % 4 == 3) ? float(samples) : u(rng) * 1000.0f * u(rng);
    return f;
}

}  // namespace

TEST(Accumulation, FoldIsIndependentOfArrivalOrder) {
    std::mt19937 rng(3);
    const ChunkGrid grid{22, 4};  // chunks of 4, the last one has 2 samples
    std::vector<FilmSegment> chunks;
    for (int j = 0; j < grid.chunk_count(); ++j)
        chunks.push_back({grid.begin(j), grid.end(j) - grid.begin(j), random_film(rng, 5, 3, grid.end(j) - grid.begin(j))});
    // The canonical order written out by hand: ((c0 + c1) + c2) + ...
    Film expect = chunks[0].film;
    for (size_t j = 1; j < chunks.size(); ++j)
        for (size_t i = 0; i < expect.rgba.size(); ++i) expect.rgba[i] = expect.rgba[i] + chunks[j].film.rgba[i];
    std::vector<size_t> order(chunks.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (int trial = 0; trial < 20; ++trial) {
        std::shuffle(order.begin(), order.end(), rng);
        SampleAccumulator acc(grid, 5, 3);
        for (size_t i : order) acc.add(chunks[i]);
        EXPECT_EQ(acc.samples(), 22);
        // full chunks fold into one prefix; the short last chunk stays apart (resumable)
        EXPECT_EQ(acc.segments().size(), 2u);
        EXPECT_EQ(acc.compose().rgba, expect.rgba);
    }
}

TEST(Accumulation, RejectsSegmentsOffTheGridOrOverlapping) {
    std::mt19937 rng(1);
    const ChunkGrid grid{16, 4};
    SampleAccumulator acc(grid, 2, 2);
    acc.add({4, 4, random_film(rng, 2, 2, 4)});
    EXPECT_THROW(acc.add({2, 2, random_film(rng, 2, 2, 2)}), std::invalid_argument);   // off the grid
    EXPECT_THROW(acc.add({4, 2, random_film(rng, 2, 2, 2)}), std::invalid_argument);   // overlaps
    EXPECT_THROW(acc.add({8, 8, random_film(rng, 2, 2, 8)}), std::invalid_argument);   // not a prefix
    EXPECT_THROW(acc.add({12, 8, random_film(rng, 2, 2, 8)}), std::invalid_argument);  // past spp
    acc.add({8, 3, random_film(rng, 2, 2, 3)});                                        // unfinished chunk 2
    EXPECT_EQ(acc.pending_chunks({0, 16}), (std::vector<int>{0, 2, 3}));
    ASSERT_NE(acc.unfinished(2), nullptr);
    EXPECT_EQ(acc.take_unfinished(2).count, 3);
}

TEST(Accumulation, AovSumsFoldLikeTheBeautyAndAreNeverMixed) {
    std::mt19937 rng(5);
    const ChunkGrid grid{8, 4};
    SampleAccumulator acc(grid, 3, 2, 2);  // two AOV sums per pixel
    EXPECT_EQ(acc.compose().aov, std::vector<float>(12, 0.0f));  // no samples yet: zeros, not none
    Film a = random_film(rng, 3, 2, 4), b = random_film(rng, 3, 2, 4);
    EXPECT_THROW(acc.add({0, 4, a}), std::invalid_argument);  // a film without them
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    for (Film* f : {&a, &b})
        for (int i = 0; i < 12; ++i) f->aov.push_back(u(rng));
    std::vector<float> expect(12);
    for (size_t i = 0; i < expect.size(); ++i) expect[i] = a.aov[i] + b.aov[i];
    acc.add({4, 4, b});
    acc.add({0, 4, a});
    ASSERT_EQ(acc.segments().size(), 1u);  // folded into one prefix
    EXPECT_EQ(acc.compose().aov, expect);
}

TEST(Accumulation, SampleRangeValidation) {
    const ChunkGrid grid{16, 4};
    EXPECT_EQ(parse_sample_range("4:12", grid).count(), 8);
    EXPECT_EQ(parse_sample_range("12:16", grid).count(), 4);
    EXPECT_THROW(parse_sample_range("8:4", grid), UsageError);    // A < B
    EXPECT_THROW(parse_sample_range("4:4", grid), UsageError);    // empty
    EXPECT_THROW(parse_sample_range("0:20", grid), UsageError);   // beyond spp
    EXPECT_THROW(parse_sample_range("2:8", grid), UsageError);    // off the chunk grid
    EXPECT_THROW(parse_sample_range("-1:8", grid), UsageError);
    EXPECT_THROW(parse_sample_range("8", grid), UsageError);
    EXPECT_EQ(parse_sample_range("12:14", ChunkGrid{14, 4}).count(), 2);  // B = spp may be off the grid
}

TEST(Accumulation, RankRangesAreContiguousWholeChunks) {
    const ChunkGrid grid{18, 4};  // 5 chunks
    for (int ranks : {1, 2, 3, 4, 7}) {
        int next = 0;
        for (int r = 0; r < ranks; ++r) {
            SampleRange s = rank_range({0, 18}, grid, r, ranks);
            if (s.count() == 0) continue;
            EXPECT_EQ(s.first, next);
            EXPECT_TRUE(grid.boundary(s.first) && grid.boundary(s.end));
            next = s.end;
        }
        EXPECT_EQ(next, 18) << ranks << " ranks";
    }
}

#ifdef HT_BINARY
namespace {
const std::string kScene = " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3 --quiet";
const std::string kRender = std::string(HT_BINARY) + kScene + " --seed 9";

}  // namespace

TEST(RenderFarm, MergeOfFourPartsEqualsTheFullRender) {
    TempDir d("ht_dist_");
    const std::string opts = " --spp 16 --chunk 4";
    ASSERT_EQ(run(kRender + opts + " -o " + (d / "full.exr")), 0);
    for (int i = 0; i < 4; ++i)
        ASSERT_EQ(run(kRender + opts + " --sample-range " + std::to_string(4 * i) + ":" + std::to_string(4 * i + 4) +
                      " -o " + (d / ("p" + std::to_string(i) + ".exr"))), 0);
    // parts given in any order
    ASSERT_EQ(run(std::string(HT_BINARY) + " merge " + (d / "p2.exr") + " " + (d / "p0.exr") + " " + (d / "p3.exr") +
                  " " + (d / "p1.exr") + " -o " + (d / "merged.exr") + " -o " + (d / "merged.png") + " --quiet"), 0);
    auto full = image(d / "full.exr");
    EXPECT_EQ(full, image(d / "merged.exr"));
    EXPECT_TRUE(fs::exists(d / "merged.png"));
    // uneven parts, some spanning several chunks, with the default chunk size of the full render
    ASSERT_EQ(run(kRender + " --spp 40 -o " + (d / "full40.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 40 --sample-range 0:32 -o " + (d / "a.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 40 --sample-range 32:40 -o " + (d / "b.exr")), 0);
    ASSERT_EQ(run(std::string(HT_BINARY) + " merge " + (d / "b.exr") + " " + (d / "a.exr") + " -o " + (d / "m40.exr") + " --quiet"), 0);
    EXPECT_EQ(image(d / "full40.exr"), image(d / "m40.exr"));
}

// The parts carry the AOV sums segment by segment (4:12 holds two chunks apart) and the merge
// folds them like the beauty; a part rendered without AOVs belongs to another render.
TEST(RenderFarm, MergeOfPartsWithAovsEqualsTheFullRenderInEveryChannel) {
    TempDir d("ht_dist_");
    const std::string opts = " --spp 16 --chunk 4";
    const std::string aovs = kRender + clitest::kEveryAov + opts;
    ASSERT_EQ(run(aovs + " -o " + (d / "full.exr")), 0);
    ASSERT_EQ(run(aovs + " --sample-range 0:4 -o " + (d / "p0.exr")), 0);
    ASSERT_EQ(run(aovs + " --sample-range 4:12 -o " + (d / "p1.exr")), 0);
    ASSERT_EQ(run(aovs + " --sample-range 12:16 -o " + (d / "p2.exr")), 0);
    const std::string merge = std::string(HT_BINARY) + " merge ";
    ASSERT_EQ(run(merge + (d / "p2.exr") + " " + (d / "p0.exr") + " " + (d / "p1.exr") + " -o " + (d / "merged.exr") +
                  " --quiet"), 0);
    clitest::expect_same_channel_bits(d / "full.exr", d / "merged.exr");

    ASSERT_EQ(run(kRender + opts + " --sample-range 12:16 -o " + (d / "plain.exr")), 0);
    EXPECT_EQ(run(merge + (d / "p0.exr") + " " + (d / "p1.exr") + " " + (d / "plain.exr") + " -o " +
                  (d / "m.exr") + " 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("different AOVs"), std::string::npos) << slurp(d / "err.txt");
}

TEST(RenderFarm, MergeReportsGapsOverlapsAndForeignParts) {
    TempDir d("ht_dist_");
    const std::string opts = " --spp 12 --chunk 4";
    for (const char* r : {"0:4", "4:8", "8:12", "4:12"})
        ASSERT_EQ(run(kRender + opts + " --sample-range " + r + " -o " + (d / (std::string(r).replace(1, 1, "_") + ".exr"))), 0);
    ASSERT_EQ(run(std::string(HT_BINARY) + kScene + " --seed 10 --spp 12 --chunk 4 --sample-range 8:12 -o " + (d / "other.exr")), 0);
    const std::string merge = std::string(HT_BINARY) + " merge ";
    EXPECT_EQ(run(merge + (d / "0_4.exr") + " " + (d / "8_12.exr") + " -o " + (d / "m.exr") + " 2>" + (d / "gap.txt")), 2);
    EXPECT_EQ(run(merge + (d / "0_4.exr") + " " + (d / "4_8.exr") + " " + (d / "4_12.exr") + " -o " + (d / "m.exr") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(merge + (d / "0_4.exr") + " " + (d / "4_8.exr") + " " + (d / "other.exr") + " -o " + (d / "m.exr") + " 2>/dev/null"), 2);
    EXPECT_EQ(run(merge + (d / "0_4.exr") + " " + (d / "4_12.exr") + " -o " + (d / "m.exr") + " --quiet"), 0);
    std::ifstream f(d / "gap.txt");
    std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("samples [4, 8) are missing"), std::string::npos) << text;
}

TEST(RenderFarm, SampleRangeIsValidated) {
    TempDir d("ht_dist_");
    const std::string o = " -o " + (d / "x.exr") + " 2>/dev/null";
    EXPECT_EQ(run(kRender + " --spp 16 --chunk 4 --sample-range 8:4" + o), 2);
    EXPECT_EQ(run(kRender + " --spp 16 --chunk 4 --sample-range 0:20" + o), 2);
    EXPECT_EQ(run(kRender + " --spp 16 --chunk 4 --sample-range 0:3" + o), 2);
    EXPECT_EQ(run(kRender + " --spp 16 --chunk 4 --sample-range 4-8" + o), 2);
    EXPECT_EQ(run(kRender + " --spp 16 --chunk 4 --sample-range 0:4 -o " + (d / "x.png") + " 2>/dev/null"), 2);  // no .exr
}

TEST(RenderFarm, ResumeAcrossChunksEqualsUninterrupted) {
    TempDir d("ht_dist_");
    ASSERT_EQ(run(kRender + " --spp 16 --chunk 4 -o " + (d / "full.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 6 --chunk 4 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "a.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 16 --chunk 4 --resume " + (d / "c.ckpt") + " -o " + (d / "r.exr")), 0);
    EXPECT_EQ(image(d / "full.exr"), image(d / "r.exr"));
}

// PoCL exposes one CPU device per entry of POCL_DEVICES: two `pthread` devices share the cores.
TEST(MultiDevice, SplitAcrossDevicesEqualsOneDevice) {
    TempDir d("ht_dist_");
    const std::string env = "POCL_DEVICES='pthread basic' ";
    ASSERT_EQ(run(env + kRender + " --spp 12 --chunk 2 --device 0 -o " + (d / "one.exr")), 0);
    ASSERT_EQ(run(env + kRender + " --spp 12 --chunk 2 --device 0,1 -o " + (d / "two.exr")), 0);
    ASSERT_EQ(run(env + kRender + " --spp 12 --chunk 2 --device all -o " + (d / "all.exr")), 0);
    auto one = image(d / "one.exr");
    EXPECT_EQ(one, image(d / "two.exr"));
    EXPECT_EQ(one, image(d / "all.exr"));
    EXPECT_EQ(run(env + kRender + " --spp 2 --device 0,0 -o " + (d / "x.exr") + " 2>/dev/null"), 2);
}

// --target-error takes the chunks one at a time, on whichever device is free: the same image.
TEST(MultiDevice, AdaptiveSplitAcrossDevicesEqualsOneDevice) {
    TempDir d("ht_dist_");
    const std::string env = "POCL_DEVICES='pthread basic' ";
    const std::string adaptive = kRender + " --spp 24 --chunk 4 --target-error 0.4 --min-spp 4";
    ASSERT_EQ(run(env + adaptive + " --device 0 -o " + (d / "one.exr")), 0);
    ASSERT_EQ(run(env + adaptive + " --device 0,1 -o " + (d / "two.exr")), 0);
    EXPECT_EQ(clitest::channel_bits(d / "one.exr"), clitest::channel_bits(d / "two.exr"));
}

// Work stealing: the devices together render every chunk exactly once.  (Which device takes how
// many depends on timing; on a loaded machine one device may legitimately take them all.)
TEST(MultiDevice, DevicesRenderEveryChunkOnce) {
    TempDir d("ht_dist_");
    std::string cmd = "POCL_DEVICES='pthread basic' " + std::string(HT_BINARY) +
                      " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3"
                      " --seed 9 --spp 12 --chunk 2 --device all -o " + (d / "x.exr") + " 2>" + (d / "log.txt");
    ASSERT_EQ(run(cmd), 0);
    std::ifstream f(d / "log.txt");
    std::string line;
    std::vector<int> chunks;
    while (std::getline(f, line)) {
        auto at = line.find(" chunks, ");
        if (line.rfind("device ", 0) == 0 && at != std::string::npos) {
            auto colon = line.rfind(": ", at);
            chunks.push_back(std::stoi(line.substr(colon + 2, at - colon - 2)));
        }
    }
    ASSERT_EQ(chunks.size(), 2u);
    EXPECT_EQ(chunks[0] + chunks[1], 6);
}

#ifdef HT_MPIEXEC
namespace {
// mpirun as CI meets it: root on a fresh machine or container, fewer cores than ranks, no
// InfiniBand, maybe a small /dev/shm without CMA.  Open MPI refuses root without both the flag
// and the two variables (flag alone suffices in 4.1, the variables in 5.x), refuses more ranks
// than cores without --oversubscribe, and its vader transport's default single-copy mechanism
// (CMA) fails where ptrace is restricted, hence none.  btl self,vader keeps it from probing
// network transports that a container lacks (and from warning about them).
std::string mpirun(int np) {
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none "
           "OMPI_MCA_rmaps_base_oversubscribe=1 " + std::string(HT_MPIEXEC) +
           " --oversubscribe --allow-run-as-root --mca btl self,vader -np " + std::to_string(np) + " ";
}

// Runs cmd with stderr kept, so a failure shows what mpirun or a rank said.
int run_logged(const std::string& cmd, const std::string& log, std::string& text) {
    const int code = run(cmd + " 2>" + log);
    std::ifstream f(log);
    text.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    return code;
}
}  // namespace

// The launcher itself, so that a broken MPI set-up reads as such and not as a render bug.  Both
// ranks must have initialised MPI: a rank that did not would report itself as rank 0 of 1.
TEST(Mpi, LauncherStartsRanksThatSeeEachOther) {
    TempDir d("ht_dist_");
    std::string log;
    const std::string loud = std::string(HT_BINARY) +
                             " render 'builtin:strand?hairs=120&segments=12' --width 40 --height 32 --max-depth 3";
    ASSERT_EQ(run_logged(mpirun(2) + loud + " --spp 2 --chunk 1 -o " + (d / "x.exr"), d / "log.txt", log), 0) << log;
    EXPECT_NE(log.find("MPI: 2 ranks"), std::string::npos) << log;
}

TEST(Mpi, RanksGiveTheOneProcessImage) {
    TempDir d("ht_dist_");
    ASSERT_EQ(run(kRender + " --spp 12 --chunk 2 -o " + (d / "one.exr")), 0);
    auto one = image(d / "one.exr");
    for (int np : {2, 4}) {
        std::string out = d / ("np" + std::to_string(np) + ".exr"), log;
        ASSERT_EQ(run_logged(mpirun(np) + kRender + " --spp 12 --chunk 2 -o " + out, d / "log.txt", log), 0) << np << log;
        EXPECT_EQ(one, image(out)) << np << " ranks";
    }
}

// Which pixels a chunk renders depends on the chunks before it, which other ranks render.
TEST(Mpi, TargetErrorIsRefused) {
    TempDir d("ht_dist_");
    std::string log;
    EXPECT_EQ(run_logged(mpirun(2) + kRender + " --spp 8 --chunk 2 --target-error 0.1 --min-spp 2 -o " + (d / "x.exr"),
                         d / "log.txt", log), 2) << log;
    EXPECT_NE(log.find("--target-error cannot run on 2 MPI ranks"), std::string::npos) << log;
}

TEST(Mpi, PerRankCheckpointsResumeTogether) {
    TempDir d("ht_dist_");
    std::string log;
    ASSERT_EQ(run(kRender + " --spp 12 --chunk 2 -o " + (d / "one.exr")), 0);
    // a time limit that stops each rank early, at a point that depends on timing
    ASSERT_EQ(run_logged(mpirun(2) + kRender + " --spp 12 --chunk 2 --time-limit 0.001 --checkpoint " + (d / "c") +
                         " -o " + (d / "early.exr"), d / "log.txt", log), 0) << log;
    ASSERT_TRUE(fs::exists(d / "c.rank0") && fs::exists(d / "c.rank1"));
    ASSERT_EQ(run_logged(mpirun(2) + kRender + " --spp 12 --chunk 2 --resume " + (d / "c") + " -o " + (d / "resumed.exr"),
                         d / "log.txt", log), 0) << log;
    EXPECT_EQ(image(d / "one.exr"), image(d / "resumed.exr"));
}

// The reduction carries the AOV sums with the films, and each rank's checkpoint keeps them.
TEST(Mpi, AovsSurviveTheReductionAndPerRankCheckpoints) {
    TempDir d("ht_dist_");
    std::string log;
    const std::string aovs = kRender + clitest::kEveryAov + " --spp 12 --chunk 2";
    ASSERT_EQ(run(aovs + " -o " + (d / "one.exr")), 0);
    ASSERT_EQ(run_logged(mpirun(2) + aovs + " -o " + (d / "np2.exr"), d / "log.txt", log), 0) << log;
    clitest::expect_same_channel_bits(d / "one.exr", d / "np2.exr");
    ASSERT_EQ(run_logged(mpirun(2) + aovs + " --time-limit 0.001 --checkpoint " + (d / "c") + " -o " + (d / "early.exr"),
                         d / "log.txt", log), 0) << log;
    ASSERT_EQ(run_logged(mpirun(2) + aovs + " --resume " + (d / "c") + " -o " + (d / "resumed.exr"), d / "log.txt", log),
              0) << log;
    clitest::expect_same_channel_bits(d / "one.exr", d / "resumed.exr");
}
#endif
#endif
