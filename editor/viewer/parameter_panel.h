#pragma once
// The viewer's panels that change the running graph without touching its file: its parameters,
// editable within their declared ranges, and its passes switched off and on.
#include <functional>

#include "viewer/hot_reload.h"

namespace caustica::editor {

// An edit the graph refuses is taken back, with the compiler's message in the session's status.
// `configure` recompiles the session's edited graph (throws when it does not compile).
void parameter_panel(Session& session, const std::function<void()>& configure);
// A pass switched off stays off only if the graph still compiles without it (its outputs have a
// fallback or nothing needs them); otherwise it comes back on with the compiler's message.
void pass_switches(Session& session, const std::function<void()>& configure);

}  // namespace caustica::editor
