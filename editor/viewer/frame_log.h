#pragma once
// caustica view --stats: each frame the viewer drew, for measuring it while it moves (issue 40):
// the frame's wall time (input to present), its GPU and recording times, and which passes ran.
#include <string>
#include <vector>

#include "graph/executor.h"

namespace caustica::editor {

// What the viewer drew a frame with.
struct FrameSettings {
  bool moving = false;     // the camera or a light changed before this frame (input or --orbit / --move-light)
  uint32_t divider = 1;    // the frame rendered at the window's size over this (the frame budget)
  bool lowered = false;    // with the graph parameters' while_moving values
  bool still = false;      // with their while_still values,
  size_t still_level = 0;  // those of this level (0: the first) where a parameter lists several
  bool presented = true;   // the frame went to the window (editor::present_due)
};

class FrameLog {
 public:
  void add(double wall_ms, const graph::FrameResult& frame, const FrameSettings& settings);
  // JSON: every frame, and the median and 95th percentile of the wall time over all frames, the
  // moving ones and the still ones. Written through a temporary file, so a killed viewer leaves none.
  void write(const std::string& path) const;

 private:
  struct Entry {
    double wall_ms, gpu_ms, cpu_ms;
    FrameSettings settings;
    bool converging;
    uint64_t accumulated;  // graph::FrameResult
    graph::FramePart part;
    std::vector<std::string> ran, reused;
  };
  std::vector<Entry> entries_;
};

}  // namespace caustica::editor
