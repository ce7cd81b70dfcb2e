// The anchor-format ray files the tools exchange: `render --dump-rays` writes a render's rays with
// its answers, `bench --rays` traces them again and exits 1 on any disagreement, and `bench
// --answers-out` writes them back with the bench's answers for the anchor's double-precision
// referee (host/io/rays_file.h).  A round trip must keep every ray and every answer bit for bit.
#include <gtest/gtest.h>

#include "io/rays_file.h"
#include "scene/scene.h"
#include "cli_test_util.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef HT_BINARY
namespace {
namespace fs = std::filesystem;
using clitest::run, clitest::slurp, clitest::TempDir;
const std::string kBin = HT_BINARY;
}  // namespace

TEST(RayFiles, DumpedRaysBenchAgainAndComeBackWithTheSameAnswers) {
    TempDir d("ht_rayfiles_");
    ASSERT_EQ(run(kBin + " render builtin:strand --width 32 --height 32 --spp 1 --max-depth 2 --seed 1 --quiet --dump-rays " +
                  d.path.string() + " -o " + (d / "x.exr")),
              0);
    const std::string closest = d / "strand.b0.closest.rays", shadow = d / "strand.b1.shadow.rays";
    ASSERT_TRUE(fs::exists(closest) && fs::exists(shadow));
    fs::create_directories(d / "out");
    ASSERT_EQ(run(kBin + " bench --scene builtin:strand --rays " + closest + " --rays " + shadow +
                  " --reps 1 --no-wavefront --answers-out " + (d / "out") + " >" + (d / "log.txt") + " 2>&1"),
              0)
        << slurp(d / "log.txt");

    const ht::RaysFile a = ht::read_rays_file(closest), b = ht::read_rays_file(d / "out/strand.b0.closest.hairtrace.rays");
    EXPECT_EQ(a.header, b.header);
    // the dump names its scene by the anchor's content hash, as the anchor's files do
    const uint64_t strand_hash = ht::hair_file_hash(ht::make_builtin("strand").strands);
    EXPECT_NE(strand_hash, 0u);
    EXPECT_EQ(a.scene_hash, strand_hash);
    ASSERT_EQ(a.rays.size(), b.rays.size());
    ASSERT_EQ(0, std::memcmp(a.rays.data(), b.rays.data(), a.rays.size() * sizeof(HtRay)));
    // whole records, the outward normals too: the render's camera stage and the bench's tree give the
    // same hits, and one conversion (render/ray_dump.h anchor_hit_record) makes both files' records
    size_t hits = 0, same = 0, normals = 0;
    for (size_t i = 0; i < a.hits.size(); ++i) {
        hits += a.hits[i].prim != ht::kEmbreeNoPrim;
        same += std::memcmp(&a.hits[i], &b.hits[i], sizeof(ht::EmbreeHit)) == 0;
        const float* n = a.hits[i].ng;
        normals += a.hits[i].prim != ht::kEmbreeNoPrim && n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0.0f;
    }
    EXPECT_EQ(same, a.hits.size());
    EXPECT_GT(hits, a.hits.size() / 20);  // not a file of misses alone
    EXPECT_EQ(normals, hits);

    // against another scene of as many segments the bench refuses the file (a bad input, exit 2),
    // naming both hashes, before tracing a ray
    EXPECT_EQ(run(kBin + " bench --scene 'builtin:strand?seed=7' --rays " + closest + " --reps 1 --no-wavefront >" +
                  (d / "wrong.txt") + " 2>&1"),
              2);
    char stated[17];
    std::snprintf(stated, sizeof stated, "%016llx", static_cast<unsigned long long>(strand_hash));
    EXPECT_NE(slurp(d / "wrong.txt").find(std::string("made for the scene of content hash ") + stated),
              std::string::npos)
        << slurp(d / "wrong.txt");

    const ht::RaysFile s = ht::read_rays_file(shadow), t = ht::read_rays_file(d / "out/strand.b1.shadow.hairtrace.rays");
    EXPECT_EQ(s.header, t.header);
    ASSERT_EQ(s.rays.size(), t.rays.size());
    ASSERT_GT(s.rays.size(), 0u);
    EXPECT_EQ(s.occluded, t.occluded);

    // answers that do not match the file's rays are refused, naming the count
    try {
        ht::write_rays_file(d / "bad.rays", a.header, a.rays, {}, {});
        ADD_FAILURE() << "no answers accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("0 answers for " + std::to_string(a.rays.size()) + " rays"), std::string::npos)
            << e.what();
    }
    // and so are rays whose count is not the header's
    try {
        ht::write_rays_file(d / "bad.rays", ht::make_rays_header(0, 0, 5, a.segments, a.strands, a.scene_hash, a.scene), a.rays,
                            a.hits, {});
        ADD_FAILURE() << "a header for 5 rays written with " << a.rays.size();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("the header says 5 rays, " + std::to_string(a.rays.size()) + " given"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(fs::exists(d / "bad.rays"));
}
#endif
