// The identity of a render: digests of the bytes of everything that shapes its image, in six
// parts so that a mismatch can say WHAT differs.  A checkpoint, a render-farm part and `merge`
// continue or combine only films whose identities are equal; the sample count is not part of it
// (a resume may raise --spp), nor is anything that never changes a bit (devices, pass size,
// geometry paging, --max-memory, threads).
#pragma once

#include "render/prepared_scene.h"
#include "scene/scene.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ht {

struct RenderIdentity {
    enum Part { Geometry, Materials, Lights, Camera, Settings, Aovs, kPartCount };
    std::array<uint64_t, kPartCount> digests{};

    bool operator==(const RenderIdentity& o) const { return digests == o.digests; }
    bool operator!=(const RenderIdentity& o) const { return digests != o.digests; }

    // One number for messages and metadata that only need "same or not".
    uint64_t key() const;
    // "different materials (--model, --sigma-a, ...) and a different camera": the parts where
    // this and `other` differ, with the options and scene contents each covers; "" when equal.
    std::string differences(const RenderIdentity& other) const;
    // "geometry=0123456789abcdef,materials=...": how partial images store it (EXR metadata).
    std::string to_text() const;
    // Throws std::invalid_argument when `text` is not what to_text() writes.
    static RenderIdentity from_text(const std::string& text);
};

// `scene` after every command-line override (materials, environment, default camera and
// light), `prepared` = prepare_scene(scene, settings) as the devices get it, the chunk size of
// the canonical summation order (split/accumulation.h) and the --aovs names (render/aovs.h; the
// set counts, not the order).  The AOV list is part of it because checkpoints and parts carry
// the AOV sums only when it is not empty, and merge writes the channels it names.
RenderIdentity render_identity(const Scene& scene, const PreparedScene& prepared, int chunk,
                               const std::vector<std::string>& aovs);
// The same, preparing the scene first (tests and tools that render nothing).
RenderIdentity render_identity(const Scene& scene, const RenderSettings& settings, int chunk,
                               const std::vector<std::string>& aovs = {});

}  // namespace ht
