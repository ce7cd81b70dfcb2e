#include "split/partial_image.h"

#include "core/hash.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace ht {
namespace fs = std::filesystem;
using namespace OIIO;

void write_partial_exr(const std::string& path, const PartialImage& part, const ImageMetadata& extra) {
    if (fs::path(path).extension() != ".exr")
        throw ImageError(path + ": a partial render (--sample-range) is written as .exr only");
    const size_t pixels = size_t(part.width) * size_t(part.height);
    const int nseg = int(part.segments.size());
    const int nc = 3 + 4 * nseg;
    ImageSpec spec(part.width, part.height, nc, TypeDesc::FLOAT);
    std::vector<std::string> names = {"R", "G", "B"};
    std::string seg_list;
    int held = 0;
    for (int i = 0; i < nseg; ++i) {
        for (const char* c : {".R", ".G", ".B", ".N"}) names.push_back("seg" + std::to_string(i) + c);
        auto& s = part.segments[i];
        seg_list += (i ? "," : "") + std::to_string(s.first) + "+" + std::to_string(s.count);
        held += s.count;
    }
    spec.channelnames = names;
    spec.attribute("compression", "zip");  // lossless: the sums must come back bit for bit
    for (auto& [k, v] : extra.text) spec.attribute(k, v);
    for (auto& [k, v] : extra.ints) spec.attribute(k, v);
    for (auto& [k, v] : extra.floats) spec.attribute(k, v);
    spec.attribute("hairtrace:partial", 1);
    spec.attribute("hairtrace:sample_first", nseg ? part.segments[0].first : 0);
    spec.attribute("hairtrace:sample_count", held);
    spec.attribute("hairtrace:spp_target", part.spp_target);
    spec.attribute("hairtrace:chunk", part.chunk);
    spec.attribute("hairtrace:seed", int(part.seed));
    spec.attribute("hairtrace:max_depth", part.max_depth);
    spec.attribute("hairtrace:render_identity", part.identity.to_text());
    spec.attribute("hairtrace:render_key", hex64(part.identity.key()));
    spec.attribute("hairtrace:segments", seg_list);
    spec.attribute("hairtrace:scene", part.scene);
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("Software", std::string("hairtrace ") + HT_VERSION);

    SampleAccumulator acc(ChunkGrid{part.spp_target, part.chunk}, part.width, part.height);
    for (auto& s : part.segments) acc.add(s);
    const Film preview = acc.compose();
    std::vector<float> data(pixels * nc);
    for (size_t p = 0; p < pixels; ++p) {
        float* px = &data[p * nc];
        for (int c = 0; c < 3; ++c) px[c] = preview.mean(p, c);
        for (int i = 0; i < nseg; ++i)
            for (int c = 0; c < 4; ++c) px[3 + 4 * i + c] = part.segments[i].film.rgba[4 * p + c];
    }

    fs::path target(path);
    fs::path tmp = target.parent_path() / (".tmp." + std::to_string(::getpid()) + "." + target.filename().string());
    auto out = ImageOutput::create(path);
    if (!out) throw ImageError(path + ": OpenImageIO has no EXR writer");
    if (!out->open(tmp.string(), spec)) throw ImageError(path + ": cannot write: " + out->geterror());
    bool ok = out->write_image(TypeDesc::FLOAT, data.data());
    std::string err = out->geterror();
    ok = out->close() && ok;
    std::error_code ec;
    if (ok) fs::rename(tmp, target, ec);
    if (!ok || ec) {
        fs::remove(tmp, ec);
        throw ImageError(path + ": write failed" + (err.empty() ? std::string() : ": " + err));
    }
}

PartialImage read_partial_exr(const std::string& path) {
    auto in = ImageInput::open(path);
    if (!in) throw SceneError(path + ": cannot read: " + OIIO::geterror());
    const ImageSpec spec = in->spec();
    if (spec.get_int_attribute("hairtrace:partial", 0) != 1)
        throw SceneError(path + ": not a partial render (render it with --sample-range A:B)");
    PartialImage p;
    p.width = spec.width;
    p.height = spec.height;
    p.spp_target = spec.get_int_attribute("hairtrace:spp_target", 0);
    p.chunk = spec.get_int_attribute("hairtrace:chunk", 0);
    p.max_depth = spec.get_int_attribute("hairtrace:max_depth", 0);
    p.seed = uint32_t(spec.get_int_attribute("hairtrace:seed", 0));
    p.scene = spec.get_string_attribute("hairtrace:scene");
    p.command_line = spec.get_string_attribute("hairtrace:command_line");
    const std::string identity = spec.get_string_attribute("hairtrace:render_identity");
    const std::string segs = spec.get_string_attribute("hairtrace:segments");
    if (p.spp_target < 1 || p.chunk < 1)
        throw SceneError(path + ": partial render metadata is missing or corrupt");
    if (identity.empty())
        throw SceneError(path + ": no hairtrace:render_identity: the part was written by an older hairtrace; "
                                "render it again with this one");
    try {
        p.identity = RenderIdentity::from_text(identity);
    } catch (const std::invalid_argument& e) {
        throw SceneError(path + ": corrupt hairtrace:render_identity: " + e.what());
    }

    std::vector<float> all(size_t(p.width) * p.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, all.data()))
        throw SceneError(path + ": read failed: " + in->geterror());
    in->close();
    auto channel = [&](const std::string& name) {
        for (int c = 0; c < spec.nchannels; ++c)
            if (spec.channelnames[c] == name) return c;
        throw SceneError(path + ": channel " + name + " is missing");
    };
    std::stringstream ss(segs);
    std::string item;
    for (int i = 0; std::getline(ss, item, ','); ++i) {
        FilmSegment s;
        auto plus = item.find('+');
        try {
            if (plus == std::string::npos) throw std::invalid_argument("no +");
            s.first = std::stoi(item.substr(0, plus));
            s.count = std::stoi(item.substr(plus + 1));
        } catch (const std::exception&) {
            throw SceneError(path + ": corrupt hairtrace:segments '" + segs + "'");
        }
        int ch[4];
        const char* suffix[4] = {".R", ".G", ".B", ".N"};
        for (int c = 0; c < 4; ++c) ch[c] = channel("seg" + std::to_string(i) + suffix[c]);
        s.film.width = p.width;
        s.film.height = p.height;
        const size_t pixels = size_t(p.width) * p.height;
        s.film.rgba.resize(4 * pixels);
        for (size_t px = 0; px < pixels; ++px)
            for (int c = 0; c < 4; ++c) s.film.rgba[4 * px + c] = all[px * spec.nchannels + ch[c]];
        p.segments.push_back(std::move(s));
    }
    if (p.segments.empty()) throw SceneError(path + ": the partial render holds no samples");
    return p;
}

}  // namespace ht
