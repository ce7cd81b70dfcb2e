#include "core/image_files.h"

#include "core/errors.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>

// Weak: a program that links the module's code itself (the fuzz targets, tests/fuzz/CMakeLists.txt)
// defines the entry point; the renderer does not (its address is null) and loads the module.
extern "C" const ht::ImageFilesApi* ht_image_files_api() __attribute__((weak));

namespace ht {

namespace {

namespace fs = std::filesystem;

// Beside the executable (the build tree), or in the installed layout's lib/hairtrace.
std::vector<fs::path> module_candidates() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {fs::path(kImageFilesModule)};
    const fs::path dir = exe.parent_path();
    return {dir / kImageFilesModule, dir.parent_path() / "lib" / "hairtrace" / kImageFilesModule};
}

const ImageFilesApi* open_module() {
    if (ht_image_files_api) return ht_image_files_api();
    std::string tried;
    for (const fs::path& path : module_candidates()) {
        std::error_code ec;
        if (!fs::exists(path, ec)) {
            tried += "\n  " + path.string() + ": not found";
            continue;
        }
        // Never closed: OpenImageIO keeps threads and static state for the process's lifetime.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* err = dlerror();
            tried += "\n  " + path.string() + ": " + (err ? err : "cannot load");
            continue;
        }
        using Entry = const ImageFilesApi* (*)();
        auto entry = reinterpret_cast<Entry>(dlsym(handle, kImageFilesEntry));
        const ImageFilesApi* api = entry ? entry() : nullptr;
        if (!api || api->abi != kImageFilesAbi) {
            tried += "\n  " + path.string() + ": not this hairtrace's image module (rebuild or reinstall)";
            continue;
        }
        return api;
    }
    throw ImageError("cannot load the image module (OpenImageIO), tried:" + tried);
}

std::once_flag g_once;
const ImageFilesApi* g_api = nullptr;
std::string g_error;

const ImageFilesApi& api() {
    std::call_once(g_once, [] {
        try {
            g_api = open_module();
        } catch (const std::exception& e) {
            g_error = e.what();
        }
    });
    if (!g_api) throw ImageError(g_error);
    return *g_api;
}

}  // namespace

namespace image_files {

ImageFileResult write(const std::string& format_path, const std::string& file, const ImageFileSpec& spec,
                      const void* pixels) {
    return api().write(format_path, file, spec, pixels);
}

ImageFileResult read(const std::string& path, const std::function<bool(const ImageFileSpec&)>& accept,
                     ImageFileSpec* spec, std::vector<float>* pixels) {
    return api().read(path, accept, spec, pixels);
}

ImageFileResult decode(const unsigned char* bytes, size_t size, const char* format_name,
                       const std::function<bool(const ImageFileSpec&)>& accept, ImageFileSpec* spec,
                       std::vector<unsigned char>* pixels) {
    return api().decode(bytes, size, format_name, accept, spec, pixels);
}

void render_text(std::vector<float>& rgb, int width, int height, const std::vector<ImageTextLabel>& labels,
                 const std::string& font) {
    api().render_text(rgb, width, height, labels, font);
}

std::string global_attribute(const std::string& name) { return api().global_attribute(name); }

void load() { (void)api(); }

std::string module_stamp() {
    if (ht_image_files_api) return "";
    for (const fs::path& path : module_candidates()) {
        std::error_code ec;
        const auto size = fs::file_size(path, ec);
        if (ec) continue;
        const auto mtime = fs::last_write_time(path, ec);
        if (ec) continue;
        return path.string() + " " + std::to_string(size) + " " +
               std::to_string(mtime.time_since_epoch().count());
    }
    return "";
}

}  // namespace image_files

ImageFilesPreload::ImageFilesPreload()
    : thread_([] {
          try {
              image_files::load();
          } catch (const std::exception&) {
              // the first image call reports it
          }
      }) {}

ImageFilesPreload::~ImageFilesPreload() { thread_.join(); }

}  // namespace ht
