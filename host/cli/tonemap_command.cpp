// hairtrace tonemap: a linear image (any renderer's EXR) to an 8-bit image through the same
// exposure and tone mapping `render` uses for its PNG/JPEG outputs, so that our render and
// another renderer's can be shown side by side mapped the same way (tools/pbrt-compare).
#include "cli/commands.h"
#include "cli/path_checks.h"
#include "io/image_io.h"

#include <cstdio>
#include <iostream>

namespace ht {

int cmd_tonemap(const std::vector<std::string>& args) {
    ArgParser p("tonemap", "Maps a linear image (.exr/.hdr/.tif) to an 8-bit sRGB image exactly as `render` maps its\n"
                           "PNG/JPEG outputs.");
    p.positional("IN", "linear input image")
        .path("-o", "OUT", "output image (.png/.jpg: tone mapped, .png with the input's alpha if it has one; .exr: the input unchanged)", PathKind::Image, "", true)
        .option("--exposure", "E|auto", kExposureHelp, "auto")
        .option("--tonemap", "filmic|clip", kToneMapHelp, "filmic")
        .flag("--quiet", "no report on stderr");
    p.parse(args);
    if (p.wants_help()) {
        std::cout << p.help();
        return kExitOk;
    }
    const std::string in = p.get("IN");
    check_path("tonemap: IN", in, PathKind::Input);
    const auto outputs = p.all("-o");
    if (outputs.empty()) throw UsageError("tonemap: no output given (-o OUT.png)");
    const std::optional<double> fixed_exposure = p.get_double_or("--exposure", "auto", 0, 1e9);
    const ToneMap tone_map = tone_map_from_name(p.get_choice("--tonemap", tone_map_names()));

    Film film;
    std::vector<float> rgb, alpha;
    try {
        rgb = read_rgb_image(in, film.width, film.height, &alpha);
    } catch (const ImageError& e) {
        throw UsageError(std::string("tonemap: ") + e.what());
    }
    film.rgba.resize(4 * size_t(film.width) * size_t(film.height));
    for (size_t i = 0; i < rgb.size() / 3; ++i) {
        for (int c = 0; c < 3; ++c) film.rgba[4 * i + c] = rgb[3 * i + c];
        film.rgba[4 * i + 3] = 1.0f;  // one "sample": the mean is the pixel
    }
    const float exposure = fixed_exposure ? float(*fixed_exposure) : auto_exposure(film);
    ImageMetadata meta;
    meta.text["hairtrace:source"] = in;
    meta.floats["hairtrace:exposure"] = exposure;
    meta.text["hairtrace:tonemap"] = tone_map_name(tone_map);
    // An input with alpha keeps it: straight in a PNG, as `render --aovs alpha` writes it.
    std::vector<ImageChannel> extra;
    if (!alpha.empty()) extra.push_back({"A", std::move(alpha)});
    for (const auto& o : outputs) {
        write_image(o, film, meta, exposure, tone_map, extra);
        if (!p.has("--quiet")) std::fprintf(stderr, "wrote %s (exposure %.6g, %s)\n", o.c_str(), exposure, tone_map_name(tone_map).c_str());
    }
    return kExitOk;
}

}  // namespace ht
