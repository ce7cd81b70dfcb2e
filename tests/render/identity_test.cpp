// The render identity: a resume or a merge of a different render is refused with exit 2 and a
// message that names what differs (materials, lights, camera, ...), instead of mixing two images.
#include "render/render_identity.h"
#include "split/checkpoint.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"

#include <cstring>
#include <fstream>

using namespace ht;
using clitest::TempDir;
using clitest::run;
using clitest::slurp;

TEST(RenderIdentity, TextRoundTripsAndDifferencesNameTheParts) {
    RenderIdentity a;
    for (int p = 0; p < RenderIdentity::kPartCount; ++p) a.digests[p] = 0x0123456789abcdefull * (p + 1);
    EXPECT_EQ(RenderIdentity::from_text(a.to_text()), a);
    EXPECT_THROW(RenderIdentity::from_text("geometry=0123"), std::invalid_argument);
    EXPECT_THROW(RenderIdentity::from_text(a.to_text() + ","), std::invalid_argument);
    RenderIdentity b = a;
    EXPECT_EQ(a.differences(b), "");
    b.digests[RenderIdentity::Materials] ^= 1;
    b.digests[RenderIdentity::Camera] ^= 1;
    EXPECT_NE(a.key(), b.key());
    const std::string why = a.differences(b);
    EXPECT_NE(why.find("materials"), std::string::npos) << why;
    EXPECT_NE(why.find("camera"), std::string::npos) << why;
    EXPECT_EQ(why.find("geometry"), std::string::npos) << why;
}

TEST(RenderIdentity, EachPartFollowsItsInputs) {
    Scene s = make_builtin("strand?hairs=20&segments=4");
    ensure_camera_and_light(s);
    RenderSettings rs;
    const RenderIdentity base = render_identity(s, rs, 16);
    EXPECT_EQ(render_identity(s, rs, 16), base);  // deterministic
    auto only = [&](const RenderIdentity& id, RenderIdentity::Part part) {
        for (int p = 0; p < RenderIdentity::kPartCount; ++p)
            EXPECT_EQ(id.digests[p] != base.digests[p], p == part) << "part " << p << " of " << id.to_text();
    };
    Scene m = s;
    m.materials[0].eta = 1.6f;
    only(render_identity(m, rs, 16), RenderIdentity::Materials);
    Scene l = s;
    l.lights[0].intensity *= 2;
    only(render_identity(l, rs, 16), RenderIdentity::Lights);
    Scene c = s;
    c.camera.eye[0] += 1;
    only(render_identity(c, rs, 16), RenderIdentity::Camera);
    Scene g = s;
    g.strands.points[3][1] += 0.5f;
    only(render_identity(g, rs, 16), RenderIdentity::Geometry);
    RenderSettings other = rs;
    other.clamp_indirect = 3;
    only(render_identity(s, other, 16), RenderIdentity::Settings);
    RenderSettings split = rs;
    split.first_hit_splits = 2;
    only(render_identity(s, split, 16), RenderIdentity::Settings);
    RenderSettings light_samples = rs;
    light_samples.first_hit_light_samples = 2;
    only(render_identity(s, light_samples, 16), RenderIdentity::Settings);
    RenderSettings threshold = rs;
    threshold.light_threshold = 0.1f;
    only(render_identity(s, threshold, 16), RenderIdentity::Settings);
    RenderSettings guided = rs, guided_auto = rs;
    guided.light_guiding = 0.2f;
    guided_auto.light_guiding = kAutoLightGuiding;
    only(render_identity(s, guided, 16), RenderIdentity::Settings);
    only(render_identity(s, guided_auto, 16), RenderIdentity::Settings);
    // The BVH's options are not identity: every tree gives the same hits, so parts and checkpoints
    // of one render may come from different trees (Render.OrientedBvhNodesGiveTheSameImage).
    RenderSettings aligned = rs, oriented_splits = rs;
    aligned.bvh_oriented = 0.0f;
    oriented_splits.bvh_oriented_splits = 1.0f;
    EXPECT_EQ(render_identity(s, aligned, 16), render_identity(s, rs, 16));
    EXPECT_EQ(render_identity(s, oriented_splits, 16), render_identity(s, rs, 16));
    RenderSettings afs = rs, dual = rs;
    afs.indirect = RenderSettings::Indirect::Afs;
    dual.indirect = RenderSettings::Indirect::Dual;
    only(render_identity(s, dual, 16), RenderIdentity::Settings);
    EXPECT_NE(render_identity(s, dual, 16), render_identity(s, afs, 16));
    only(render_identity(s, rs, 8), RenderIdentity::Settings);
    // the set of AOVs asked for, in whatever order
    const RenderIdentity aovs = render_identity(s, rs, 16, {"alpha", "depth"});
    only(aovs, RenderIdentity::Aovs);
    EXPECT_EQ(render_identity(s, rs, 16, {"depth", "alpha"}), aovs);
    EXPECT_NE(render_identity(s, rs, 16, {"alpha"}), aovs);
}

#ifdef HT_BINARY
namespace {
const std::string kOptions = " --width 24 --height 20 --max-depth 2 --seed 3 --chunk 1 --quiet";

// A copy of scenes/default.gltf with the small strand, with `from` replaced by `to`.
std::string scene_variant(const TempDir& d, const std::string& name, const std::string& from = "",
                          const std::string& to = "") {
    std::string text = slurp(std::string(HT_SOURCE_DIR) + "/scenes/default.gltf");
    const std::string builtin = "\"hairtrace_builtin\": \"strand\"";
    text.replace(text.find(builtin), builtin.size(), "\"hairtrace_builtin\": \"strand?hairs=60&segments=6\"");
    if (!from.empty()) {
        const size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
    }
    std::ofstream(d / name) << text;
    return d / name;
}

// Renders `first` (scene and options) for one sample with a checkpoint, then resumes it to two
// samples as `resume`; returns the exit status of the resume and its stderr in *err.
int resume_with(const TempDir& d, const std::string& first, const std::string& resume, std::string* err) {
    const std::string bin = std::string(HT_BINARY) + " render ";
    EXPECT_EQ(run(bin + first + kOptions + " --spp 1 --checkpoint " + (d / "c.ckpt") + " -o " + (d / "a.exr")), 0);
    const int code = run(bin + resume + kOptions + " --spp 2 --resume " + (d / "c.ckpt") + " -o " + (d / "b.exr") +
                         " 2>" + (d / "err.txt"));
    *err = slurp(d / "err.txt");
    return code;
}

// The message names `part` ("materials", "camera", ...) as different and no other part.
void expect_only_difference(const std::string& err, const std::string& part) {
    for (const char* p : {"geometry", "materials", "lights", "camera", "settings", "AOVs"})
        EXPECT_EQ(err.find(std::string("different ") + p) != std::string::npos, p == part) << p << ": " << err;
}

// The stderr of a resume from a checkpoint of the scene with `from`, resumed with `to` instead.
std::string refused_scene_change(const std::string& from, const std::string& to) {
    TempDir d("ht_ident_");
    std::string err;
    EXPECT_EQ(resume_with(d, scene_variant(d, "a.gltf"), scene_variant(d, "b.gltf", from, to), &err), 2);
    return err;
}
}  // namespace

TEST(RenderIdentity, ResumeRefusesAChangedSigmaA) {
    TempDir d("ht_ident_");
    const std::string scene = scene_variant(d, "s.gltf");
    std::string err;
    EXPECT_EQ(resume_with(d, scene, scene + " --sigma-a 2,2,2", &err), 2);
    expect_only_difference(err, "materials");
    EXPECT_NE(err.find("--sigma-a"), std::string::npos) << err;
}

TEST(RenderIdentity, ResumeRefusesAChangedMaterialExtra) {
    expect_only_difference(refused_scene_change("\"eta\": 1.55", "\"eta\": 1.6"), "materials");
}

TEST(RenderIdentity, ResumeRefusesAChangedLight) {
    expect_only_difference(refused_scene_change("\"intensity\": 10230.0", "\"intensity\": 10000.0"), "lights");
}

TEST(RenderIdentity, ResumeRefusesAChangedCamera) {
    expect_only_difference(refused_scene_change("\"yfov\": 0.523599", "\"yfov\": 0.5"), "camera");
}

// A checkpoint holds the AOV sums only when its render recorded them, and then for the names it
// was asked for: resuming with another list, or with AOVs where there were none, is refused.
TEST(RenderIdentity, ResumeRefusesAChangedAovList) {
    TempDir d("ht_ident_");
    const std::string scene = scene_variant(d, "s.gltf");
    std::string err;
    EXPECT_EQ(resume_with(d, scene + " --aovs alpha", scene, &err), 2);
    expect_only_difference(err, "AOVs");
    EXPECT_NE(err.find("--aovs"), std::string::npos) << err;
    EXPECT_EQ(resume_with(d, scene, scene + " --aovs alpha", &err), 2);
    expect_only_difference(err, "AOVs");
    EXPECT_EQ(resume_with(d, scene + " --aovs alpha", scene + " --aovs alpha,depth", &err), 2);
    expect_only_difference(err, "AOVs");
    EXPECT_EQ(resume_with(d, scene + " --aovs alpha,depth", scene + " --aovs depth,alpha", &err), 0) << err;
}

TEST(RenderIdentity, MergeRefusesPartsWithDifferentMaterials) {
    TempDir d("ht_ident_");
    const std::string scene = scene_variant(d, "s.gltf");
    const std::string bin = std::string(HT_BINARY) + " render " + scene + kOptions + " --spp 2";
    ASSERT_EQ(run(bin + " --sample-range 0:1 -o " + (d / "p0.exr")), 0);
    ASSERT_EQ(run(bin + " --sample-range 1:2 --sigma-a 2,2,2 -o " + (d / "p1.exr")), 0);
    EXPECT_EQ(run(std::string(HT_BINARY) + " merge " + (d / "p0.exr") + " " + (d / "p1.exr") + " -o " +
                  (d / "m.exr") + " 2>" + (d / "err.txt")), 2);
    expect_only_difference(slurp(d / "err.txt"), "materials");
    ASSERT_EQ(run(bin + " --sample-range 1:2 -o " + (d / "p1same.exr")), 0);
    EXPECT_EQ(run(std::string(HT_BINARY) + " merge " + (d / "p0.exr") + " " + (d / "p1same.exr") + " -o " +
                  (d / "m.exr") + " --quiet"), 0);
}

// Version 4, the last one before the AOV sums, stands for every older format.
TEST(RenderIdentity, CheckpointOfAnOlderVersionIsRefusedClearly) {
    TempDir d("ht_ident_");
    const std::string scene = scene_variant(d, "s.gltf");
    ASSERT_EQ(run(std::string(HT_BINARY) + " render " + scene + kOptions + " --spp 1 --checkpoint " + (d / "c.ckpt") +
                  " -o " + (d / "a.exr")), 0);
    {
        std::fstream f(d / "c.ckpt", std::ios::in | std::ios::out | std::ios::binary);
        const uint32_t version4 = 4;
        f.seekp(4);
        f.write(reinterpret_cast<const char*>(&version4), sizeof version4);
    }
    try {
        load_checkpoint(d / "c.ckpt");
        FAIL() << "a version 4 checkpoint was accepted";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("older hairtrace"), std::string::npos) << e.what();
    }
    EXPECT_EQ(run(std::string(HT_BINARY) + " render " + scene + kOptions + " --spp 2 --resume " + (d / "c.ckpt") +
                  " -o " + (d / "b.exr") + " 2>" + (d / "err.txt")), 2);
    EXPECT_NE(slurp(d / "err.txt").find("older hairtrace"), std::string::npos) << slurp(d / "err.txt");
}
#endif
