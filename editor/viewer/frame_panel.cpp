#include "viewer/frame_panel.h"

#include <imgui.h>

#include <cfloat>

#include "scene/acceleration.h"
#include "scene/gpu_scene.h"

namespace caustica::editor {

void frame_panel(const graph::FrameResult& frame, const graph::Plan& plan, std::map<std::string, std::vector<float>>& gpu_history) {
  if (ImGui::CollapsingHeader("passes", ImGuiTreeNodeFlags_DefaultOpen) &&
      ImGui::BeginTable("passes", 4, ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg)) {
    // Per pass: GPU and CPU recording time, and the GPU time of the last 120 frames drawn.
    ImGui::TableSetupColumn("pass", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableSetupColumn("GPU ms");
    ImGui::TableSetupColumn("CPU ms");
    ImGui::TableSetupColumn("GPU, last frames");
    ImGui::TableHeadersRow();
    for (const auto& p : frame.passes) {
      std::vector<float>& history = gpu_history[p.name];
      history.push_back(static_cast<float>(p.gpu_ms));
      if (history.size() > 120) history.erase(history.begin());
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      if (p.ran()) {
        ImGui::TextUnformatted(p.name.c_str());
      } else {
        ImGui::TextDisabled("%s (reused)", p.name.c_str());  // nothing it depends on changed
      }
      ImGui::TableNextColumn();
      ImGui::Text("%7.2f", p.gpu_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%5.2f", p.cpu_ms);
      ImGui::TableNextColumn();
      ImGui::PlotHistogram(("##gpu" + p.name).c_str(), history.data(), static_cast<int>(history.size()), 0, nullptr, 0.0f, FLT_MAX,
                           ImVec2(70, 14));
    }
    for (const auto& culled : plan.culled) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextDisabled("%s (culled)", culled.c_str());
    }
    ImGui::EndTable();
  }
}

void counters_and_memory(const graph::FrameResult& frame, const graph::Plan& plan, const scene::GpuScene* scene) {
  if (ImGui::CollapsingHeader("counters")) {
    for (const auto& [name, value] : frame.counters) ImGui::Text("%-28s %.6g", name.c_str(), value);
  }
  if (ImGui::CollapsingHeader("memory")) {
    ImGui::Text("transient: %.1f MiB aliased (lifetime bound %.1f)", double(plan.transient_bytes_aliased) / 1048576.0,
                double(plan.transient_bytes_lifetime_bound) / 1048576.0);
    ImGui::Text("%.1f MiB unaliased, persistent %.1f MiB", double(plan.transient_bytes_unaliased) / 1048576.0,
                double(plan.persistent_bytes) / 1048576.0);
    if (const auto* acceleration = scene ? scene->built_acceleration() : nullptr) {
      ImGui::Text("acceleration structures: %.1f MiB", double(acceleration->bytes()) / 1048576.0);
    }
    if (const auto* bvh = scene ? scene->built_tracer_bvh() : nullptr) {
      ImGui::Text("compute tracer's BVH: %.1f MiB, %u nodes, %u deep", double(bvh->bytes) / 1048576.0, bvh->nodes, bvh->depth);
    }
  }
  if (plan.tracer != graph::Tracer::none) ImGui::Text("exact paths traced by %s", graph::tracer_name(plan.tracer));
}

}  // namespace caustica::editor
