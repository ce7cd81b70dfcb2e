#include "cli/render_request.h"

#include "cl/device.h"
#include "cli/commands.h"
#include "io/image_io.h"
#include "kernels/types.h"
#include "render/depth_choice.h"
#include "render/aovs.h"
#include "render/memory_plan.h"
#include "render/prepared_scene.h"

#include <algorithm>
#include <sstream>

namespace ht {

namespace {

enum Uses { kRender = 1, kConverge = 2, kBoth = 3 };
enum class Kind { Flag, Value, InputFile, InputFolder, Images, Checkpoint };

struct OptionRow {
    const char* group;
    const char* name;
    const char* value;  // the value's form in --help
    const char* help;
    const char* default_value;
    Kind kind;
    int uses;
};

// Every option of render and converge besides the scene-loading ones, grouped as --help shows
// them.  A new option is one row here and one line in parse_image_request/parse_render_request.
const OptionRow kOptions[] = {
    {"output", "-o", "OUT", "output image; the extension picks the format (.exr/.hdr/.tif linear float, .png/.jpg sRGB 8-bit)", "", Kind::Images, kRender},
    {"output", "--aovs", "LIST", "comma-separated output values, written as extra channels of the .exr/.hdr/.tif outputs: alpha (A: coverage, premultiplied; it also makes .png outputs RGBA, with straight alpha), depth (Z: mean hit distance), tangent (first hit's fibre tangent), albedo (first vertex's directional albedo), direct, indirect (light scattered at most once / more; direct + indirect = the beauty), R, TT, TRT, residual (the hair's share split by the lobes of the first hair vertex)", "", Kind::Value, kRender},
    {"output", "--exposure", "E|auto", kExposureHelp, "auto", Kind::Value, kRender},
    {"output", "--tonemap", "filmic|clip", kToneMapHelp, "filmic", Kind::Value, kRender},

    {"sampling", "--width", "W", "image width in pixels", "512", Kind::Value, kRender},
    {"sampling", "--height", "H", "image height in pixels", "512", Kind::Value, kRender},
    {"sampling", "--width", "W", "image width in pixels (must match the reference)", "256", Kind::Value, kConverge},
    {"sampling", "--height", "H", "image height in pixels (must match the reference)", "256", Kind::Value, kConverge},
    {"sampling", "--spp", "N", "samples per pixel (hair-to-hair light through narrow fibre lobes sparkles below ~64)", "64", Kind::Value, kRender},
    {"sampling", "--seed", "S", "random seed; the image depends only on seed, spp, scene and options", "1", Kind::Value, kBoth},
    {"sampling", "--chunk", "K", "samples per chunk: the image is the sum of K-sample chunk films added in chunk order, which every split (devices, MPI ranks, --sample-range parts) reproduces exactly; K >= spp is the plain sequential sum", "16", Kind::Value, kRender},
    {"sampling", "--target-error", "E|off", "adaptive sampling: after --min-spp samples everywhere, each further --chunk of samples goes only to the 8x8-pixel tiles whose relative error estimate exceeds E, until every tile is below E, --spp (now the maximum) or --time-limit is reached. A pixel's estimate is |Y(even half) - Y(odd half)| / (2 (Y + eps)): half the difference between the means of its even- and odd-numbered samples (an estimate of the standard error of its mean) over its luminance Y, eps = 0.1x the image's mean luminance; a tile's is the RMS over its pixels (e.g. 0.02: about 2 % noise). Prints the achieved estimate (largest tile, RMS over tiles); .exr outputs get an spp channel. Deterministic, exact with checkpoints and several devices; not with --sample-range or MPI", "off", Kind::Value, kRender},
    {"sampling", "--min-spp", "N", "with --target-error: samples every pixel gets before the estimate decides (rounded up to whole --chunk)", "16", Kind::Value, kRender},
    {"sampling", "--sample-range", "A:B", "render-farm part: render samples [A, B) of --spp only (A, B multiples of --chunk or B = spp); the .exr output then holds the raw sums for `hairtrace merge`", "", Kind::Value, kRender},

    {"light transport", "--max-depth", "D|auto", "path length in fibre bounces (1 = direct light only); auto: from the materials' averaged attenuation (AFS_TT^avg^D < 0.2, Zinke 2004 §5)", "auto", Kind::Value, kBoth},
    {"light transport", "--indirect", "exact|afs|dual|none", "hair-to-hair light: exact = path traced to --max-depth; afs = traced to --max-depth (auto: 1), then the paper's averaged attenuation: the last bounce's shadow rays cross hair with AFS_TT^avg per fibre; dual = dual scattering (Zinke et al. 2008): exact single scattering at the camera hit, all multiple scattering approximated from the fibres its shadow rays cross plus precomputed local back-scattering, no path beyond the first hit (depth 1): fast but biased (docs/PERFORMANCE.md §5 tables its bias against exact depth-20 path tracing and its time); none = direct light with opaque hair (depth 1)", "exact", Kind::Value, kBoth},
    {"light transport", "--model", "kajiya|marschner|zinke|chiang", "override every material's fibre model", "", Kind::Value, kBoth},
    {"light transport", "--fiber-field", "near|far|auto|material", "for marschner/zinke materials: near field (zinke) everywhere, far field (marschner) everywhere, or auto: near where a fibre covers at least half a camera pixel's footprint and for hair-to-hair light, far elsewhere; with --model and no --fiber-field: material", "auto", Kind::Value, kBoth},
    {"light transport", "--features", "scene|all|all-lobes", "what the kernels are compiled with: what the scene needs (lights, models, meshes, fibre lobes above 1e-3 of R's energy for some material; --verbose lists them), everything, or the scene's choice with every lobe kept (A/B comparisons)", "scene", Kind::Value, kBoth},
    {"light transport", "--clamp-indirect", "C|off", "cap the contribution of every light path that scattered at two or more surfaces at C (radiance, largest rgb channel, hue kept): fewer sparkles at low sample counts at the cost of a bias that must be measured per scene (builtin:strand, irradiance 1: C = 3 removes 2.8 % of the light, C = 1 14.5 %)", "off", Kind::Value, kBoth},
    {"sampling", "--first-hit-splits", "N|auto", "continue every camera path N times from its first hit, each with 1/N of the weight, while the camera ray, its hit and its direct light are computed once: N hair-to-hair samples per camera sample (1 = one path per camera sample); auto: N from 2 to 8 chosen per scene by a pilot render (8 samples with 2 continuations, twice with seeds of its own, over a sixteenth of the pixels and at most about 1024 of them) that measures how much of a sample's variance the continuations carry and what they cost in rays, the N with the least work to a given error; the same choice for the same scene and options, reported on stderr and in the image metadata (docs/ESTIMATOR.md, docs/PERFORMANCE.md section 8)", "auto", Kind::Value, kBoth},
    {"sampling", "--first-hit-light-samples", "M|auto", "at the first hit of every camera path, M next-event estimates (each 1/M of the weight, each picking a light from its own M-th of the choice) instead of one; auto: one per light that next-event estimation picks from (the lights and an environment map), so that every light is met once at the first hit (1 = one estimate, as with a single light; measured in docs/PERFORMANCE.md section 8)", "auto", Kind::Value, kBoth},
    {"sampling", "--light-threshold", "T|off", "from the second vertex of a path on, next-event estimates whose weight without the light (throughput x fibre scattering value, largest channel, for the whole camera sample) is below T trace their shadow ray only with probability weight / T and then count T / weight times: unbiased, fewer shadow rays for faint deep estimates at a little more noise (relative to the light, so the same T suits any light intensity; the default paid on every scene measured, docs/PERFORMANCE.md section 8); with it, Russian roulette judges the continuation into the last vertex (--max-depth) at 4x its throughput, since this roulette judges that vertex's estimate again", "0.1", Kind::Value, kBoth},
    {"sampling", "--light-guiding", "F|auto|off", "the share of the continuations from a path's first four fibre vertices drawn from a lobe about 18 degrees wide around the direction to a light (one of those that reach it, picked evenly; up to 16) instead of from the fibre's scattering function, each continuation weighted by the value over the mixture of both densities: unbiased, and the rare bright paths through a fibre lying between the path and a light become common (light through a lock), at one more scattering evaluation per continuation (later vertices are not guided: the weights' spread would multiply over hundreds of bounces); auto: 0.2 in a scene lit by its lights alone, off where an environment gives light too (it comes from every direction, and guided weights add noise there; measured in docs/PERFORMANCE.md section 8); off, and for scenes without lights or for surfaces, no guiding", "auto", Kind::Value, kBoth},
    {"sampling", "--light-vertices", "N|off", "light-vertex next-event estimation: each camera sample also traces N light rays from the scene's point, spot and directional lights, which take turns (a point or spot light's uniform in the cone towards the scene's bounding sphere, a directional light's uniform over a disc across it that covers the scene), and every fibre vertex before the last connects to the first fibre hit of one of them, picked at random, with a shadow ray between the two fibres; the connection and the vertex's continuations share those paths by multiple importance sampling, so the sum stays unbiased and the light that reaches a fibre through a lit neighbour no longer arrives only as a rare bright sample, at one more shadow ray and two scattering evaluations per vertex; needs a point, spot or directional light, not with --indirect afs or dual or with --aovs; off at --max-depth 1; measured in docs/PERFORMANCE.md section 8 (not the default: it did not pay)", "off", Kind::Value, kBoth},
    {"sampling", "--light-pick", "importance|uniform", "how a next-event estimate that picks one light chooses it (every estimate after the first vertex; the first vertex's with --first-hit-light-samples 1): importance = half in proportion to what each light delivers to the shading point unshadowed (radiance over distance squared, a spot's falloff, a sphere's cone) times how squarely it faces the fibre or surface there, half evenly over the lights that reach the point, so no estimate is spent on a light that cannot reach it (unbiased); uniform = each light alike (A/B: the images of before). Scenes with one light or more than 16 always pick uniformly; an environment map keeps its uniform share (measured in docs/PERFORMANCE.md section 8)", "importance", Kind::Value, kBoth},
    {"sampling", "--camera-rays", "auto|lists|tree", "how camera rays find their closest hit: auto = lists when spp times the image's pixels reaches 4 per segment (below that they cost more to make than they save); lists = each pixel's candidates (the primitives whose projected bounds, widened by 1/64 pixel, overlap it), nearest first, tested in groups of eight through the tree's leaf test and stopping at the first group beyond the closest hit; a pixel with more than 1,024 candidates, and every pixel when the projection is unbounded (geometry reaching the eye's plane), traverses the tree; the lists are capped at 2^24 entries of 8 bytes (the per-pixel cap halves until they fit), and left out when the device holds the render only without them (stderr says so); the same hits as the tree, bit for bit; tree = every camera ray traverses the BVH (A/B; measured in docs/PERFORMANCE.md section 8)", "auto", Kind::Value, kBoth},
    {"sampling", "--shadow-rays", "auto|lists|tree", "how shadow rays toward a directional, point or spot light find a blocker: auto = lists when the first-vertex shadow rays that would use them (spp times the pixels that see geometry times the first-hit light samples; none with --indirect dual, whose stage does not read them, or afs at depth 1) reach 0.6 per entry the lists would hold, estimated from a sample of the primitives before they are made (below that they cost more to build than they save); lists = a grid across each directional light's direction (cells of 4 mean fibre radii, at most 4 cells per segment and 4096 a side), each cell listing the primitives whose shadow covers it by how far towards the light they reach, and for a point or spot light outside the hair (everything in front of it within 63 degrees of one axis) a grid on the image a camera at the light would see (cells of 4 mean fibre radii at the hair's mean depth, the same limits), each cell listing the primitives whose image, widened by two fibre widths, covers it, nearest the light first; the first 4 such lights; a shadow ray tests its cell's list from its origin on (towards a point light: the entries nearer the light than its origin), stopping at the first blocker, instead of traversing the tree; a cell with more than 1,024 entries keeps the tree; left out, before the camera's lists, when the device holds the render only without them (stderr says so); the same answers as the tree; tree = no lists: every shadow ray traverses the BVH, or walks the path rays' grid when the render has one (--path-rays; the same answers, docs/PERFORMANCE.md section 1 \"Shadow rays through the path grid\") (A/B; measured in docs/PERFORMANCE.md section 8)", "auto", Kind::Value, kBoth},
    {"sampling", "--path-rays", "auto|grid|tree", "how the path rays (every ray after the camera's) find their closest hit: grid = a uniform grid over the capsules (cells of 0.7 x the edge of one segment's share of the hair's bounding box, larger where capsules would each be listed in more than 14 cells or fewer than 6 share an occupied cell; each cell lists the capsules it may meet), walked cell by cell from the ray's origin and tested eight capsules at a time until the closest hit lies before the next cell; tree = the BVH from the node of the path's last hit; auto = the grid when spp times the image's pixels times (max depth - 1) reaches 8 per segment and the scene has at most 3.7 million segments (the grid then stays under 256 MiB) and each of the grid's arrays fits one buffer of the device (else auto says so and takes the tree; grid exits 3 with the sizes) and at least 3 % of its cells hold capsules (hair in clumps far apart shares one box whose cells are too coarse for it), the tree otherwise; a scene with triangles, and a render of depth 1, keep the tree; with the grid, the shadow rays that no lists serve (--shadow-rays) walk it too, stopping at the first blocker; the same answers either way (measured in docs/PERFORMANCE.md section 1)", "auto", Kind::Value, kBoth},
    {"sampling", "--empty-pixels", "skip|trace", "pixels whose every camera ray provably misses all geometry (an empty candidate list with --camera-rays lists; else the projection of no primitive's bounds, widened by a pixel, overlaps them): skip = not traced, given the background's value in every sample, the same bits as tracing them (not with an environment map or --aovs, nor while --dump-rays records the camera rays); trace = every pixel traced (A/B; measured in docs/PERFORMANCE.md section 8)", "skip", Kind::Value, kBoth},
    {"sampling", "--samples-per-pass", "N", "how many consecutive samples of each traced pixel one pass of the wavefront renders, when a pass holds them all (at most 2^18 camera paths; else one sample per pass as before): a pixel's samples are neighbouring work-items that find its candidate list and fibres in cache, and each stage is launched once for all of them; the same image bits for any N (1 = a pass per sample, A/B; measured in docs/PERFORMANCE.md section 8)", "8", Kind::Value, kBoth},
    {"sampling", "--sampler", "sobol|independent", "random numbers: Owen-scrambled Sobol' points (each jointly used pair stratified, kernels/rng.h) or independent counter-based hashing (A/B); measured in docs/PERFORMANCE.md", "sobol", Kind::Value, kBoth},
    {"light transport", "--spawn-offset", "capsule|pbrt", "where rays leaving a fibre start: just outside its capsule, or 1-1.73 fibre diameters off it along the normal as pbrt-v4 offsets its curves' rays (a diagnostic for comparing with pbrt renders: rays then skip the nearest neighbours; docs/ESTIMATOR.md)", "capsule", Kind::Value, kBoth},
    {"light transport", "--regularize", "DEG|off", "path regularisation: where a path meets hair after a first scattering, widen the marschner/zinke lobes to at least DEG degrees (longitudinal widths and zinke's azimuthal spread); bright two-lobe sparkles become a blur of indirect highlights (biased; measured in docs/PERFORMANCE.md)", "off", Kind::Value, kBoth},

    {"scene overrides", "--sigma-a", "R,G,B", "override every hair material's absorption: sigma_a per unit radius (replaces melanin or colour)", "", Kind::Value, kBoth},
    {"scene overrides", "--background", "R,G,B", "uniform environment radiance, found by the fibres' own sampling (uniform light directions would rarely meet narrow lobes: no next-event estimation); replaces the scene's", "", Kind::Value, kBoth},
    {"scene overrides", "--environment", "FILE", "lat-long HDR environment map (.exr/.hdr, +y up); replaces the scene's", "", Kind::InputFile, kBoth},
    {"scene overrides", "--environment-intensity", "K", "multiplier for the environment", "1", Kind::Value, kBoth},

    {"long renders", "--time-limit", "SECONDS", "stop after the pass that crosses this wall time (a pass renders up to --samples-per-pass samples; 0 = none)", "0", Kind::Value, kRender},
    {"long renders", "--checkpoint", "FILE", "write the progressive state to FILE (atomically) every --checkpoint-every seconds, at the end (after the images) and on SIGINT/SIGTERM", "", Kind::Checkpoint, kRender},
    {"long renders", "--checkpoint-every", "SECONDS", "checkpoint interval", "60", Kind::Value, kRender},
    {"long renders", "--resume", "FILE", "continue a render from a checkpoint (same scene, options and seed)", "", Kind::Value, kRender},

    {"devices", "--device", "I|I,J,..|all", "OpenCL device index from `hairtrace devices` (default: first CPU/GPU); several devices split the chunks between them (one host thread each, work stealing), with the same image", "", Kind::Value, kBoth},
    {"devices", "--max-memory", "SIZE", "upper bound for host memory while loading and for device memory while rendering, e.g. 512M or 8G; inputs that need more are refused before allocating, with the size named", "", Kind::Value, kBoth},
    {"devices", "--bvh-oriented", "auto|R|off", "oriented-box BVH nodes where their children's count-weighted box area is below R x the axis-aligned one: each child box along its segments' dominant direction; off: axis-aligned boxes only; auto: R = 0.8 (the measured value) when the render takes at least 4 path vertices per segment (width x height x spp x max depth), where the traversal wins their longer build back, else off. Every tree gives the same hits and images. They pay on long fibres (render time: the 3.2M-segment head 0.88-0.90x, straight.hair 0.94-0.95x; the head's build +0.6-0.9 s) and cost nothing measurable on locks of short segments (the anchor strand, the ball); +1 (strand) to +7 (straight.hair) bytes/segment; docs/PERFORMANCE.md section 1", "auto", Kind::Value, kBoth},
    {"devices", "--bvh-oriented-splits", "R|off", "with oriented nodes (not --bvh-oriented off): the builder also bins each node of 16 or more segments in the frame of its segments' dominant direction and splits there where that split's count-weighted box area is below R x the best axis-aligned split's (1 measured), so bundles of fibres across the axes are cut along and across the fibres; hits are the same. Pays in long renders of large heads (the 3.2M-segment head at 128 spp: render 0.95x, path rays 1.08-1.21x faster than oriented nodes alone), not on the anchor strand or straight.hair; the build takes 1.5x as long; docs/PERFORMANCE.md section 1", "off", Kind::Value, kBoth},
    {"devices", "--kernel-dir", "DIR", "load kernel sources from DIR instead of the embedded copies", "", Kind::InputFolder, kBoth},

    {"reporting", "--reference", "REF", "linear image to compare with: prints RMSE, relMSE, max error, NaN count, the share of sparkles (pixels off by more than 10x the reference's 3x3 local standard deviation, docs/PERFORMANCE.md) and each rgb channel's image mean over the reference's", "", Kind::InputFile, kRender},
    {"reporting", "--verbose", "", "print the kernel features chosen for the scene and the build options", "", Kind::Flag, kRender},
    {"reporting", "--profile", "", "time every stage kernel separately and print the split (slows the render a little)", "", Kind::Flag, kRender},
    {"reporting", "--dump-rays", "DIR", "write the rays the render traces (closest hit and shadow, per bounce, the first 1,048,576 of each) with this tracer's answers to DIR/<scene>.b<bounce>.{closest,shadow}.rays, the Embree anchor's format with its content hash of the scene (hair only; so the anchor's hair_refcheck takes them with the scene's .hair file), for `hairtrace bench --rays` (with several devices: the first device's share); beside a closest-hit set, .starts: the node each ray's traversal started at (its path's last hit's), so that bench also times them as the render traced them (only when the tree traces the path rays: --path-rays tree, or auto below its threshold; bench times every set by the grid too)", "", Kind::Value, kRender},
    {"reporting", "--quiet", "", "no progress output on stderr", "", Kind::Flag, kBoth},
};

void declare(ArgParser& p, const OptionRow& row) {
    p.group(row.group);
    switch (row.kind) {
    case Kind::Flag: p.flag(row.name, row.help); break;
    case Kind::Value: p.option(row.name, row.value, row.help, row.default_value); break;
    case Kind::InputFile: p.path(row.name, row.value, row.help, PathKind::Input); break;
    case Kind::InputFolder: p.path(row.name, row.value, row.help, PathKind::InputFolder); break;
    case Kind::Images: p.path(row.name, row.value, row.help, PathKind::Image, "", true); break;
    case Kind::Checkpoint: p.path(row.name, row.value, row.help, PathKind::AnyOutput); break;
    }
}

DeviceChoice parse_device_choice(const ArgParser& p) {
    DeviceChoice choice;
    if (!p.has("--device")) return choice;
    const std::string v = p.get("--device");
    if (v == "all") {
        choice.all = true;
        return choice;
    }
    const UsageError bad = p.error("--device", "must be an index, a list like 0,2, or all; got '" + v + "'");
    std::stringstream ss(v);
    for (std::string item; std::getline(ss, item, ',');) {
        if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos || item.size() > 4) throw bad;
        const int d = std::stoi(item);
        if (std::count(choice.indices.begin(), choice.indices.end(), d))
            throw p.error("--device", v + ": device " + item + " is listed twice");
        choice.indices.push_back(d);
    }
    if (choice.indices.empty()) throw bad;
    return choice;
}

FeatureMode feature_mode(const std::string& word) {
    if (word == "all") return FeatureMode::All;
    if (word == "all-lobes") return FeatureMode::AllLobes;
    return FeatureMode::Scene;
}

}  // namespace

RenderSettings::ListChoice list_choice(const std::string& word) {
    if (word == "lists") return RenderSettings::ListChoice::Lists;
    if (word == "tree") return RenderSettings::ListChoice::Tree;
    return RenderSettings::ListChoice::Auto;
}

const std::vector<std::string>& fiber_model_names() {
    static const std::vector<std::string> names = {"kajiya", "marschner", "zinke", "chiang"};
    return names;
}

const std::vector<std::string>& indirect_mode_names() {
    static const std::vector<std::string> names = {"exact", "afs", "dual", "none"};
    return names;
}

void add_render_options(ArgParser& p, RenderCommand command) {
    add_scene_argument(p);
    const int use = command == RenderCommand::Render ? kRender : kConverge;
    for (const OptionRow& row : kOptions)
        if (row.uses & use) declare(p, row);
    p.group("scene");
    add_scene_options(p);
}

ImageRequest parse_image_request(const ArgParser& p) {
    ImageRequest r;
    r.scene = p.get("SCENE");
    r.load = scene_load_options(p);
    r.view = scene_view_options(p);
    r.hair_color = hair_color_options(p);
    RenderSettings& s = r.settings;
    s.width = p.get_int("--width", 1, 16384);
    s.height = p.get_int("--height", 1, 16384);
    s.seed = uint32_t(p.get_int("--seed", 0, 2147483647));
    if (p.has("--model")) r.model = p.get_choice("--model", fiber_model_names());
    if (p.has("--sigma-a")) r.sigma_a = parse_rgb("--sigma-a", p.get("--sigma-a"));
    r.max_depth = p.get_int_or("--max-depth", "auto", 1, 1000);
    r.indirect = p.get_choice("--indirect", indirect_mode_names());
    if (r.indirect == "none" && r.max_depth && *r.max_depth != 1)
        throw UsageError("--indirect none renders direct light only; it contradicts --max-depth " + p.get("--max-depth"));
    if (r.indirect == "dual" && r.max_depth && *r.max_depth != 1)
        throw UsageError("--indirect dual stands for all multiple scattering at the first hit (depth 1); it contradicts "
                         "--max-depth " + p.get("--max-depth"));
    if (p.has("--fiber-field")) r.fiber_field = parse_fiber_field("--fiber-field", p.get("--fiber-field"));
    s.features = feature_mode(p.get_choice("--features", {"scene", "all", "all-lobes"}));
    s.clamp_indirect = float(p.get_double_or("--clamp-indirect", "off", 1e-30, 3.0e38).value_or(0.0));
    s.regularize_deg = float(p.get_double_or("--regularize", "off", 0.1, 90).value_or(0.0));
    s.light_threshold = float(p.get_double_or("--light-threshold", "off", kMinLightThreshold, kMaxLightThreshold).value_or(0.0));
    s.light_guiding = parse_light_guiding("--light-guiding", p.get("--light-guiding"));
    s.light_vertices = uint32_t(p.get_int_or("--light-vertices", "off", 1, int(kMaxLightVertices)).value_or(0));
    s.bvh_oriented = float(parse_auto_off_or_double("--bvh-oriented", p.get("--bvh-oriented"), 0.01, 1, kAutoOriented));
    s.bvh_oriented_splits = float(p.get_double_or("--bvh-oriented-splits", "off", 0.01, 2).value_or(0.0));
    if (s.bvh_oriented_splits > 0 && s.bvh_oriented == 0)
        throw p.error("--bvh-oriented-splits", "needs oriented nodes (not --bvh-oriented off): the splits serve oriented boxes");
    if (p.get_choice("--spawn-offset", {"capsule", "pbrt"}) == "pbrt") s.spawn_offset = RenderSettings::SpawnOffset::Pbrt;
    if (p.get_choice("--sampler", {"sobol", "independent"}) == "independent") s.sampler = RenderSettings::Sampler::Independent;
    s.skip_empty_pixels = p.get_choice("--empty-pixels", {"skip", "trace"}) == "skip";
    s.camera_lists = list_choice(p.get_choice("--camera-rays", {"auto", "lists", "tree"}));
    s.samples_per_pass = p.get_int("--samples-per-pass", 1, kMaxSamplesPerPass);
    s.shadow_lists = list_choice(p.get_choice("--shadow-rays", {"auto", "lists", "tree"}));
    {
        const std::string w = p.get_choice("--path-rays", {"auto", "grid", "tree"});
        s.path_rays = w == "grid"   ? RenderSettings::PathRays::Grid
                      : w == "tree" ? RenderSettings::PathRays::Tree
                                    : RenderSettings::PathRays::Auto;
    }
    if (p.get_choice("--light-pick", {"importance", "uniform"}) == "importance")
        s.light_pick = RenderSettings::LightPick::Importance;
    s.first_hit_splits = p.get_int_or("--first-hit-splits", "auto", 1, kMaxFirstHitSplits).value_or(kAutoFirstHitSplits);
    r.light_samples = p.get_int_or("--first-hit-light-samples", "auto", 1, kMaxFirstHitSplits);
    if (p.has("--background")) r.background = parse_rgb("--background", p.get("--background"));
    r.environment = p.get("--environment");
    r.environment_intensity = float(p.get_double("--environment-intensity", 0, 1e12));
    if (p.has("--max-memory")) {
        try {
            s.max_device_bytes = parse_bytes(p.get("--max-memory"));
        } catch (const std::exception& e) {
            throw UsageError(std::string("--max-memory: ") + e.what());
        }
        r.load.max_bytes = s.max_device_bytes;
    }
    r.devices = parse_device_choice(p);
    r.kernel_dir = p.get("--kernel-dir");
    return r;
}

namespace {
// --aovs: known names, each once, and somewhere to write them.
std::vector<std::string> parse_aov_list_of(const std::string& text, const RenderRequest& r) {
    std::vector<std::string> names;
    for (const std::string& item : split_fields(text, ',')) {
        const std::string& name = require_choice("--aovs", item, aov_names());
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
    // Alpha alone fits a .png too (RGBA); every other value needs a float format.
    const bool alpha_only = names == std::vector<std::string>{"alpha"};
    const auto holds_them = [&](const std::string& o) {
        return is_float_format(o) || (alpha_only && is_8bit_alpha_format(o));
    };
    if (std::none_of(r.outputs.begin(), r.outputs.end(), holds_them))
        throw UsageError(alpha_only ? "--aovs alpha needs an .exr, .hdr, .tif or .png output: other 8-bit formats hold no alpha"
                                    : "--aovs " + text + " needs an .exr, .hdr or .tif output: 8-bit images hold the "
                                      "tone-mapped beauty only (and alpha, in .png)");
    return names;
}
}  // namespace

RenderRequest parse_render_request(const ArgParser& p) {
    RenderRequest r;
    r.image = parse_image_request(p);
    r.outputs = p.all("-o");
    if (r.outputs.empty()) throw UsageError("render: no output given (-o OUT.exr and/or -o OUT.png)");
    r.grid = ChunkGrid{p.get_int("--spp", 1, 1 << 24), p.get_int("--chunk", 1, 1 << 24)};
    r.image.settings.spp = r.grid.spp;
    if (p.has("--sample-range")) {
        r.sample_range = parse_sample_range(p.get("--sample-range"), r.grid);
        if (std::none_of(r.outputs.begin(), r.outputs.end(), keeps_raw_sums))
            throw UsageError("--sample-range needs an .exr output: only it keeps the raw sums `hairtrace merge` combines");
    }
    if (auto e = p.get_double_or("--target-error", "off", 1e-6, 100)) {
        if (r.sample_range)
            throw p.error("--target-error", "cannot be combined with --sample-range: which pixels a chunk renders "
                                            "depends on the chunks before it, which another part renders");
        RenderSettings& s = r.image.settings;
        s.target_error = float(*e);
        const int k = r.grid.chunk;
        s.adaptive_min_spp = std::min(r.grid.spp, (p.get_int("--min-spp", 2, 1 << 24) + k - 1) / k * k);
    } else if (p.has("--min-spp")) {
        throw p.error("--min-spp", "only applies with --target-error");
    }
    r.time_limit = p.get_double("--time-limit", 0, 1e9);
    r.checkpoint = p.get("--checkpoint");
    r.checkpoint_every = p.get_double("--checkpoint-every", 0.01, 1e9);
    r.resume = p.get("--resume");
    r.reference = p.get("--reference");
    r.dump_rays = p.get("--dump-rays");
    if (auto e = p.get_double_or("--exposure", "auto", 0, 1e9)) r.exposure = float(*e);
    if (p.has("--aovs")) {
        r.aovs = parse_aov_list_of(p.get("--aovs"), r);
        r.image.settings.aovs = true;
        if (r.image.indirect == "dual")
            throw UsageError("--aovs cannot split --indirect dual's light by lobe or bounce; render without one of them");
    }
    r.tone_map = tone_map_from_name(p.get_choice("--tonemap", tone_map_names()));
    r.verbose = p.has("--verbose");
    r.profile = r.image.settings.profile_stages = p.has("--profile");
    r.quiet = p.has("--quiet");
    return r;
}

void apply_scene_overrides(Scene& scene, const ImageRequest& r) {
    if (r.model) apply_model_override(scene, *r.model);
    if (r.sigma_a)
        for (auto& mat : scene.materials) mat.set_sigma_a(*r.sigma_a);
    if (r.background) scene.environment = Environment{"", *r.background, 1.0f};
    if (!r.environment.empty()) scene.environment.map_path = r.environment;
    scene.environment.intensity *= r.environment_intensity;
    apply_hair_color(r.hair_color, scene);
    ensure_camera_and_light(scene, r.view);
}

// --light-vertices: what it needs and what it cannot be combined with, as usage errors
// (render/prepared_scene.h); off where no vertex has a connection to make (the settings say what
// the render does).
void check_light_vertices(const Scene& scene, RenderSettings& s) {
    const std::string refusal = light_vertices_refusal(scene, s);
    if (!refusal.empty()) throw UsageError(refusal);
    s.light_vertices = effective_light_vertices(s.light_vertices, s.max_depth);
}

RenderSettings resolve_settings(const Scene& scene, const ImageRequest& r, std::string* why) {
    RenderSettings s = r.settings;
    // An explicit --model is taken literally unless --fiber-field says otherwise.
    s.fiber_field = r.fiber_field ? *r.fiber_field : r.model ? HT_FIELD_MATERIAL : HT_FIELD_AUTO;
    if (r.indirect == "afs") s.indirect = RenderSettings::Indirect::Afs;
    if (r.indirect == "dual") {
        s.indirect = RenderSettings::Indirect::Dual;
        for (const HairMaterialDesc& m : scene.materials)
            if (m.model == "kajiya")
                throw UsageError("--indirect dual needs a model with R/TT/TRT lobes (marschner, zinke, chiang); material '" +
                                 m.name + "' is kajiya");
    }
    if (r.indirect == "none" || r.indirect == "dual" || (r.indirect == "afs" && !r.max_depth)) {
        s.max_depth = 1;
    } else if (r.max_depth) {
        s.max_depth = *r.max_depth;
    } else {
        const DepthChoice choice = choose_max_depth(scene);
        s.max_depth = choice.depth;
        if (why) *why = choice.why;
    }
    // auto: one estimate per light next-event estimation picks from (kernels/stages/shade.cl
    // ht_nee_sample: the lights and an environment map), each light met once at the first hit
    const int nee_lights = int(scene.lights.size()) + (scene.environment.map_path.empty() ? 0 : 1);
    s.first_hit_light_samples = r.light_samples.value_or(std::clamp(nee_lights, 1, kMaxFirstHitSplits));
    // the settings say what the render does: without a choice among lights the pick is uniform
    if (!light_pick_chooses(scene.lights.size())) s.light_pick = RenderSettings::LightPick::Uniform;
    check_light_vertices(scene, s);
    return s;
}

std::vector<float> read_reference_image(const std::string& path, int width, int height) {
    int w = 0, h = 0;
    std::vector<float> rgb;
    try {
        rgb = read_rgb_image(path, w, h);
    } catch (const ImageError& e) {
        throw UsageError(std::string("--reference: ") + e.what());
    }
    if (w != width || h != height)
        throw UsageError("--reference " + path + " is " + std::to_string(w) + "x" + std::to_string(h) +
                         ", the render is " + std::to_string(width) + "x" + std::to_string(height));
    return rgb;
}

bool keeps_raw_sums(const std::string& output) {
    const auto dot = output.rfind('.');
    std::string e = dot == std::string::npos ? "" : output.substr(dot);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e == ".exr";
}

std::vector<int> device_indices(const DeviceChoice& choice) {
    if (!choice.all) return choice.indices.empty() ? std::vector<int>{-1} : choice.indices;
    std::vector<int> out;
    for (size_t i = 0; i < list_devices().size(); ++i) out.push_back(int(i));
    if (out.empty()) throw DeviceError("--device all: no OpenCL device found");
    return out;
}

}  // namespace ht
