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

// How 8-bit outputs map radiance (after --exposure) to display values in [0, 1].
//  * Filmic (the default) keeps hue: the curve filmic_curve() is applied to the luminance
//    (Rec. 709 weights) and all three channels are scaled by the same ratio, so a blond lock keeps
//    its hue in the highlights instead of going grey-white as channels clip one by one.  Where the
//    scaled colour would leave the display gamut (a channel above 1: bright saturated colours
//    only), it is mixed towards the grey of the same luminance just enough to fit: luminance and
//    hue stay, saturation drops, and only near white.
//  * Clip: the colour times the exposure, each channel clipped to [0, 1] (the behaviour before
//    the filmic mapping; saturated highlights turn white-yellow, hue shifts channel by channel).
enum class ToneMap { Filmic, Clip };
const std::vector<std::string>& tone_map_names();  // "filmic", "clip": --tonemap's words
ToneMap tone_map_from_name(const std::string& name);  // a name of tone_map_names()
const std::string& tone_map_name(ToneMap t);
// --tonemap's help and --exposure's, shared by every command that writes 8-bit images.
extern const char* const kToneMapHelp;
extern const char* const kExposureHelp;

// The filmic curve on luminance: the identity up to the knee 0.6 (auto exposure puts the 95th
// percentile at 0.8, just above it), then an exponential shoulder that meets it with slope 1
// and approaches 1 without reaching it: f(0.8) = 0.757, f(1) = 0.853, f(2) = 0.988.  Monotone;
// 0 for NaN and anything <= 0, 1 for +infinity.
float filmic_curve(float luminance);

// One pixel: linear rgb (already multiplied by the exposure) to display-linear rgb in [0, 1]
// (sRGB encoding comes after).  NaN and negative channels count as 0, +infinity as very bright.
void tone_map_pixel(const float in[3], float out[3], ToneMap mode);

// Throws ImageError naming the file on failure.  `exposure` and `tone_map` shape 8-bit outputs
// only; float formats get the radiance unchanged, and the `extra` channels after R, G, B (an
// A channel there is premultiplied alpha, as OpenEXR defines it: the film's radiance already is
// coverage times the colour of what covers the pixel).  8-bit images hold the tone-mapped
// beauty, and formats with alpha (is_8bit_alpha_format) an A channel of `extra` as straight
// alpha, as PNG defines it: each pixel's colour is divided by its coverage before the tone
// mapping, so an edge pixel shows the colour of the hair and its alpha how much of it there is.
// Where the camera sees an environment (--background, --environment) the beauty holds it behind
// the hair: background pixels become transparent, but edge pixels keep its share in their colour.
void write_image(const std::string& path, const Film& film, const ImageMetadata& meta,
                 float exposure = 1.0f, ToneMap tone_map = ToneMap::Filmic,
                 const std::vector<ImageChannel>& extra = {});

// Reads a float RGB(A) image (reference images): width, height, rgb (3 per pixel).  With `alpha`,
// also the file's alpha channel (one per pixel, as stored), or an empty vector if it has none.
std::vector<float> read_rgb_image(const std::string& path, int& width, int& height,
                                  std::vector<float>* alpha = nullptr);

bool is_float_format(const std::string& path);
// 8-bit formats whose files can hold an alpha channel: .png.
bool is_8bit_alpha_format(const std::string& path);

// An exposure that maps the 95th percentile of the non-black pixels' luminance to 0.8: a
// sensible default for looking at an image whose absolute scale is arbitrary.  A high percentile
// would follow the Monte Carlo sparkles of low sample counts (builtin:strand depth 5: the 99.5th
// percentile halves from 16 to 64 spp, the 95th moves 0.7 %), so highlights above it clip instead.
// Returns 1 for an all-black film.
float auto_exposure(const Film& film);

}  // namespace ht
