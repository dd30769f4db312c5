#pragma once
// The viewer's panels that change the running graph without touching its file: its parameters,
// editable within their declared ranges, and its passes switched off and on.
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>

#include "graph/pass_type.h"
#include "viewer/hot_reload.h"

namespace caustica::editor {

// A parameter's whole name on a line of its own, wrapped, its description on hover: beside a
// widget a name is cut where the panel is narrow ("converge_sprea"). The widget after it should
// take the panel's width (ImGui::SetNextItemWidth(-FLT_MIN)) and no label ("##name").
void parameter_name(const graph::ParamDecl& d);
// A graph parameter's name and widget (a slider over its range, a checkbox or a choice) showing
// `value`; returns the value the user set, if any.
std::optional<nlohmann::json> parameter_input(const graph::ParamDecl& d, const nlohmann::json& value);

// An edit the graph refuses is taken back, with the compiler's message in the session's status.
// `configure` recompiles the session's edited graph (throws when it does not compile).
void parameter_panel(Session& session, const std::function<void()>& configure);
// A pass switched off stays off only if the graph still compiles without it (its outputs have a
// fallback or nothing needs them); otherwise it comes back on with the compiler's message.
void pass_switches(Session& session, const std::function<void()>& configure);

}  // namespace caustica::editor
