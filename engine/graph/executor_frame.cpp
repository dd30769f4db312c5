// Executor::run_frame: the run policy decides (run_policy.h), the executor records what it decided,
// submits, waits and reports.
#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/low_discrepancy.h"
#include "graph/executor_internal.h"
#include "graph/expression.h"
#include "graph/per_light.h"

namespace caustica::graph {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A pass's parameters with those that follow the frame evaluated for `frame`. The compiler checked
// each expression on the first frame; a later frame's value is clamped to the declared range, and
// one that is not finite (a division by a frame count that reached zero) is bad input, named.
nlohmann::json params_for_frame(const Plan& plan, const PlannedPass& pass, const FrameInfo& frame) {
  // In the order of kFrameNames.
  const double frame_values[] = {static_cast<double>(frame.index), static_cast<double>(frame.since_reset),
                                 static_cast<double>(frame.camera_jitter.x), static_cast<double>(frame.camera_jitter.y)};
  static_assert(sizeof(frame_values) / sizeof(double) == std::size(kFrameNames));
  ExpressionScope scope;
  scope.lookup = [&](std::string_view name) -> std::optional<double> {
    for (size_t i = 0; i < std::size(kFrameNames); ++i) {
      if (name == kFrameNames[i]) return frame_values[i];
    }
    const auto it = plan.expression_values.find(std::string(name));
    return it == plan.expression_values.end() ? std::nullopt : std::optional<double>(it->second);
  };
  scope = light_scope(std::move(scope), pass.instance);
  nlohmann::json params = pass.params;
  for (const auto& [name, expression] : pass.frame_params) {
    try {
      params[name] = param_value_of_number(*pass.decl->find_param(name), evaluate_expression(expression, scope), true);
    } catch (const std::invalid_argument& e) {  // not finite on this frame: the names and syntax were checked
      throw InputError(plan.graph_path + ": pass '" + pass.name + "' (" + pass.pointer + "), parameter '" + name + "': " + e.what() +
                       " on frame " + std::to_string(frame.index) + " (frame.since_reset " + std::to_string(frame.since_reset) + ")");
    }
  }
  return params;
}

}  // namespace

std::optional<SceneKeys> Executor::scene_keys() const {
  if (!scene_) return std::nullopt;
  return SceneKeys{{scene_->parts_key(true, false, false), scene_->parts_key(false, true, false), scene_->parts_key(false, false, true)},
                   scene_->light_keys()};
}

FrameResult Executor::run_frame(bool read_back, FrameRequest request) {
  assert(plan_ && "configure() before run_frame()");
  Realized& real = *realized_;
  const Plan& p = *plan_;
  VkCommandBuffer cmd = real.cmd;
  FrameResult result;
  const auto frame_start = Clock::now();
  const uint64_t submission = vk_.begin_submission();
  if (scene_) scene_->update_frame(p.output_width, p.output_height);
  real.scene_now = scene_keys();
  const FrameDecision decision = decide_frame(p, real.run, real.scene_now, request);
  result.part = decision.part;
  glm::vec2 camera_jitter(0.0f);
  if (decision.jitters) {
    camera_jitter = r2_point(decision.jitter_frame) - 0.5f;
    scene_->jitter_camera(camera_jitter);
  }
  begin_frame(p, real.run, decision, real.scene_now, camera_jitter);
  real.host_counters.clear();

  vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  vkCmdResetQueryPool(cmd, real.queries.get(), 0, real.query_count);
  vkCmdFillBuffer(cmd, real.counters.get(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  if (real.run.frame_index == 0) {
    std::vector<PlannedBarrier> kept = kept_images_to_final_layouts(p);
    std::erase_if(kept, [&](const PlannedBarrier& b) {
      return std::any_of(carried_.images.begin(), carried_.images.end(),
                         [&](const ImageMove& m) { return m.handed && m.to == b.resource; });
    });
    record_barriers(cmd, kept);
    record_carried(cmd);
  }
  uint32_t next_query = 0;
  std::vector<std::pair<uint32_t, uint32_t>> stamps;  // the frame's, then each pass's
  record_passes(cmd, decision, frame_start, result, stamps, next_query);
  if (read_back) record_read_back(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
  vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  result.cpu_ms = ms_since(frame_start);
  submit_and_wait(decision);
  vk_.retire(submission);
  carried_ = {};  // copied and handed over: the plan before can go

  std::vector<uint64_t> times(next_query);
  vk::check(vkGetQueryPoolResults(vk_.device(), real.queries.get(), 0, next_query, times.size() * sizeof(uint64_t), times.data(),
                                  sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults");
  const double period_ms = static_cast<double>(vk_.properties().limits.timestampPeriod) * 1e-6;
  const uint64_t mask = vk_.timestamp_valid_bits() >= 64 ? ~0ull : (1ull << vk_.timestamp_valid_bits()) - 1;
  auto elapsed = [&](uint32_t a, uint32_t b) { return static_cast<double>((times[b] - times[a]) & mask) * period_ms; };
  result.gpu_ms = elapsed(stamps[0].first, stamps[0].second);
  for (size_t i = 0; i < result.passes.size(); ++i) {
    result.passes[i].gpu_ms = elapsed(stamps[i + 1].first, stamps[i + 1].second);
    result.passes[i].gpu_start_ms = elapsed(stamps[0].first, stamps[i + 1].first);
  }
  collect_counters(decision, result);
  result.converging = std::any_of(real.run.passes.begin(), real.run.passes.end(), [](const PassRunState& s) { return s.converging; });
  real.read_back_done = read_back;
  const uint64_t index = real.run.frame_index;
  const FrameAccount account = end_frame(p, real.run, decision, real.scene_now);
  result.frame = {index, account.since_reset};
  result.accumulated = account.accumulated;
  return result;
}

void Executor::record_passes(VkCommandBuffer cmd, const FrameDecision& decision, std::chrono::steady_clock::time_point frame_start,
                             FrameResult& result, std::vector<std::pair<uint32_t, uint32_t>>& stamps, uint32_t& next_query) {
  Realized& real = *realized_;
  const Plan& p = *plan_;
  auto stamp = [&]() {
    const uint32_t index = next_query;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, real.queries.get(), next_query++);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, real.queries.get(), next_query++);  // the dummy
    return index;
  };
  const uint32_t frame_begin = stamp();
  stamps.emplace_back(frame_begin, 0);
  record_history(cmd, decision);
  for (size_t i = 0; i < p.passes.size(); ++i) {
    const PlannedPass& pass = p.passes[i];
    const auto pass_start = Clock::now();
    vk_.begin_label(cmd, pass.name);
    const uint32_t start = stamp();  // a pass's barriers count as part of its cost
    record_barriers(cmd, pass.barriers);
    const PassRun run = decision.passes[i];
    if (runs(run)) {
      real.recording_pass = i;
      real.recording_params = &pass.params;
      if (!pass.frame_params.empty()) {
        real.frame_params.resize(p.passes.size());
        real.frame_params[i] = params_for_frame(p, pass, real.run.passes[i].frames);
        real.recording_params = &real.frame_params[i];
      }
      PassContext context(*this, pass, cmd);
      real.passes[i]->execute(context);
    }
    const uint32_t end = stamp();
    if (runs(run)) {
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                         VK_ACCESS_2_NONE);
      vkCmdFillBuffer(cmd, real.finished.get(), i * sizeof(uint32_t), sizeof(uint32_t), 1);
    }
    vk_.end_label(cmd);
    stamps.emplace_back(start, end);
    result.passes.push_back(
        {pass.name, 0, ms_since(pass_start), 0, std::chrono::duration<double, std::milli>(pass_start - frame_start).count(), run});
  }
  stamps.front().second = stamp();
}

void Executor::submit_and_wait(const FrameDecision& decision) {
  Realized& real = *realized_;
  VkCommandBufferSubmitInfo cmd_submit{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cmd_submit.commandBuffer = real.cmd;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmd_submit;
  VkFence fence = real.fence.get();
  std::memset(real.finished.mapped, 0, plan_->passes.size() * sizeof(uint32_t));
  vk::check(vkQueueSubmit2(vk_.queue(), 1, &submit, fence), "vkQueueSubmit2");
  // A lost device, a hung GPU or a shader that never ends ends the frame with an error instead of
  // waiting forever; a signal ends it at once. The wait is cut into slices to see either.
  const double limit_s = real.run.frame_index == 0 ? first_frame_timeout_s_ : frame_timeout_s_;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit_s));
  constexpr uint64_t kSliceNs = 50'000'000;
  const InterruptPolling polling;
  VkResult waited = VK_TIMEOUT;
  while (waited == VK_TIMEOUT) {
    waited = vk_.frame_result(vkWaitForFences(vk_.device(), 1, &fence, VK_TRUE, kSliceNs));
    if (waited != VK_TIMEOUT) break;
    if (interrupt_signal() != 0) {
      vk_.abandon();
      throw_if_interrupted();
    }
    if (Clock::now() >= deadline) throw_frame_timeout(decision, limit_s);
  }
  vk::check(waited, "vkWaitForFences");
  vk::check(vkResetFences(vk_.device(), 1, &fence), "vkResetFences");
}

void Executor::throw_frame_timeout(const FrameDecision& decision, double limit_s) const {
  // The pass that was running: the first that ran and has not finished.
  const Realized& real = *realized_;
  std::string running = "?";
  const auto* finished = static_cast<const uint32_t*>(real.finished.mapped);
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    uint32_t done = 0;
    std::memcpy(&done, finished + i, sizeof(done));
    if (runs(decision.passes[i]) && done == 0) {
      running = plan_->passes[i].name;
      break;
    }
  }
  vk_.abandon();
  char seconds[32];
  std::snprintf(seconds, sizeof(seconds), "%g", limit_s);
  throw FrameTimeout("frame " + std::to_string(real.run.frame_index) + " did not finish within " + seconds + " s: pass '" + running +
                         "' was still running (a shader that never ends? --frame-timeout sets the limit)",
                     running);
}

void Executor::collect_counters(const FrameDecision& decision, FrameResult& result) {
  Realized& real = *realized_;
  for (size_t c = 0; c < real.counter_slots.size(); ++c) {
    Realized::CounterSlot& slot = real.counter_slots[c];
    // A skipped pass's counters stand as it last left them.
    if (runs(decision.passes[slot.pass])) {
      if (const auto host = real.host_counters.find(static_cast<uint32_t>(c)); host != real.host_counters.end()) {
        slot.value = host->second;
      } else {
        const auto* value = static_cast<const unsigned char*>(real.counters.mapped) + c * sizeof(uint32_t);
        if (slot.is_sum) {
          float sum;
          std::memcpy(&sum, value, sizeof(sum));  // the zero fill is 0.0f too
          slot.value = static_cast<double>(sum);
        } else {
          uint32_t count;
          std::memcpy(&count, value, sizeof(count));
          slot.value = count;
        }
      }
    }
    result.counters[slot.name] += slot.value;
    result.counter_passes.emplace(slot.name, plan_->passes[slot.pass].name);
  }
}

}  // namespace caustica::graph
