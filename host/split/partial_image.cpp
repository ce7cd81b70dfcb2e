#include "split/partial_image.h"

#include "core/hash.h"
#include "render/aovs.h"

#include "core/image_files.h"
#include "core/temporary_path.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace ht {
namespace fs = std::filesystem;

namespace {
constexpr int kFormat = 2;  // hairtrace:partial; see partial_image.h

// The channels of segment i's raw sums, in the order film_sum() numbers them: (r, g, b, n), then
// the `aov_sums` AOV sums.
std::vector<std::string> segment_channels(int i, int aov_sums) {
    const std::string seg = "seg" + std::to_string(i) + ".";
    std::vector<std::string> names;
    for (const char* c : {"R", "G", "B", "N"}) names.push_back(seg + c);
    for (int k = 0; k < aov_sums; ++k) names.push_back(seg + "aov." + aov_sum_names()[k]);
    return names;
}

// Sum j of pixel p of a film with `aov_sums` AOV sums per pixel (numbered as segment_channels).
template <typename F>
auto& film_sum(F& film, size_t p, int j, int aov_sums) {
    return j < 4 ? film.rgba[4 * p + j] : film.aov[size_t(aov_sums) * p + (j - 4)];
}

std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
    return out;
}

// hairtrace:aovs back into names, each one of aov_names().
std::vector<std::string> aov_list(const std::string& text, const std::string& path) {
    std::vector<std::string> names;
    std::stringstream ss(text);
    for (std::string name; std::getline(ss, name, ',');) {
        if (std::find(aov_names().begin(), aov_names().end(), name) == aov_names().end())
            throw SceneError(path + ": corrupt hairtrace:aovs '" + text + "'");
        names.push_back(name);
    }
    return names;
}
}  // namespace

void write_partial_exr(const std::string& path, const PartialImage& part, const ImageMetadata& extra) {
    if (fs::path(path).extension() != ".exr")
        throw ImageError(path + ": a partial render (--sample-range) is written as .exr only");
    const size_t pixels = size_t(part.width) * size_t(part.height);
    const int nseg = int(part.segments.size());
    const int aov_sums = aov_sums_per_pixel(part.aovs);
    const int per_segment = 4 + aov_sums;

    SampleAccumulator acc(ChunkGrid{part.spp_target, part.chunk}, part.width, part.height, aov_sums);
    for (auto& s : part.segments) acc.add(s);
    const Film preview = acc.compose();
    const std::vector<ImageChannel> preview_aovs = aov_channels(preview, part.aovs);

    std::vector<std::string> names = {"R", "G", "B"};
    for (const ImageChannel& c : preview_aovs) names.push_back(c.name);
    const int first_sum = int(names.size());
    std::string seg_list;
    int held = 0;
    for (int i = 0; i < nseg; ++i) {
        for (std::string& c : segment_channels(i, aov_sums)) names.push_back(std::move(c));
        auto& s = part.segments[i];
        seg_list += (i ? "," : "") + std::to_string(s.first) + "+" + std::to_string(s.count);
        held += s.count;
    }
    const int nc = int(names.size());
    ImageFileSpec spec;
    spec.width = part.width;
    spec.height = part.height;
    spec.channels = nc;
    spec.channel_names = names;
    ImageAttributes& a = spec.attributes;
    a.text.emplace_back("compression", "zip");  // lossless: the sums must come back bit for bit
    for (auto& [k, v] : extra.text) a.text.emplace_back(k, v);
    for (auto& [k, v] : extra.ints) a.ints.emplace_back(k, v);
    for (auto& [k, v] : extra.floats) a.floats.emplace_back(k, v);
    a.ints.emplace_back("hairtrace:partial", kFormat);
    a.ints.emplace_back("hairtrace:sample_first", nseg ? part.segments[0].first : 0);
    a.ints.emplace_back("hairtrace:sample_count", held);
    a.ints.emplace_back("hairtrace:spp_target", part.spp_target);
    a.ints.emplace_back("hairtrace:chunk", part.chunk);
    a.ints.emplace_back("hairtrace:seed", int(part.seed));
    a.ints.emplace_back("hairtrace:max_depth", part.max_depth);
    a.text.emplace_back("hairtrace:render_identity", part.identity.to_text());
    a.text.emplace_back("hairtrace:render_key", hex64(part.identity.key()));
    a.text.emplace_back("hairtrace:segments", seg_list);
    a.text.emplace_back("hairtrace:scene", part.scene);
    a.text.emplace_back("hairtrace:aovs", joined(part.aovs));
    a.text.emplace_back("oiio:ColorSpace", "Linear");
    a.text.emplace_back("Software", std::string("hairtrace ") + HT_VERSION);

    std::vector<float> data(pixels * nc);
    for (size_t p = 0; p < pixels; ++p) {
        float* px = &data[p * nc];
        for (int c = 0; c < 3; ++c) px[c] = preview.mean(p, c);
        for (size_t a = 0; a < preview_aovs.size(); ++a) px[3 + a] = preview_aovs[a].values[p];
        for (int i = 0; i < nseg; ++i)
            for (int j = 0; j < per_segment; ++j)
                px[first_sum + per_segment * i + j] = film_sum(part.segments[i].film, p, j, aov_sums);
    }

    fs::path target(path);
    fs::path tmp = temporary_beside(target);
    const ImageFileResult written = image_files::write(path, tmp.string(), spec, data.data());
    if (written.status == ImageFileStatus::NoFormat) throw ImageError(path + ": OpenImageIO has no EXR writer");
    if (written.status == ImageFileStatus::OpenFailed) throw ImageError(path + ": cannot write: " + written.error);
    std::error_code ec;
    if (written.ok()) fs::rename(tmp, target, ec);
    if (!written.ok() || ec) {
        fs::remove(tmp, ec);
        throw ImageError(path + ": write failed" + (written.error.empty() ? std::string() : ": " + written.error));
    }
}

PartialImage read_partial_exr(const std::string& path) {
    PartialImage p;
    int aov_sums = 0;
    std::string segs;
    // The metadata is checked on the header, before the pixels are read.
    auto check_metadata = [&](const ImageFileSpec& spec) {
        const int format = spec.attributes.int_or("hairtrace:partial", 0);
        if (format == 1)
            throw SceneError(path + ": a partial render of an older hairtrace (format 1, without AOV sums); render "
                                    "it again with this one");
        if (format != kFormat) throw SceneError(path + ": not a partial render (render it with --sample-range A:B)");
        p.width = spec.width;
        p.height = spec.height;
        p.spp_target = spec.attributes.int_or("hairtrace:spp_target", 0);
        p.chunk = spec.attributes.int_or("hairtrace:chunk", 0);
        p.max_depth = spec.attributes.int_or("hairtrace:max_depth", 0);
        p.seed = uint32_t(spec.attributes.int_or("hairtrace:seed", 0));
        p.scene = spec.attributes.text_or("hairtrace:scene");
        p.aovs = aov_list(spec.attributes.text_or("hairtrace:aovs"), path);
        aov_sums = aov_sums_per_pixel(p.aovs);
        p.command_line = spec.attributes.text_or("hairtrace:command_line");
        const std::string identity = spec.attributes.text_or("hairtrace:render_identity");
        segs = spec.attributes.text_or("hairtrace:segments");
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
        return true;
    };
    ImageFileSpec spec;
    std::vector<float> all;
    const ImageFileResult r = image_files::read(path, check_metadata, &spec, &all);
    if (r.status == ImageFileStatus::OpenFailed) throw SceneError(path + ": cannot read: " + r.error);
    if (!r.ok()) throw SceneError(path + ": read failed: " + r.error);
    auto channel = [&](const std::string& name) {
        for (int c = 0; c < spec.channels; ++c)
            if (spec.channel_names[c] == name) return c;
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
        std::vector<int> ch;
        for (const std::string& name : segment_channels(i, aov_sums)) ch.push_back(channel(name));
        s.film.width = p.width;
        s.film.height = p.height;
        const size_t pixels = size_t(p.width) * p.height;
        s.film.rgba.resize(4 * pixels);
        s.film.aov.resize(size_t(aov_sums) * pixels);
        for (size_t px = 0; px < pixels; ++px)
            for (size_t j = 0; j < ch.size(); ++j)
                film_sum(s.film, px, int(j), aov_sums) = all[px * spec.channels + ch[j]];
        p.segments.push_back(std::move(s));
    }
    if (p.segments.empty()) throw SceneError(path + ": the partial render holds no samples");
    return p;
}

}  // namespace ht
