// Writing images through OpenImageIO: the extension picks the format.  Float formats (.exr,
// .hdr, .tif/.tiff as float) get linear radiance; 8-bit formats (.png, .jpg, ...) get an sRGB
// tone-mapped image.  Files are written to a temporary name and renamed, so a failed write (full
// disk, permissions) leaves any previous file intact.
#pragma once

#include "core/errors.h"
#include "core/film.h"

#include <map>
#include <string>
#include <vector>

namespace ht {

struct ImageMetadata {
    std::map<std::string, std::string> text;    // e.g. "hairtrace:device"
    std::map<std::string, int> ints;            // e.g. "hairtrace:spp"
    std::map<std::string, float> floats;        // e.g. "hairtrace:render_seconds"
};

// A channel written after R, G, B by float formats (render --aovs).
struct ImageChannel {
    std::string name;           // e.g. "A", "Z", "direct.R"
    std::vector<float> values;  // one per pixel, row 0 at the top
};

// Mean radiance per pixel, RGB, row 0 at the top.
std::vector<float> film_to_rgb(const Film& film);

// Throws ImageError naming the file on failure.  `extra` channels go into float formats only
// (8-bit images hold the tone-mapped beauty).
void write_image(const std::string& path, const Film& film, const ImageMetadata& meta,
                 float exposure = 1.0f, const std::vector<ImageChannel>& extra = {});

// Reads a float RGB(A) image (reference images): width, height, rgb (3 per pixel).
std::vector<float> read_rgb_image(const std::string& path, int& width, int& height);

bool is_float_format(const std::string& path);

// An exposure that maps the 95th percentile of the non-black pixels' luminance to 0.8: a
// sensible default for looking at an image whose absolute scale is arbitrary.  A high percentile
// would follow the Monte Carlo sparkles of low sample counts (builtin:strand depth 5: the 99.5th
// percentile halves from 16 to 64 spp, the 95th moves 0.7 %), so highlights above it clip instead.
// Returns 1 for an all-black film.
float auto_exposure(const Film& film);

}  // namespace ht
