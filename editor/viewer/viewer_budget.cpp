#include "viewer/viewer_impl.h"

namespace caustica::editor {

VkExtent2D Viewer::Impl::render_size() const {
  const uint32_t divider = budget_.setting().step.divider;
  return {std::max(1u, swapchain_.extent.width / divider), std::max(1u, swapchain_.extent.height / divider)};
}

void Viewer::Impl::fit_frame_budget(bool moved) {
  const graph::PlannedResource& out = executor_.plan().resources[executor_.plan().outputs.front()];
  const bool can_scale =
      blit_supported_ && out.format == graph::Format::rgba8 && !(inspector_.in_main_view && !inspector_.inspected.empty());
  const bool can_lower = std::any_of(session_.graph->parameters.begin(), session_.graph->parameters.end(),
                                     [](const auto& p) { return p.while_moving.has_value(); });
  if (!budget_.begin_frame(now_s(), moved, can_scale, can_lower).new_plan) return;
  try {
    // At rest the change is one of quality (the while_still values), not of what the picture shows:
    // the picture stands while the new plan refines, where the sizes let it.
    configure(false, !moved);
  } catch (const std::exception&) {
    if (!budget_.setting().still_values) throw;
    // The device cannot run the graph with them (exact photons without VK_KHR_ray_query): the
    // values as set, until the graph changes. A device failure goes on up (exit 3).
    const std::string refusal = still_values_refusal(std::current_exception());
    budget_.refuse_still_values();
    configure();
    session_.report("not using the while_still values: " + refusal, true);
    std::fprintf(stderr, "view: not using the while_still values: %s\n", refusal.c_str());
  }
}

ViewBudget::Measured Viewer::Impl::measured(double wall_ms) const {
  ViewBudget::Measured m{
      now_s(), wall_ms, last_result_.gpu_ms, false, last_result_.part, last_result_.frame.index == 0, last_result_.accumulated, 0, {}};
  m.rendered = std::any_of(last_result_.passes.begin(), last_result_.passes.end(), [](const auto& p) { return p.ran(); });
  const graph::Plan& plan = executor_.plan();
  if (!plan.refines_apart) return m;  // PlannedPass::showing numbers nothing else
  m.showing_passes = static_cast<size_t>(std::count_if(plan.passes.begin(), plan.passes.end(), [](const auto& p) { return !p.refines; }));
  if (last_result_.passes.size() != plan.passes.size()) return m;
  m.showing_ms.resize(m.showing_passes);
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    if (plan.passes[i].refines) continue;
    // A pass that keeps its result while nothing changes (the G-buffer, the shadow map) is skipped
    // by a display, which runs at rest: it costs its barriers alone, whatever it took when it ran.
    if (plan.passes[i].reusable(plan.reuses_unchanged_passes)) {
      m.showing_ms[plan.passes[i].showing] = 0.0;
    } else if (last_result_.passes[i].ran()) {
      m.showing_ms[plan.passes[i].showing] = last_result_.passes[i].gpu_ms;
    }
  }
  return m;
}

void Viewer::Impl::take_still_level(size_t level_before) {
  const StillLevels& levels = budget_.still_levels();
  if (levels.level() > level_before) {
    std::fprintf(stderr,
                 "view: refining frames too slow for the %.0f ms budget (median %.0f ms): the while_still values of level %zu of %zu\n",
                 options_.budget_ms, levels.judged(), levels.level() + 1, levels.levels());
  } else {
    std::fprintf(stderr,
                 "view: refining frames well within the %.0f ms budget again (median %.0f ms, about %.0f ms predicted a level up): "
                 "the while_still values of level %zu of %zu\n",
                 options_.budget_ms, levels.judged(), levels.predicted(), levels.level() + 1, levels.levels());
  }
  configure(true, true);  // a plan whose picture stands still (its showing passes have not run) hands it on
}

void Viewer::Impl::forget_still_values() {
  size_t levels = 0;
  if (session_.graph) {
    for (const auto& p : session_.graph->parameters) levels = std::max(levels, p.while_still.size());
  }
  budget_.new_graph(levels);
}

}  // namespace caustica::editor
