// glTF base colour textures: TEXCOORD_0 in every allowed encoding, images from a PNG file URI, a
// data: URI and a GLB bufferView (written with OpenImageIO here), samplers, and each hostile
// input refused with one line naming the file and the problem.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "scene/scene.h"
#include "scene_test_util.h"

namespace ht {
namespace {

using nlohmann::json;
using test::contains;
using test::scene_error_of;

constexpr int kLineStrip = 3, kTriangles = 4;

// An 8-bit image written by OpenImageIO (format from the extension), returned as bytes.
test::Bytes encode_image(const test::TempDir& dir, const std::string& name, int w, int h,
                         const std::vector<unsigned char>& rgb, int channels = 3) {
    const std::string path = dir.file(name);
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out) << OIIO::geterror();
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // store the colour bytes as given, not divided by alpha
    EXPECT_TRUE(out->open(path, spec)) << out->geterror();
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data())) << out->geterror();
    out->close();
    std::ifstream in(path, std::ios::binary);
    return test::Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// 2 x 2: red, green / blue, white (row 0 on top).
const std::vector<unsigned char> kQuad = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};

uint32_t rgb8(uint32_t r, uint32_t g, uint32_t b) { return r | g << 8 | b << 16; }

uint32_t be32(const test::Bytes& b, size_t at) {
    return uint32_t(b[at]) << 24 | b[at + 1] << 16 | b[at + 2] << 8 | b[at + 3];
}

// Byte offset of the first IDAT chunk (its length field) of a PNG.
size_t idat_chunk(const test::Bytes& png) {
    size_t at = 8;
    while (at + 8 <= png.size() && std::memcmp(&png[at + 4], "IDAT", 4) != 0) at += 12 + be32(png, at);
    EXPECT_LT(at + 8, png.size()) << "no IDAT chunk";
    return at;
}

// PNG chunk CRC (ISO 3309, as in the PNG spec's sample code), to forge a consistent header.
uint32_t png_crc32(const unsigned char* p, size_t n) {
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

int add_vec2(test::GltfBuilder& g, const std::vector<std::array<float, 2>>& v) {
    test::Bytes bytes;
    for (const auto& p : v) test::append(bytes, p);
    return g.add_accessor(bytes, "VEC2", 5126, v.size());
}

// A bufferView holding raw bytes (an embedded image); returns its index.
int add_view(test::GltfBuilder& g, const test::Bytes& bytes) {
    while (g.bin.size() % 4) g.bin.push_back(0);
    const size_t offset = g.bin.size();
    g.bin.insert(g.bin.end(), bytes.begin(), bytes.end());
    g.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size()}});
    return static_cast<int>(g.doc["bufferViews"].size() - 1);
}

// A textured quad (material 0, texture 0, sampler 0 with the given wraps) and a hair strand.
// The image is for the caller to add as images[0].
void textured_quad(test::GltfBuilder& g, int uv_accessor, json sampler = json::object()) {
    g.doc["materials"] = json::array({{{"name", "checker"},
                                       {"pbrMetallicRoughness",
                                        {{"baseColorFactor", {1.0, 0.5, 1.0, 1.0}},
                                         {"baseColorTexture", {{"index", 0}}}}}}});
    g.doc["samplers"] = json::array({sampler});
    g.doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
    const int pos = g.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}});
    const int mesh = g.add_mesh(kTriangles, pos, -1, g.add_indices({0, 2, 1, 0, 3, 2}), 0);
    if (uv_accessor >= 0) g.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv_accessor;
    g.add_node({{"mesh", mesh}});
    g.add_node({{"mesh", g.add_mesh(kLineStrip, g.add_vec3({{0, 0, 0}, {0, 1, 0}}), g.add_scalar({1, 1}))}});
}

const std::vector<std::array<float, 2>> kUvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

void expect_quad_texture(const Scene& s) {
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.width, 2u);
    ASSERT_EQ(t.height, 2u);
    ASSERT_EQ(t.texels.size(), 4u);
    EXPECT_EQ(t.texels[0], rgb8(255, 0, 0));
    EXPECT_EQ(t.texels[1], rgb8(0, 255, 0));
    EXPECT_EQ(t.texels[2], rgb8(0, 0, 255));
    EXPECT_EQ(t.texels[3], rgb8(255, 255, 255));
    ASSERT_EQ(s.meshes.size(), 1u);
    const SurfaceMaterialDesc& m = s.surface_materials.at(s.meshes[0].material);
    EXPECT_EQ(m.texture, 0);
    EXPECT_FLOAT_EQ(m.albedo[1], 0.5f);  // the factor is kept and multiplies the texture
    ASSERT_EQ(s.meshes[0].uvs.size(), 4u);
    EXPECT_FLOAT_EQ(s.meshes[0].uvs[2][0], 1.0f);
    EXPECT_FLOAT_EQ(s.meshes[0].uvs[2][1], 1.0f);
}

TEST(SceneGltfTexture, PngFileUri) {
    test::TempDir dir;
    encode_image(dir, "my quad.png", 2, 2, kQuad);
    test::GltfBuilder g;
    textured_quad(g, add_vec2(g, kUvs),
                  {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}});
    g.doc["images"] = json::array({{{"uri", "my%20quad.png"}}});  // percent-encoded space
    const std::string path = dir.file("scene.gltf");
    test::write_text(path, g.gltf_text());
    const Scene s = load_scene(path);
    expect_quad_texture(s);
    EXPECT_EQ(s.textures[0].wrap_s, TextureWrap::ClampToEdge);
    EXPECT_EQ(s.textures[0].wrap_t, TextureWrap::MirroredRepeat);
}

TEST(SceneGltfTexture, EmbeddedGlbBufferView) {
    test::TempDir dir;
    const test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
    test::GltfBuilder g;
    textured_quad(g, add_vec2(g, kUvs));
    g.doc["images"] = json::array({{{"bufferView", add_view(g, png)}, {"mimeType", "image/png"}}});
    const std::string path = dir.file("scene.glb");
    test::write_file(path, g.glb_bytes());
    const Scene s = load_scene(path);
    expect_quad_texture(s);
    EXPECT_EQ(s.textures[0].wrap_s, TextureWrap::Repeat);  // no wraps stated: REPEAT
}

TEST(SceneGltfTexture, DataUriPngAndJpeg) {
    test::TempDir dir;
    {
        const test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "data:image/png;base64," + test::GltfBuilder::base64(png)}}});
        const std::string path = dir.file("png.gltf");
        test::write_text(path, g.gltf_text());
        expect_quad_texture(load_scene(path));
    }
    {
        // JPEG is lossy: a flat 8 x 8 grey survives to within a step or two.
        const test::Bytes jpg = encode_image(dir, "q.jpg", 8, 8, std::vector<unsigned char>(8 * 8 * 3, 128));
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "data:image/jpeg;base64," + test::GltfBuilder::base64(jpg)}}});
        const std::string path = dir.file("jpg.gltf");
        test::write_text(path, g.gltf_text());
        const Scene s = load_scene(path);
        ASSERT_EQ(s.textures.size(), 1u);
        EXPECT_EQ(s.textures[0].width, 8u);
        EXPECT_NEAR(double(s.textures[0].texels[27] & 0xff), 128.0, 2.0);
    }
}

TEST(SceneGltfTexture, GreyAndAlphaImages) {
    // Grey + alpha: grey replicated to rgb, alpha dropped and not premultiplied into the colour.
    test::TempDir dir;
    encode_image(dir, "ga.png", 2, 1, {200, 0, 50, 128}, 2);
    test::GltfBuilder g;
    textured_quad(g, add_vec2(g, kUvs));
    g.doc["images"] = json::array({{{"uri", "ga.png"}}});
    const std::string path = dir.file("ga.gltf");
    test::write_text(path, g.gltf_text());
    const Scene s = load_scene(path);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].texels[0], rgb8(200, 200, 200));
    EXPECT_EQ(s.textures[0].texels[1], rgb8(50, 50, 50));
}

TEST(SceneGltfTexture, NormalizedIntegerTexcoords) {
    test::TempDir dir;
    encode_image(dir, "q.png", 2, 2, kQuad);
    for (int component : {5121, 5123}) {
        test::GltfBuilder g;
        test::Bytes bytes;
        const uint16_t top = component == 5121 ? 255 : 65535;
        const uint16_t uv[8] = {0, 0, top, 0, top, top, 0, uint16_t(top / 2)};
        for (uint16_t x : uv) {
            if (component == 5121) bytes.push_back(uint8_t(x));
            else test::append(bytes, x);
        }
        // unsigned byte VEC2 elements are 2 bytes: the accessor stays 4-byte aligned via padding
        const int acc = g.add_accessor(bytes, "VEC2", component, 4);
        g.doc["accessors"][acc]["normalized"] = true;
        textured_quad(g, acc);
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        const std::string path = dir.file("n.gltf");
        test::write_text(path, g.gltf_text());
        const Scene s = load_scene(path);
        ASSERT_EQ(s.meshes[0].uvs.size(), 4u);
        EXPECT_FLOAT_EQ(s.meshes[0].uvs[2][0], 1.0f) << component;
        EXPECT_NEAR(s.meshes[0].uvs[3][1], 0.5f, 0.5f / top) << component;
        // not normalized: refused
        g.doc["accessors"][acc]["normalized"] = false;
        test::write_text(path, g.gltf_text());
        const std::string msg = scene_error_of([&] { load_scene(path); });
        test::expect_one_line_naming(msg, path);
        EXPECT_TRUE(contains(msg, "normalized")) << msg;
    }
}

TEST(SceneGltfTexture, TexturedMaterialWithoutTexcoordsWarnsAndUsesTheFactor) {
    test::TempDir dir;
    encode_image(dir, "q.png", 2, 2, kQuad);
    test::GltfBuilder g;
    textured_quad(g, -1);
    g.doc["images"] = json::array({{{"uri", "q.png"}}});
    const std::string path = dir.file("nouv.gltf");
    test::write_text(path, g.gltf_text());
    const Scene s = load_scene(path);
    EXPECT_TRUE(s.meshes[0].uvs.empty());
    EXPECT_TRUE(test::any_warning_contains(s, "no TEXCOORD_0")) << (s.warnings.empty() ? "" : s.warnings[0]);
}

// Each hostile file: SceneError, one line, starting with the glTF file's name, naming the problem.
class HostileTexture : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string refuse(const test::GltfBuilder& g, const std::string& name, bool glb = false,
                       uint64_t max_bytes = uint64_t(16) << 30) {
        const std::string path = dir.file(name);
        if (glb) test::write_file(path, g.glb_bytes());
        else test::write_text(path, g.gltf_text());
        LoadOptions opt;
        opt.max_bytes = max_bytes;
        const std::string msg = scene_error_of([&] { load_scene(path, opt); });
        test::expect_one_line_naming(msg, path);
        return msg;
    }
};

TEST_F(HostileTexture, MissingImageFile) {
    test::GltfBuilder g;
    textured_quad(g, add_vec2(g, kUvs));
    g.doc["images"] = json::array({{{"uri", "nowhere.png"}}});
    const std::string msg = refuse(g, "missing.gltf");
    EXPECT_TRUE(contains(msg, "nowhere.png") && contains(msg, "does not exist")) << msg;
    // a directory where the image should be
    std::filesystem::create_directory(dir.file("folder.png"));
    g.doc["images"] = json::array({{{"uri", "folder.png"}}});
    const std::string msg2 = refuse(g, "folder.gltf");
    EXPECT_TRUE(contains(msg2, "folder.png") && contains(msg2, "not a regular file")) << msg2;
}

TEST_F(HostileTexture, UndecodableImages) {
    {
        test::write_text(dir.file("text.png"), "this is not a picture");
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "text.png"}}});
        const std::string msg = refuse(g, "text.gltf");
        EXPECT_TRUE(contains(msg, "not a PNG or JPEG")) << msg;
    }
    {
        // A valid PNG signature and header, the rest cut off.
        test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
        png.resize(40);
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"bufferView", add_view(g, png)}, {"mimeType", "image/png"}}});
        const std::string msg = refuse(g, "cut.glb", true);
        EXPECT_TRUE(contains(msg, "truncated")) << msg;
    }
    {
        // One flipped bit in the compressed pixels: the chunk's CRC no longer matches.
        test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
        png[idat_chunk(png) + 8 + 2] ^= 0x10;  // third byte of the compressed pixels
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"bufferView", add_view(g, png)}}});
        const std::string msg = refuse(g, "crc.glb", true);
        EXPECT_TRUE(contains(msg, "CRC")) << msg;
    }
    {
        // Whole chunks with valid CRCs around pixel data that is not a zlib stream: only the
        // decoder can tell.
        test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
        const size_t idat = idat_chunk(png);
        const uint32_t len = be32(png, idat);
        for (uint32_t i = 0; i < len; ++i) png[idat + 8 + i] = 0x55;
        const uint32_t crc = png_crc32(&png[idat + 4], 4 + len);
        for (int i = 0; i < 4; ++i) png[idat + 8 + len + i] = uint8_t(crc >> (24 - 8 * i));
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"bufferView", add_view(g, png)}}});
        const std::string msg = refuse(g, "zlib.glb", true);
        EXPECT_TRUE(contains(msg, "decode")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"bufferView", add_view(g, test::Bytes{1, 2, 3})}, {"mimeType", "image/webp"}}});
        const std::string msg = refuse(g, "webp.glb", true);
        EXPECT_TRUE(contains(msg, "image/webp")) << msg;
    }
}

TEST_F(HostileTexture, AbsurdDimensionsAreBoundedByTheMemoryLimit) {
    // A real PNG header claiming 60000 x 60000 pixels (14.4 GB as texels) and no pixel data:
    // refused from the header under a 1 GiB limit, before any decoding or allocation.
    test::Bytes png = encode_image(dir, "q.png", 2, 2, kQuad);
    auto put_be32 = [&](size_t at, uint32_t v) {
        for (int i = 0; i < 4; ++i) png[at + i] = uint8_t(v >> (24 - 8 * i));
    };
    put_be32(16, 60000);  // IHDR width
    put_be32(20, 60000);  // IHDR height
    put_be32(29, png_crc32(&png[12], 17));  // IHDR's CRC over its type and 13 data bytes
    test::GltfBuilder g;
    textured_quad(g, add_vec2(g, kUvs));
    g.doc["images"] = json::array({{{"bufferView", add_view(g, png)}}});
    const std::string msg = refuse(g, "huge.glb", true, uint64_t(1) << 30);
    EXPECT_TRUE(contains(msg, "60000 x 60000") && contains(msg, "memory limit")) << msg;
    // And the same 2 x 2 image under a limit smaller than its 16 texel bytes.
    test::GltfBuilder small;
    textured_quad(small, add_vec2(small, kUvs));
    small.doc["images"] = json::array(
        {{{"bufferView", add_view(small, encode_image(dir, "q.png", 2, 2, kQuad))}}});
    const std::string msg2 = refuse(small, "limit.glb", true, 8);
    EXPECT_TRUE(contains(msg2, "memory limit")) << msg2;
}

TEST_F(HostileTexture, IndicesOutOfRange) {
    encode_image(dir, "q.png", 2, 2, kQuad);
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 7;
        const std::string msg = refuse(g, "tex.gltf");
        EXPECT_TRUE(contains(msg, "texture 7 does not exist")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        g.doc["textures"][0]["source"] = 3;
        const std::string msg = refuse(g, "src.gltf");
        EXPECT_TRUE(contains(msg, "source image")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        g.doc["textures"][0]["sampler"] = 5;
        const std::string msg = refuse(g, "sampler.gltf");
        EXPECT_TRUE(contains(msg, "sampler 5")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs), {{"wrapS", 1234}});
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        const std::string msg = refuse(g, "wrap.gltf");
        EXPECT_TRUE(contains(msg, "wrapS 1234")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"bufferView", 99}, {"mimeType", "image/png"}}});
        const std::string msg = refuse(g, "view.glb", true);
        EXPECT_TRUE(contains(msg, "bufferView") && contains(msg, "99")) << msg;
    }
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, kUvs));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
        const std::string msg = refuse(g, "set1.gltf");
        EXPECT_TRUE(contains(msg, "texCoord 1")) << msg;
    }
}

TEST_F(HostileTexture, TexcoordCountMismatchAndNanUvs) {
    encode_image(dir, "q.png", 2, 2, kQuad);
    {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, {{0, 0}, {1, 0}, {1, 1}}));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        const std::string msg = refuse(g, "count.gltf");
        EXPECT_TRUE(contains(msg, "TEXCOORD_0 has 3 values for 4 positions")) << msg;
    }
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        test::GltfBuilder g;
        textured_quad(g, add_vec2(g, {{0, 0}, {1, 0}, {bad, 1}, {0, 1}}));
        g.doc["images"] = json::array({{{"uri", "q.png"}}});
        const std::string msg = refuse(g, "nan.gltf");
        EXPECT_TRUE(contains(msg, "TEXCOORD_0 of vertex 2 is not finite")) << msg;
    }
}

}  // namespace
}  // namespace ht
