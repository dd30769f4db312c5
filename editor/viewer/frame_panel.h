#pragma once
// What the viewer shows of the last frame: each pass's times, the counters and the memory.
#include <map>
#include <string>
#include <vector>

#include "graph/executor.h"

namespace caustica::editor {

// The passes in order with GPU and CPU times and a bar chart of the GPU time over the last 120
// frames drawn (kept in `gpu_history`), culled passes greyed.
void frame_panel(const graph::FrameResult& frame, const graph::Plan& plan, std::map<std::string, std::vector<float>>& gpu_history);
// Every counter, and transient memory with and without aliasing (and the acceleration structures').
void counters_and_memory(const graph::FrameResult& frame, const graph::Plan& plan, const scene::GpuScene* scene);

}  // namespace caustica::editor
