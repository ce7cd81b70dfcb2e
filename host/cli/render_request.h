// The typed request of `hairtrace render` and `hairtrace converge`: their options are declared in
// one table and parsed once, with one rule for each setting, so that the same words on either
// command line render the same image.  Parsing checks every value and path; nothing here loads
// the scene or touches a device.
#pragma once

#include "cli/args.h"
#include "cli/commands.h"
#include "io/image_io.h"
#include "split/accumulation.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace ht {

enum class RenderCommand { Render, Converge };

// --device: the default device, some indices, or every device.
struct DeviceChoice {
    bool all = false;
    std::vector<int> indices;  // empty and !all: the default device
};

// What shapes the image (besides the sample count): shared by render and converge.
struct ImageRequest {
    std::string scene;
    LoadOptions load;
    RenderSettings settings;              // size, seed, clamp, regularisation, features, memory bound
    std::optional<std::string> model;     // --model: every material's fibre model
    std::optional<Vec3f> sigma_a;         // --sigma-a: every hair material's absorption
    std::optional<int> max_depth;         // --max-depth; nullopt: auto
    std::optional<int> light_samples;     // --first-hit-light-samples; nullopt: auto (one per light)
    std::string indirect = "exact";       // exact | afs | none
    std::optional<uint32_t> fiber_field;  // --fiber-field; nullopt: auto, or the materials' own with --model
    std::optional<Vec3f> background;
    HairColorOverride hair_color;         // --hair-preset, --eumelanin, --pheomelanin, --hair-color
    ViewOptions view;                     // --up-axis, --look-from, --look-at, --up, --fov
    std::string environment;
    float environment_intensity = 1.0f;
    DeviceChoice devices;
    std::string kernel_dir;
};

// Everything `hairtrace render` was asked for.
struct RenderRequest {
    ImageRequest image;
    std::vector<std::string> outputs;       // -o, in order
    ChunkGrid grid;                         // --spp, --chunk
    std::optional<SampleRange> sample_range;
    double time_limit = 0;                  // seconds; 0: none
    std::string checkpoint, resume, reference;
    std::string dump_rays;  // --dump-rays DIR (render/ray_dump.h)
    double checkpoint_every = 60;
    std::optional<float> exposure;          // nullopt: auto
    std::vector<std::string> aovs;          // --aovs, in the order given (render/aovs.h names)
    ToneMap tone_map = ToneMap::Filmic;     // --tonemap, for 8-bit outputs
    bool verbose = false, profile = false, quiet = false;
    std::vector<std::string> command_line;  // every word, for the images' metadata (set by the command)
};

// --camera-rays and --shadow-rays auto|lists|tree (also converge's camera_rays and shadow_rays keys)
RenderSettings::ListChoice list_choice(const std::string& word);

// The words --model and --indirect accept (converge's --configs keys take the same).
const std::vector<std::string>& fiber_model_names();
const std::vector<std::string>& indirect_mode_names();

// Declares the options of `command` grouped by topic (scene loading options included).
void add_render_options(ArgParser& p, RenderCommand command);
ImageRequest parse_image_request(const ArgParser& p);
RenderRequest parse_render_request(const ArgParser& p);

// Applies the overrides (--model, --sigma-a, --background, --environment...) to a loaded scene and
// adds the default camera and light it lacks.
void apply_scene_overrides(Scene& scene, const ImageRequest& request);

// The settings a render of `scene` uses: the request's, with the path depth chosen (auto: from the
// materials; `why` receives the explanation) and the one rule for --indirect and --fiber-field.
RenderSettings resolve_settings(const Scene& scene, const ImageRequest& request, std::string* why = nullptr);

// A --sample-range part writes its raw sums (for `hairtrace merge`) to the .exr outputs only;
// other formats show the part's mean.
bool keeps_raw_sums(const std::string& output);

// The rgb floats of a --reference image of the render's size; an unreadable file or another size
// is a usage error (exit 2) naming the file.
std::vector<float> read_reference_image(const std::string& path, int width, int height);

// The OpenCL device indices of a choice (-1: the default device).
std::vector<int> device_indices(const DeviceChoice& choice);

}  // namespace ht
