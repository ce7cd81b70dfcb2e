// hairtrace merge: combine render-farm parts (render --sample-range A:B) into the final image.
//
// The parts' segments are folded in the canonical chunk order (split/accumulation.h), so the
// result is bit for bit the image one `hairtrace render` with the same --spp/--chunk/--seed would
// have written, AOV channels (render --aovs) included.  The parts must come from the same render
// (same render identity, size, seed, spp, chunk), be disjoint and together cover [0, spp);
// anything else is reported and exits 2.  The merged image records its own command line and, in
// hairtrace:parts, every part's ("FILE: COMMAND" a line, in the order given), so that the render
// behind it can be told and run again.
#include "cli/commands.h"
#include "cli/path_checks.h"
#include "core/hash.h"
#include "io/image_io.h"
#include "render/aovs.h"
#include "split/accumulation.h"
#include "split/partial_image.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace ht {

namespace {
struct Located {
    FilmSegment seg;
    std::string file;
};
}  // namespace

int cmd_merge(const std::vector<std::string>& args) {
    ArgParser p("merge", "Combines the partial renders of `hairtrace render --sample-range A:B` exactly: the result is\n"
                         "bit for bit the image one render of all the samples would have written.");
    p.positional("PART", "a part's .exr, as render --sample-range wrote it", Arity::Many)
        .path("-o", "OUT", "merged image; the extension picks the format (.exr linear float, .png sRGB 8-bit)", PathKind::Image, "", true)
        .option("--exposure", "E|auto", kExposureHelp, "auto")
        .option("--tonemap", "filmic|clip", kToneMapHelp, "filmic")
        .flag("--quiet", "no report on stderr")
        .epilog("exit codes: 0 ok, 2 parts missing, overlapping or from different renders, 3 write failure");
    p.parse(args);
    if (p.wants_help()) {
        std::cout << p.help();
        return kExitOk;
    }
    const std::vector<std::string> parts = p.all("PART");
    for (const std::string& part : parts) check_path("merge: PART", part, PathKind::Input);
    const auto outputs = p.all("-o");
    if (outputs.empty()) throw UsageError("merge: no output given (-o OUT.exr and/or -o OUT.png)");
    const std::optional<double> fixed_exposure = p.get_double_or("--exposure", "auto", 0, 1e9);
    const ToneMap tone_map = tone_map_from_name(p.get_choice("--tonemap", tone_map_names()));
    const bool quiet = p.has("--quiet");

    std::vector<Located> all;
    PartialImage first;
    std::string part_commands;  // "FILE: COMMAND LINE", one line per part
    for (size_t i = 0; i < parts.size(); ++i) {
        PartialImage part = read_partial_exr(parts[i]);
        if (i == 0) first = part;
        part_commands += (i ? "\n" : "") + parts[i] + ": " +
                         (part.command_line.empty() ? "(no command line recorded)" : part.command_line);
        auto differ = [&](const std::string& what, long long a, long long b) {
            if (a != b)
                throw SceneError("merge: " + parts[i] + " has " + what + " " + std::to_string(b) + ", but " + parts[0] +
                                 " has " + std::to_string(a) + ": the parts belong to different renders");
        };
        differ("width", first.width, part.width);
        differ("height", first.height, part.height);
        differ("spp", first.spp_target, part.spp_target);
        differ("chunk", first.chunk, part.chunk);
        differ("seed", first.seed, part.seed);
        differ("max depth", first.max_depth, part.max_depth);
        if (part.identity != first.identity)
            throw SceneError("merge: " + parts[i] + " was rendered with " + part.identity.differences(first.identity) +
                             " than " + parts[0] + ": the parts belong to different renders");
        for (auto& s : part.segments) all.push_back({std::move(s), parts[i]});
    }
    std::sort(all.begin(), all.end(), [](const Located& a, const Located& b) { return a.seg.first < b.seg.first; });

    // Every problem at once: a farm operator wants the full list of jobs to rerun.
    const ChunkGrid grid{first.spp_target, first.chunk};
    std::vector<std::string> problems;
    auto range = [](int a, int b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + ")"; };
    int next = 0;
    for (size_t i = 0; i < all.size(); ++i) {
        const FilmSegment& s = all[i].seg;
        if (s.first > next) problems.push_back("samples " + range(next, s.first) + " are missing");
        if (s.first < next)
            problems.push_back(all[i].file + " and " + all[i - 1].file + " overlap on samples " +
                               range(s.first, std::min(next, s.first + s.count)));
        if (!grid.boundary(s.first + s.count))
            problems.push_back(all[i].file + " holds an unfinished chunk " + range(s.first, s.first + s.count) +
                               " (the part was interrupted; rerun it)");
        next = std::max(next, s.first + s.count);
    }
    if (next < grid.spp) problems.push_back("samples " + range(next, grid.spp) + " are missing");
    if (!problems.empty()) {
        std::string msg = "merge: the parts do not make up samples [0, " + std::to_string(grid.spp) + ") exactly:";
        for (auto& pr : problems) msg += "\n  " + pr;
        throw SceneError(msg);
    }

    // equal identities mean equal AOV lists (render/render_identity.h)
    SampleAccumulator acc(grid, first.width, first.height, aov_sums_per_pixel(first.aovs));
    for (auto& l : all) acc.add(std::move(l.seg));
    const Film film = acc.compose();
    ImageMetadata meta;
    std::vector<std::string> command_line = {"hairtrace", "merge"};
    command_line.insert(command_line.end(), args.begin(), args.end());
    meta.text["hairtrace:command_line"] = shell_words(command_line);
    meta.text["hairtrace:parts"] = part_commands;
    meta.ints["hairtrace:spp"] = grid.spp;
    meta.ints["hairtrace:seed"] = int(first.seed);
    meta.ints["hairtrace:max_depth"] = first.max_depth;
    meta.ints["hairtrace:chunk"] = grid.chunk;
    meta.ints["hairtrace:merged_parts"] = int(parts.size());
    meta.text["hairtrace:version"] = HT_VERSION;
    meta.text["hairtrace:scene"] = first.scene;
    meta.text["hairtrace:render_key"] = hex64(first.identity.key());
    const float exposure = fixed_exposure ? float(*fixed_exposure) : auto_exposure(film);
    meta.floats["hairtrace:exposure"] = exposure;
    meta.text["hairtrace:tonemap"] = tone_map_name(tone_map);
    const std::vector<ImageChannel> aovs = aov_channels(film, first.aovs);
    for (auto& o : outputs) {
        write_image(o, film, meta, exposure, tone_map, aovs);
        if (!quiet) std::fprintf(stderr, "wrote %s (%zu parts, %d spp)\n", o.c_str(), parts.size(), grid.spp);
    }
    return kExitOk;
}

}  // namespace ht
