// Renders chunks of samples on one or more OpenCL devices, one host thread per device.
//
// Load balance is by work stealing: each device thread claims the next unrendered chunk from a
// shared queue as soon as it finishes its previous one, so a device twice as fast renders about
// twice as many chunks without any up-front throughput estimate.  Which device renders a chunk
// does not change its bits, and the finished chunks are folded on the calling thread in the
// canonical order (SampleAccumulator), so the image is the same for any number of devices.
#pragma once

#include "split/accumulation.h"
#include "render/renderer.h"

#include <functional>
#include <string>
#include <vector>

namespace ht {

struct DeviceShare {
    std::string name;
    int chunks = 0, samples = 0;
    double busy_seconds = 0;  // time spent rendering (throughput = samples / busy_seconds)
};

struct ChunkRunHooks {
    std::function<bool()> should_stop;          // polled about every 50 ms; true stops after the current sample
    std::function<void(int samples)> progress;  // samples rendered by this run so far
    std::function<void()> chunk_finished;       // after a finished chunk was added (checkpoints)
};

// Renders `chunks` (chunk indices of acc's grid; an unfinished segment held by acc for one of
// them is continued, not restarted) and adds the results to acc.  On a stop, every device
// finishes its current sample and the unfinished chunks are added as unfinished segments, so
// nothing rendered is lost.  A device failure stops the others and is rethrown here.
std::vector<DeviceShare> render_chunks(const std::vector<Renderer*>& devices, const std::vector<std::string>& names,
                                       SampleAccumulator& acc, const std::vector<int>& chunks,
                                       const ChunkRunHooks& hooks);

}  // namespace ht
