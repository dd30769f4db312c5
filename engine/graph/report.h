#pragma once
// What `render --stats` and `trace` write: per-pass timings, memory and counters.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "graph/executor.h"

namespace caustica::graph {

struct RunRecord {
  std::string device;
  std::vector<FrameResult> frames;
  std::vector<double> frame_start_ms;  // CPU time of each frame's start, from the first
  std::vector<double> frame_wall_ms;   // each frame's wall time, where the run measured it
  // The structures the plan's tracer walks (the ray queries' acceleration structures or the compute
  // tracer's BVH), when a pass traces (else all 0).
  uint64_t acceleration_bytes = 0;
  double acceleration_build_ms = 0;  // triangle sort on the host plus the build, waited for
};

// The p-th percentile (0..100) by the nearest-rank rule; 0 for no values.
double percentile(std::vector<double> values, double p);

// Medians over the frames after the first (pipelines JIT-compile on first use), or the one frame.
nlohmann::json stats_json(const Plan& plan, const RunRecord& run);

// Chrome trace-event JSON (Perfetto, chrome://tracing): a GPU track, a CPU track, counter tracks.
nlohmann::json chrome_trace_json(const Plan& plan, const RunRecord& run);

}  // namespace caustica::graph
