// HT_PATH_GRID_PARAMS (kernels/stages/stage_args.h): the path rays' grid (render/path_grid.h) on a
// device, as the stages that walk it take it: the renderer's path and shadow stages
// (features[PATH_GRID]) and bench's DeviceTracer, which runs those same stages (bvh/device_geometry.h).
#pragma once

#include "cl/arg_bundle.h"
#include "kernels/types.h"

#include <CL/opencl.hpp>

namespace ht {

struct PathGridBuffers {
    cl::Buffer cells, entries;
    HtPathGrid grid{};
};

// Calls f(name, value) for each argument of the bundle, in the kernels' order.
template <typename F>
void for_each_arg(const PathGridBuffers& g, F&& f) {
    f("grid_cells", g.cells);
    f("grid_entries", g.entries);
    f("grid", g.grid);
}

}  // namespace ht
