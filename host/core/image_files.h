// Image files (OpenImageIO) behind a module loaded on first use.
//
// Linking OpenImageIO makes the dynamic loader map and relocate ~260 shared libraries (its
// codecs: OpenEXR, ffmpeg, OpenCV, GDAL, DICOM, ...) before main: ~0.45 s of every process here,
// `--help` included (docs/PERFORMANCE.md §3 "Image files loaded on first use").  So only the
// module libhairtrace_image.so (host/image_files/) links it, and this file loads the module
// the first time an image is read or written, or a command checks an output's format that the
// kept list does not name (host/io/image_formats.h), or in the background (ImageFilesPreload).
// The rest of the renderer decides what goes into a file (host/io/image_io.cpp,
// host/split/partial_image.cpp, ...); the module only moves pixels and attributes between memory
// and OpenImageIO.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace ht {

// Metadata entries by type (EXR keeps the types; what other formats keep is image_io.cpp's
// business).
struct ImageAttributes {
    std::vector<std::pair<std::string, std::string>> text;
    std::vector<std::pair<std::string, int>> ints;
    std::vector<std::pair<std::string, float>> floats;

    int int_or(const std::string& name, int fallback) const {
        for (const auto& [k, v] : ints)
            if (k == name) return v;
        return fallback;
    }
    std::string text_or(const std::string& name, const std::string& fallback = "") const {
        for (const auto& [k, v] : text)
            if (k == name) return v;
        return fallback;
    }
};

// An image's layout: interleaved channels, float or 8-bit.
struct ImageFileSpec {
    int width = 0, height = 0, channels = 0;
    bool bytes = false;                      // 8-bit pixels (else 32-bit float)
    std::vector<std::string> channel_names;  // empty: the format's default names
    int alpha_channel = -1, z_channel = -1;
    ImageAttributes attributes;
};

// Outcomes of the module's calls; `error` carries OpenImageIO's message (may be empty).
enum class ImageFileStatus { Ok, NoFormat, OpenFailed, IoFailed };
struct ImageFileResult {
    ImageFileStatus status = ImageFileStatus::Ok;
    std::string error;
    bool ok() const { return status == ImageFileStatus::Ok; }
};

struct ImageTextLabel {
    int x = 0, y = 0;
    std::string text;
    int size = 12;  // pixels
};

namespace image_files {

// Writes `pixels` (spec.channels per pixel, float or bytes by spec.bytes) to `file`, in the format
// of `format_path`'s extension (so a temporary name can be written for the real one).  NoFormat:
// no writer for that extension.
ImageFileResult write(const std::string& format_path, const std::string& file, const ImageFileSpec& spec,
                      const void* pixels);

// Reads the first subimage's layout and its scalar int, float and text attributes into *spec,
// then, if `accept(*spec)` (may throw; empty: always), every channel as float into *pixels.
// OpenFailed: not an image OpenImageIO can open.
ImageFileResult read(const std::string& path, const std::function<bool(const ImageFileSpec&)>& accept,
                     ImageFileSpec* spec, std::vector<float>* pixels);

// Decodes an image held in memory with the named reader only ("png", "jpeg"), colour not
// premultiplied by alpha.  After opening, `accept(spec)` decides whether to read the pixels (it
// may throw: limits are checked before any pixel is allocated); then *pixels holds them as bytes.
ImageFileResult decode(const unsigned char* bytes, size_t size, const char* format_name,
                       const std::function<bool(const ImageFileSpec&)>& accept, ImageFileSpec* spec,
                       std::vector<unsigned char>* pixels);

// Draws the labels in black onto `rgb` (width x height x 3 floats) with the TrueType font `font`.
void render_text(std::vector<float>& rgb, int width, int height, const std::vector<ImageTextLabel>& labels,
                 const std::string& font);

// An OpenImageIO global attribute as text ("extension_list", "output_format_list").
std::string global_attribute(const std::string& name);

// Loads the module now (a no-op once loaded).  Throws ImageError naming the paths tried.
void load();

// The module file load() would open, as "path size mtime" ("" when the program links the module's
// code itself or there is none): what a list taken from the module is kept under.
std::string module_stamp();

}  // namespace image_files

// Loads the image module on a thread of its own, joined by the destructor: `render` overlaps the
// loading with its scene's set-up when the kept list of formats (host/io/image_formats.h) has
// already answered its output checks.  A failure is left for the first image call to report.
class ImageFilesPreload {
public:
    ImageFilesPreload();
    ~ImageFilesPreload();
    ImageFilesPreload(const ImageFilesPreload&) = delete;
    ImageFilesPreload& operator=(const ImageFilesPreload&) = delete;

private:
    std::thread thread_;
};

// The module's entry point: the functions above, as the module implements them.
struct ImageFilesApi {
    int abi;  // kImageFilesAbi
    ImageFileResult (*write)(const std::string&, const std::string&, const ImageFileSpec&, const void*);
    ImageFileResult (*read)(const std::string&, const std::function<bool(const ImageFileSpec&)>&, ImageFileSpec*,
                            std::vector<float>*);
    ImageFileResult (*decode)(const unsigned char*, size_t, const char*,
                              const std::function<bool(const ImageFileSpec&)>&, ImageFileSpec*,
                              std::vector<unsigned char>*);
    void (*render_text)(std::vector<float>&, int, int, const std::vector<ImageTextLabel>&, const std::string&);
    std::string (*global_attribute)(const std::string&);
};
// Raised whenever ImageFilesApi or the types it passes change, so a stale module is refused.
constexpr int kImageFilesAbi = 1;
// The module's file name (CMakeLists.txt's hairtrace_image) and its entry point's name.
constexpr const char* kImageFilesModule = "libhairtrace_image.so";
constexpr const char* kImageFilesEntry = "ht_image_files_api";

}  // namespace ht

// The entry point (named by kImageFilesEntry), defined by host/image_files/oiio_image_files.cpp.
extern "C" const ht::ImageFilesApi* ht_image_files_api();
