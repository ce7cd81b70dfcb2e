// The subcommands of the hairtrace executable.  Each takes the arguments after its name and
// returns the process exit code; errors are thrown (see main.cpp for their exit codes).
#pragma once

#include "cli/args.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

int cmd_render(const std::vector<std::string>& args);
int cmd_info(const std::vector<std::string>& args);
int cmd_devices(const std::vector<std::string>& args);
int cmd_converge(const std::vector<std::string>& args);
int cmd_merge(const std::vector<std::string>& args);
int cmd_tonemap(const std::vector<std::string>& args);

// The SCENE argument of every command that reads a scene, with its help.
void add_scene_argument(ArgParser& p);
// Scene-loading options shared by every command that reads a scene.
void add_scene_options(ArgParser& p);
LoadOptions scene_load_options(const ArgParser& p);
// --up-axis, --look-from, --look-at, --up, --fov (for ensure_camera_and_light).
ViewOptions scene_view_options(const ArgParser& p);
// --hair-preset, --eumelanin, --pheomelanin, --hair-color: every hair material's absorption
// source, read when the options are parsed (a UsageError when combined with each other or with
// --sigma-a) and applied to the loaded scene.
struct HairColorOverride {
    enum Kind { None, Melanin, Color } kind = None;
    float eumelanin = 0.0f, pheomelanin = 0.0f;
    Vec3f color{0, 0, 0};
};
HairColorOverride hair_color_options(const ArgParser& p);
void apply_hair_color(const HairColorOverride& o, Scene& scene);

// --model / configs model=: sets every material's fibre model; throws UsageError for unknown names.
void apply_model_override(Scene& scene, const std::string& model);

// near|far|auto|material -> HT_FIELD_*; throws UsageError naming `what` otherwise.
uint32_t parse_fiber_field(const std::string& what, const std::string& value);

// --light-guiding / configs light_guiding=: a share, auto (kAutoLightGuiding) or off (0); throws
// UsageError naming `what` otherwise.
float parse_light_guiding(const std::string& what, const std::string& value);

// "r,g,b" or a single value for all three.
Vec3f parse_rgb(const std::string& option, const std::string& text);

}  // namespace ht
