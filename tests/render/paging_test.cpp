// A scene larger than one device allocation: the geometry arrays are paged over several buffers
// (kernels/geometry/pages.h).  HAIRTRACE_MAX_ALLOC makes the CPU device's limit small enough to
// force it; the promise under test is the same bits as the unpaged render, and a clear refusal
// (exit 3, the sizes named) when even the maximum number of pages is too few.
#include "cl/device.h"
#include "io/image_io.h"
#include "render/memory_plan.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace ht;
using clitest::TempDir;
using clitest::run;
using clitest::slurp;
using clitest::image;

TEST(GeometryPaging, OneBufferPerArrayWhenEverythingFits) {
    const GeometryPaging g = plan_geometry_pages({{"BVH node", 1000}, {"segment", 4096}, {"point", 0}}, 4096);
    EXPECT_EQ(g.pages, 1u);
    EXPECT_EQ(g.page_log2, 0u);
    EXPECT_EQ(plan_geometry_pages({{"segment", uint64_t(1) << 40}}, 0).pages, 1u);  // no limit reported
}

TEST(GeometryPaging, PagesArePowersOfTwoWithinTheLimitAndCoverTheLargestArray) {
    // 100 KiB limit: 64 KiB pages; the 300 KiB node array needs 5 of them
    GeometryPaging g = plan_geometry_pages({{"BVH node", 300 << 10}, {"segment", 90 << 10}}, 100 << 10);
    EXPECT_EQ(g.page_log2, 16u);
    EXPECT_EQ(g.page_bytes(), uint64_t(64) << 10);
    EXPECT_EQ(g.pages, 5u);
    // exactly 8 full pages is still allowed
    g = plan_geometry_pages({{"point", 8 << 12}}, 4 << 10);
    EXPECT_EQ(g.pages, 8u);
    EXPECT_EQ(g.page_log2, 12u);
}

TEST(GeometryPaging, TooManyPagesIsRefusedWithTheSizes) {
    try {
        plan_geometry_pages({{"segment", 10}, {"BVH node", (8 << 12) + 1}}, 4 << 10);
        FAIL() << "9 pages accepted";
    } catch (const DeviceError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("BVH node array needs 32769 bytes"), std::string::npos) << m;
        EXPECT_NE(m.find("9 buffers of 4096 bytes"), std::string::npos) << m;
        EXPECT_NE(m.find("at most 8"), std::string::npos) << m;
    }
    EXPECT_THROW(plan_geometry_pages({{"point", 100}}, 32), DeviceError);  // not even one record per page
}

TEST(GeometryPaging, MemoryPlanCountsTheScenePagesNotOneAllocation) {
    // a 3 MiB scene on a device allocating at most 1 MiB: refused before paging existed, now the
    // planner only needs the film to fit one allocation and everything to fit the memory
    const GeometryPaging paging{3, 20};
    MemoryPlan p = plan_device_memory(64 * 64, 64 * 64, 3 << 20, 1 << 20, 64 << 20, 0, 1 << 20, PathBufferSet{}, paging);
    EXPECT_EQ(p.paging.pages, 3u);
    EXPECT_GT(p.paths_per_pass, 0u);
    try {
        plan_device_memory(64 * 64, 64 * 64, 3 << 20, 1 << 20, 3 << 20, 0, 1 << 20, PathBufferSet{}, paging);
        FAIL() << "a scene filling the whole device accepted";
    } catch (const DeviceError& e) {
        EXPECT_NE(std::string(e.what()).find("in 3 pages of 1.0 MiB per array"), std::string::npos) << e.what();
    }
}

#ifdef HT_BINARY
namespace {
// 10,000 segments: 160 KB of segments, 168 KB of points, 121 KB of BVH nodes (472).  With 64 KiB
// allocations that is 3, 3 and 2 pages (each array split, none past the limit of 8), and the 48x48
// film (36 KB) still fits one allocation.
const std::string kScene = "'builtin:strand?hairs=500&segments=20'";
const std::string kRender = std::string(HT_BINARY) + " render " + kScene + " --width 48 --height 48 --max-depth 4 --seed 3";

}  // namespace

TEST(GeometryPaging, PagedRenderEqualsTheUnpagedRender) {
    TempDir d("ht_page_");
    ASSERT_EQ(run(kRender + " --spp 3 --quiet -o " + (d / "flat.exr")), 0);
    ASSERT_EQ(run("HAIRTRACE_MAX_ALLOC=64K " + kRender + " --spp 3 --verbose -o " + (d / "paged.exr") + " 2>" +
                  (d / "log.txt")), 0)
        << slurp(d / "log.txt");
    const std::string log = slurp(d / "log.txt");
    // the render really was paged (the options the program was built with say so)
    EXPECT_NE(log.find("-DHT_GEOMETRY_PAGES=3 -DHT_GEOMETRY_PAGE_LOG2=16"), std::string::npos) << log;
    EXPECT_NE(log.find("geometry: 3 buffers per array"), std::string::npos) << log;
    const auto flat = image(d / "flat.exr");
    EXPECT_EQ(flat, image(d / "paged.exr"));
    // and the picture is not empty: hair was hit
    float sum = 0;
    for (float v : flat) sum += v;
    EXPECT_GT(sum, 0.0f);
    // a checkpoint of the paged render resumes unpaged (the paging is not part of the render identity)
    ASSERT_EQ(run("HAIRTRACE_MAX_ALLOC=64K " + kRender + " --spp 1 --quiet --checkpoint " + (d / "c.ckpt") + " -o " +
                  (d / "one.exr")), 0);
    ASSERT_EQ(run(kRender + " --spp 3 --quiet --resume " + (d / "c.ckpt") + " -o " + (d / "resumed.exr")), 0);
    EXPECT_EQ(flat, image(d / "resumed.exr"));
}

TEST(GeometryPaging, BenchHitsAreTheSameWhenPaged) {
    TempDir d("ht_page_");
    // 32x32 rays: the ray and hit buffers fit the 64 KiB allocations too
    const std::string bench = std::string(HT_BINARY) + " bench --scene " + kScene + " --res 32 --reps 1 --no-wavefront";
    ASSERT_EQ(run(bench + " >" + (d / "flat.txt") + " 2>&1"), 0) << slurp(d / "flat.txt");
    ASSERT_EQ(run("HAIRTRACE_MAX_ALLOC=64K " + bench + " >" + (d / "paged.txt") + " 2>&1"), 0) << slurp(d / "paged.txt");
    auto answers = [](const std::string& text) {  // the hit counts and checksums, not the timings
        std::istringstream in(text);
        std::string line, out;
        while (std::getline(in, line))
            if (line.find("hits ") != std::string::npos || line.find("occluded ") != std::string::npos) out += line + "\n";
        return out;
    };
    const std::string flat = answers(slurp(d / "flat.txt"));
    EXPECT_NE(flat.find("sum_segment"), std::string::npos) << flat;
    // the generated shadow rays run to one point light: the render's shadow stage with that light's
    // lists answers them too, as the tree does (bench exits 1 on a mismatch), paged or not;
    // and the generated primary rays all leave the eye: the camera stage with a fitted camera's lists
    for (const char* f : {"flat.txt", "paged.txt"}) {
        EXPECT_NE(slurp(d / f).find("by the lights' shadow lists (0 directional + 1 point light grids"), std::string::npos)
            << slurp(d / f);
        EXPECT_NE(slurp(d / f).find("by the per-pixel lists of a camera at their origin (32x32 pixels"), std::string::npos)
            << slurp(d / f);
    }
    EXPECT_EQ(flat, answers(slurp(d / "paged.txt")));
}

TEST(GeometryPaging, MorePagesThanSupportedExits3WithTheSizes) {
    TempDir d("ht_page_");
    // 16 KiB allocations: the point array (the largest, fixed by the scene, with axis-aligned nodes;
    // oriented ones take a second record each and may outgrow it) would need 11 pages
    EXPECT_EQ(run("HAIRTRACE_MAX_ALLOC=16K " + kRender + " --bvh-oriented off --spp 1 --quiet -o " + (d / "x.exr") +
                  " 2>" + (d / "err.txt")), 3);
    const std::string err = slurp(d / "err.txt");
    EXPECT_NE(err.find("point array needs"), std::string::npos) << err;
    EXPECT_NE(err.find("11 buffers of 16384 bytes"), std::string::npos) << err;
    EXPECT_NE(err.find("at most 8"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(d / "x.exr"));
}

TEST(GeometryPaging, MalformedMaxAllocIsAUsageError) {
    TempDir d("ht_page_");
    EXPECT_EQ(run("HAIRTRACE_MAX_ALLOC=lots " + kRender + " --spp 1 --quiet -o " + (d / "x.exr") + " 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("HAIRTRACE_MAX_ALLOC='lots'"), std::string::npos) << slurp(d / "err.txt");
}
#endif
