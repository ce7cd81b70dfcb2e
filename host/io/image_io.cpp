#include "io/image_io.h"

#include "core/image_files.h"
#include "core/temporary_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace ht {
namespace fs = std::filesystem;

namespace {
std::string lower_ext(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

float clean(float x) {
    if (!(x > 0)) return 0.0f;  // NaN and negatives
    return std::min(x, 1e30f);  // +inf: very bright but finite, so that ratios stay defined
}

float srgb_encode(float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

unsigned char to_byte(float x) { return (unsigned char)std::lround(255.0f * std::clamp(x, 0.0f, 1.0f)); }
}  // namespace

const std::vector<std::string>& tone_map_names() {
    static const std::vector<std::string> names = {"filmic", "clip"};
    return names;
}

ToneMap tone_map_from_name(const std::string& name) { return name == "clip" ? ToneMap::Clip : ToneMap::Filmic; }

const std::string& tone_map_name(ToneMap t) { return tone_map_names()[t == ToneMap::Clip ? 1 : 0]; }

const char* const kToneMapHelp =
    "how 8-bit outputs map radiance to display values: filmic = a curve on luminance with the colour scaled by "
    "the same ratio (keeps hue; bright saturated colours are desaturated only as far as they must to fit, "
    "near white), clip = each channel clipped at 1 (the old behaviour; highlights shift towards white-yellow)";
const char* const kExposureHelp =
    "multiplier applied before tone mapping 8-bit outputs; auto maps the 95th percentile of lit pixels' "
    "luminance to 0.8 (linear outputs are never scaled)";

float filmic_curve(float x) {
    constexpr float knee = 0.6f, room = 1.0f - knee;
    x = clean(x);
    if (x <= knee) return x;
    return knee + room * (1.0f - std::exp(-(x - knee) / room));
}

void tone_map_pixel(const float in[3], float out[3], ToneMap mode) {
    const float c[3] = {clean(in[0]), clean(in[1]), clean(in[2])};
    if (mode == ToneMap::Clip) {
        for (int k = 0; k < 3; ++k) out[k] = std::min(c[k], 1.0f);
        return;
    }
    const float lum = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
    if (!(lum > 0)) {  // black, or a colour with no luminance at all: nothing to show
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    const float display = filmic_curve(lum);
    const float scale = display / lum;
    float top = 0.0f;
    for (int k = 0; k < 3; ++k) top = std::max(top, out[k] = c[k] * scale);
    // Out of gamut: mix towards grey of the same luminance until the top channel is 1.  Hue (the
    // direction away from grey) and luminance stay; display < 1 so the mix factor is in (0, 1].
    if (top > 1.0f) {
        const float keep = (1.0f - display) / (top - display);
        for (int k = 0; k < 3; ++k) out[k] = std::clamp(display + keep * (out[k] - display), 0.0f, 1.0f);
    }
}

bool is_float_format(const std::string& path) {
    std::string e = lower_ext(path);
    return e == ".exr" || e == ".hdr" || e == ".pfm" || e == ".tif" || e == ".tiff";
}

bool is_8bit_alpha_format(const std::string& path) { return lower_ext(path) == ".png"; }

namespace {
// The bytes of an 8-bit image of the mean radiance `rgb` (3 per pixel): exposure, tone map, sRGB.
// With `coverage` (one per pixel, in [0, 1]) RGBA with straight alpha: the colour is the
// radiance divided by the coverage before the tone mapping (write_image says why), 0 where
// nothing covers the pixel.
std::vector<unsigned char> display_bytes(const std::vector<float>& rgb, const float* coverage, float exposure,
                                         ToneMap tone_map) {
    const size_t pixels = rgb.size() / 3;
    const int channels = coverage ? 4 : 3;
    std::vector<unsigned char> bytes(pixels * size_t(channels));
    for (size_t i = 0; i < pixels; ++i) {
        const float alpha = coverage ? coverage[i] : 1.0f;
        const float scale = alpha > 0 ? exposure / std::min(alpha, 1.0f) : 0.0f;
        const float exposed[3] = {rgb[3 * i] * scale, rgb[3 * i + 1] * scale, rgb[3 * i + 2] * scale};
        float display[3];
        tone_map_pixel(exposed, display, tone_map);
        unsigned char* px = &bytes[i * size_t(channels)];
        for (int k = 0; k < 3; ++k) px[k] = to_byte(srgb_encode(display[k]));
        if (coverage) px[3] = to_byte(alpha);
    }
    return bytes;
}
}  // namespace

std::vector<float> film_to_rgb(const Film& film) {
    size_t n = size_t(film.width) * size_t(film.height);
    std::vector<float> rgb(3 * n);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float v = film.mean(i, c);
            rgb[3 * i + c] = std::isfinite(v) ? v : 0.0f;  // the kernels never write NaN; belt and braces
        }
    return rgb;
}

float auto_exposure(const Film& film) {
    std::vector<float> lum;
    size_t n = size_t(film.width) * size_t(film.height);
    lum.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        float l = 0.2126f * film.mean(i, 0) + 0.7152f * film.mean(i, 1) + 0.0722f * film.mean(i, 2);
        if (std::isfinite(l) && l > 0) lum.push_back(l);
    }
    if (lum.empty()) return 1.0f;
    size_t k = std::min(lum.size() - 1, size_t(0.95 * double(lum.size())));
    std::nth_element(lum.begin(), lum.begin() + k, lum.end());
    return lum[k] > 0 ? 0.8f / lum[k] : 1.0f;
}

void write_image(const std::string& path, const Film& film, const ImageMetadata& meta, float exposure,
                 ToneMap tone_map, const std::vector<ImageChannel>& extra) {
    std::string ext = lower_ext(path);
    if (ext.empty()) throw ImageError(path + ": no file extension to choose an image format from");
    bool linear = is_float_format(path);
    const ImageChannel* alpha_8bit = nullptr;
    if (!linear && is_8bit_alpha_format(path))
        for (const ImageChannel& e : extra)
            if (e.name == "A") alpha_8bit = &e;
    std::vector<float> rgb = film_to_rgb(film);
    const size_t pixels = size_t(film.width) * size_t(film.height);
    const int channels = linear ? 3 + int(extra.size()) : alpha_8bit ? 4 : 3;
    ImageFileSpec spec;
    spec.width = film.width;
    spec.height = film.height;
    spec.channels = channels;
    spec.bytes = !linear;
    ImageAttributes& attrs = spec.attributes;
    if (alpha_8bit) {
        spec.channel_names = {"R", "G", "B", "A"};
        spec.alpha_channel = 3;
        // The bytes are straight alpha already; OpenImageIO would otherwise divide them once more.
        attrs.ints.emplace_back("oiio:UnassociatedAlpha", 1);
    } else if (linear && channels > 3) {
        std::vector<float> all(pixels * size_t(channels));
        for (size_t i = 0; i < pixels; ++i) {
            for (int c = 0; c < 3; ++c) all[i * channels + c] = rgb[3 * i + c];
            for (size_t e = 0; e < extra.size(); ++e) all[i * channels + 3 + e] = extra[e].values.at(i);
        }
        rgb.swap(all);
        spec.channel_names = {"R", "G", "B"};
        for (const ImageChannel& e : extra) spec.channel_names.push_back(e.name);
        for (size_t e = 0; e < extra.size(); ++e)
            if (extra[e].name == "A") spec.alpha_channel = int(3 + e);
            else if (extra[e].name == "Z") spec.z_channel = int(3 + e);
    }
    if (ext == ".exr") attrs.text.emplace_back("compression", "zip");
    // EXR keeps typed attributes; OIIO's PNG writer keeps only text ones (tEXt chunks) and drops
    // numbers silently, and its JPEG and TIFF writers keep neither, only standard tags.  So
    // other formats get the numbers as text, and every entry once more as "key: value" lines in
    // the standard ImageDescription (a JPEG comment, a TIFF tag).
    const bool typed = ext == ".exr";
    std::string description;
    auto put_text = [&](const std::string& k, const std::string& v) {
        attrs.text.emplace_back(k, v);
        description += k + ": " + v + "\n";
    };
    for (auto& [k, v] : meta.text) put_text(k, v);
    for (auto& [k, v] : meta.ints)
        if (typed) attrs.ints.emplace_back(k, v);
        else put_text(k, std::to_string(v));
    for (auto& [k, v] : meta.floats) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", double(v));
        if (typed) attrs.floats.emplace_back(k, v);
        else put_text(k, text);
    }
    if (!typed && !description.empty()) attrs.text.emplace_back("ImageDescription", description);
    attrs.text.emplace_back("oiio:ColorSpace", linear ? "Linear" : "sRGB");
    attrs.text.emplace_back("Software", std::string("hairtrace ") + HT_VERSION);

    std::vector<unsigned char> bytes;
    const void* data = rgb.data();
    if (!linear) {
        if (alpha_8bit && alpha_8bit->values.size() != pixels)
            throw ImageError(path + ": the alpha channel does not have one value per pixel");
        bytes = display_bytes(rgb, alpha_8bit ? alpha_8bit->values.data() : nullptr, exposure, tone_map);
        data = bytes.data();
    }

    // Write beside the target and rename: a failure never destroys the previous image.
    fs::path target(path);
    fs::path tmp = temporary_beside(target);
    // format from the real name's extension
    const ImageFileResult written = image_files::write(path, tmp.string(), spec, data);
    if (written.ok()) {
        std::error_code ec;
        fs::rename(tmp, target, ec);
        if (ec) {
            fs::remove(tmp, ec);
            throw ImageError(path + ": cannot rename the written image into place: " + ec.message());
        }
        return;
    }
    if (written.status == ImageFileStatus::NoFormat)
        throw ImageError(path + ": no image format for extension '" + ext + "'");
    if (written.status == ImageFileStatus::OpenFailed) throw ImageError(path + ": cannot write: " + written.error);
    std::error_code ec;
    fs::remove(tmp, ec);
    throw ImageError(path + ": write failed" + (written.error.empty() ? std::string() : ": " + written.error) +
                     " (any previous file was kept)");
}

std::vector<float> read_rgb_image(const std::string& path, int& width, int& height,
                                  std::vector<float>* alpha) {
    ImageFileSpec spec;
    std::vector<float> all;
    const ImageFileResult r = image_files::read(path, nullptr, &spec, &all);
    if (r.status == ImageFileStatus::OpenFailed) throw ImageError(path + ": cannot read: " + r.error);
    if (!r.ok()) throw ImageError(path + ": read failed: " + r.error);
    width = spec.width;
    height = spec.height;
    const int nc = spec.channels;
    std::vector<float> rgb(size_t(width) * height * 3);
    for (size_t i = 0; i < size_t(width) * height; ++i)
        for (int c = 0; c < 3; ++c) rgb[3 * i + c] = all[i * nc + std::min(c, nc - 1)];
    if (alpha) {
        alpha->clear();
        if (spec.alpha_channel >= 0) {
            alpha->resize(size_t(width) * height);
            for (size_t i = 0; i < alpha->size(); ++i) (*alpha)[i] = all[i * nc + spec.alpha_channel];
        }
    }
    return rgb;
}

}  // namespace ht
