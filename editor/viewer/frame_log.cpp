#include "viewer/frame_log.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "graph/report.h"
#include "io/files.h"

namespace caustica::editor {
namespace {

using graph::percentile;

constexpr const char* kPartNames[] = {"whole", "refine", "display"};  // graph::FramePart

}  // namespace

void FrameLog::add(double wall_ms, const graph::FrameResult& frame, const FrameSettings& settings) {
  Entry entry{wall_ms, frame.gpu_ms, frame.cpu_ms, settings, frame.converging, frame.accumulated, frame.part, {}, {}};
  for (const auto& pass : frame.passes) (pass.ran() ? entry.ran : entry.reused).push_back(pass.name);
  entries_.push_back(std::move(entry));
}

void FrameLog::write(const std::string& path) const {
  nlohmann::ordered_json out;
  std::vector<double> all, moving, still;
  out["frames"] = nlohmann::ordered_json::array();
  for (const Entry& e : entries_) {
    all.push_back(e.wall_ms);
    (e.settings.moving ? moving : still).push_back(e.wall_ms);
    out["frames"].push_back({{"wall_ms", e.wall_ms},
                             {"gpu_ms", e.gpu_ms},
                             {"cpu_ms", e.cpu_ms},
                             {"moving", e.settings.moving},
                             {"divider", e.settings.divider},
                             {"lowered", e.settings.lowered},
                             {"still", e.settings.still},
                             {"still_level", e.settings.still_level},
                             {"presented", e.settings.presented},
                             {"converging", e.converging},
                             {"accumulated", e.accumulated},
                             {"part", kPartNames[static_cast<size_t>(e.part)]},
                             {"ran", e.ran},
                             {"reused", e.reused}});
  }
  out["summary"] = {
      {"frames", all.size()},           {"wall_ms_median", percentile(all, 50)},           {"wall_ms_p95", percentile(all, 95)},
      {"moving_frames", moving.size()}, {"moving_wall_ms_median", percentile(moving, 50)}, {"moving_wall_ms_p95", percentile(moving, 95)},
      {"still_frames", still.size()},   {"still_wall_ms_median", percentile(still, 50)},   {"still_wall_ms_p95", percentile(still, 95)}};
  io::write_text_atomically(path, out.dump(2) + "\n");
}

}  // namespace caustica::editor
