#include "graph/report.h"

#include <algorithm>
#include <cmath>

namespace caustica::graph {
namespace {

// Counts print as integers, sums as numbers with a fraction.
nlohmann::json counter_value(double v) {
  if (v >= 0 && v < 9007199254740992.0 && v == std::floor(v)) return static_cast<uint64_t>(v);
  return v;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(values.size())));
  return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

nlohmann::json stats_json(const Plan& plan, const RunRecord& run) {
  using json = nlohmann::ordered_json;
  const size_t first = run.frames.size() > 1 ? 1 : 0;
  json out;
  out["graph"] = plan.graph_name;
  out["file"] = plan.graph_path;
  out["device"] = run.device;
  out["size"] = {plan.output_width, plan.output_height};
  out["frames"] = run.frames.size();
  out["frames_timed"] = run.frames.size() - first;
  out["passes"] = json::array();
  for (size_t p = 0; p < plan.passes.size(); ++p) {
    std::vector<double> gpu, cpu;
    size_t frames_run = 0;  // a plan that reuses unchanged passes skips some (their barriers still take time)
    for (size_t f = first; f < run.frames.size(); ++f) {
      gpu.push_back(run.frames[f].passes[p].gpu_ms);
      cpu.push_back(run.frames[f].passes[p].cpu_ms);
      frames_run += run.frames[f].passes[p].ran() ? 1 : 0;
    }
    out["passes"].push_back({{"name", plan.passes[p].name},
                             {"type", plan.passes[p].type},
                             {"gpu_ms", median(gpu)},
                             {"cpu_ms", median(cpu)},
                             {"frames_run", frames_run}});
  }
  std::vector<double> gpu, cpu;
  for (size_t f = first; f < run.frames.size(); ++f) {
    gpu.push_back(run.frames[f].gpu_ms);
    cpu.push_back(run.frames[f].cpu_ms);
  }
  out["frame"] = {{"gpu_ms", median(gpu)}, {"cpu_ms", median(cpu)}};
  if (run.frame_wall_ms.size() == run.frames.size()) {  // the frames' spread, where a run timed each one whole
    const std::vector<double> wall(run.frame_wall_ms.begin() + static_cast<std::ptrdiff_t>(first), run.frame_wall_ms.end());
    out["frame"]["gpu_ms_p95"] = percentile(gpu, 95);
    out["frame"]["gpu_ms_p99"] = percentile(gpu, 99);
    out["frame"]["wall_ms"] = median(wall);
    out["frame"]["wall_ms_p95"] = percentile(wall, 95);
    out["frame"]["wall_ms_p99"] = percentile(wall, 99);
  }
  out["memory"] = {{"transient_bytes_aliased", plan.transient_bytes_aliased},
                   {"transient_bytes_unaliased", plan.transient_bytes_unaliased},
                   {"persistent_bytes", plan.persistent_bytes},
                   {"acceleration_bytes", run.acceleration_bytes}};
  if (run.acceleration_bytes > 0) out["acceleration"] = {{"bytes", run.acceleration_bytes}, {"build_ms", run.acceleration_build_ms}};
  if (plan.tracer != Tracer::none) out["tracer"] = tracer_name(plan.tracer);
  out["counters"] = json::object();
  if (!run.frames.empty()) {
    for (const auto& [name, value] : run.frames.back().counters) out["counters"][name] = counter_value(value);
  }
  return nlohmann::json::parse(out.dump());
}

nlohmann::json chrome_trace_json(const Plan& plan, const RunRecord& run) {
  using json = nlohmann::json;
  constexpr int kPid = 1, kGpu = 1, kCpu = 2;
  json events = json::array();
  events.push_back({{"name", "process_name"}, {"ph", "M"}, {"pid", kPid}, {"args", {{"name", "caustica: " + plan.graph_name}}}});
  events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", kPid}, {"tid", kGpu}, {"args", {{"name", "GPU (" + run.device + ")"}}}});
  events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", kPid}, {"tid", kCpu}, {"args", {{"name", "CPU recording"}}}});
  // A span on a track: Chrome's "complete" event, times in microseconds.
  const auto complete = [&](const std::string& name, int track, double start_us, double ms, const json& args) {
    events.push_back({{"name", name}, {"ph", "X"}, {"pid", kPid}, {"tid", track}, {"ts", start_us}, {"dur", ms * 1000.0}, {"args", args}});
  };
  for (size_t f = 0; f < run.frames.size(); ++f) {
    const FrameResult& frame = run.frames[f];
    // The GPU track starts each frame where its recording started; lavapipe has no shared clock.
    const double base_us = run.frame_start_ms[f] * 1000.0;
    const std::string frame_name = "frame " + std::to_string(f);
    complete(frame_name, kGpu, base_us, frame.gpu_ms, {{"frame", f}});
    complete(frame_name, kCpu, base_us, frame.cpu_ms, {{"frame", f}});
    for (size_t p = 0; p < frame.passes.size(); ++p) {
      const PassTiming& t = frame.passes[p];
      const json args = {{"type", plan.passes[p].type}, {"frame", f}};
      complete(t.name, kGpu, base_us + t.gpu_start_ms * 1000.0, t.gpu_ms, args);
      complete(t.name, kCpu, base_us + t.cpu_start_ms * 1000.0, t.cpu_ms, args);
    }
    for (const auto& [name, value] : frame.counters) {
      events.push_back({{"name", name}, {"ph", "C"}, {"pid", kPid}, {"ts", base_us}, {"args", {{"value", counter_value(value)}}}});
    }
  }
  json passes = json::array();
  for (const auto& p : plan.passes) passes.push_back({{"name", p.name}, {"type", p.type}});
  return {{"traceEvents", events},
          {"displayTimeUnit", "ms"},
          {"otherData", {{"graph", plan.graph_name}, {"file", plan.graph_path}, {"device", run.device}, {"passes", passes}}}};
}

}  // namespace caustica::graph
