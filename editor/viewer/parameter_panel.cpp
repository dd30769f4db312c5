#include "viewer/parameter_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <optional>
#include <string>
#include <vector>

namespace caustica::editor {

void parameter_name(const graph::ParamDecl& d) {
  ImGui::TextWrapped("%s", d.name.c_str());
  if (ImGui::IsItemHovered() && !d.description.empty()) ImGui::SetTooltip("%s", d.description.c_str());
}

std::optional<nlohmann::json> parameter_input(const graph::ParamDecl& d, const nlohmann::json& value) {
  std::optional<nlohmann::json> next;
  ImGui::PushID(d.name.c_str());
  parameter_name(d);
  ImGui::SetNextItemWidth(-FLT_MIN);
  if (d.type == graph::ParamType::bool_) {
    bool v = value.get<bool>();
    if (ImGui::Checkbox("##value", &v)) next = v;
  } else if (d.power_of_two) {
    // The slider moves through the allowed values (its position is their index) and shows the value.
    const std::vector<int64_t> powers = graph::powers_of_two_within(d);
    const auto at = std::lower_bound(powers.begin(), powers.end(), value.get<int64_t>());
    int index = static_cast<int>(std::min<std::ptrdiff_t>(at - powers.begin(), std::ssize(powers) - 1));
    const std::string shown = std::to_string(powers[static_cast<size_t>(index)]);
    if (ImGui::SliderInt("##value", &index, 0, static_cast<int>(powers.size()) - 1, shown.c_str(), ImGuiSliderFlags_NoInput))
      next = powers[static_cast<size_t>(index)];
  } else if (d.type == graph::ParamType::int_) {
    int v = value.get<int>();
    if (ImGui::SliderInt("##value", &v, static_cast<int>(d.min.value_or(0)), static_cast<int>(d.max.value_or(1024)))) next = v;
  } else if (d.type == graph::ParamType::float_) {
    float v = value.get<float>();
    if (ImGui::SliderFloat("##value", &v, static_cast<float>(d.min.value_or(0)), static_cast<float>(d.max.value_or(10)))) next = v;
  } else if (d.type == graph::ParamType::choice) {
    const std::string current = value.get<std::string>();
    if (ImGui::BeginCombo("##value", current.c_str())) {
      for (const auto& c : d.choices) {
        if (ImGui::Selectable(c.c_str(), c == current)) next = c;
      }
      ImGui::EndCombo();
    }
  }
  if (ImGui::IsItemHovered() && !d.description.empty()) ImGui::SetTooltip("%s", d.description.c_str());
  ImGui::PopID();
  return next;
}

void parameter_panel(Session& session, const std::function<void()>& configure) {
  for (const auto& parameter : session.graph->parameters) {
    const auto& d = parameter.decl;
    const auto found = session.edits.find(d.name);
    const std::optional<nlohmann::json> next =
        parameter_input(d, found != session.edits.end() ? nlohmann::json::parse(found->second) : parameter.value);
    if (next) {
      const auto previous = session.edits;
      session.edits[d.name] = next->dump();
      try {
        configure();
        session.status = d.name + " = " + next->dump();
        session.status_is_error = false;
      } catch (const std::exception& e) {
        session.edits = previous;
        configure();
        session.status = e.what();
        session.status_is_error = true;
      }
    }
  }
}

void pass_switches(Session& session, const std::function<void()>& configure) {
  for (const auto& pass : session.graph->passes) {
    bool on = !session.disabled.count(pass.name);
    if (!ImGui::Checkbox(pass.name.c_str(), &on)) continue;
    if (on)
      session.disabled.erase(pass.name);
    else
      session.disabled.insert(pass.name);
    try {
      configure();
      session.status = pass.name + (on ? " enabled" : " disabled");
      session.status_is_error = false;
    } catch (const std::exception& e) {
      if (on)
        session.disabled.insert(pass.name);
      else
        session.disabled.erase(pass.name);
      configure();
      session.status = "cannot disable " + pass.name + ": " + e.what();
      session.status_is_error = true;
    }
  }
}

}  // namespace caustica::editor
