#include "model/view_budget.h"

#include <algorithm>

#include "core/error.h"

namespace caustica::editor {

ViewBudget::ViewBudget(double budget_ms, double still_after_ms, double start_s)
    : budget_ms_(budget_ms),
      still_after_s_(still_after_ms / 1000.0),
      budget_(budget_ms),
      last_move_s_(start_s),
      still_levels_(budget_ms, 1) {}

ViewBudget::Decision ViewBudget::begin_frame(double now_s, bool moved, bool can_scale, bool can_lower) {
  moved_ = moved;
  if (moved) last_move_s_ = now_s;
  at_rest_ = !moved && now_s - last_move_s_ >= still_after_s_;
  Setting next = setting_;
  if (at_rest_ || !can_scale || budget_ms_ <= 0) {
    next.step = budget_.next(0, false, can_scale, can_lower);
    judged_ms_.reset();
  } else if (moved && judged_ms_) {
    // Judged on the last frame that moved and rendered, however many idle frames came after it.
    next.step = budget_.next(*judged_ms_, true, can_scale, can_lower);
    judged_ms_.reset();
  }
  next.still_values = still_values_wanted_ && at_rest_;
  next.still_level = still_levels_.level();
  if (next == setting_) return {setting_, false, false};
  setting_ = next;
  // At rest the change is one of quality (the while_still values), not of what the picture shows.
  return {setting_, true, !moved};
}

ViewBudget::Part ViewBudget::frame_part(double now_s, bool must_show, bool refines_apart, bool converging, uint64_t accumulated) {
  if (moved_ || must_show || !refines_apart || !converging || budget_ms_ <= 0 || last_whole_ms_ <= budget_ms_) {
    display_step_ = 0;
    return {};
  }
  if (display_step_ == 0 && !display_due(now_s - last_shown_s_, accumulated, accumulated_shown_)) {
    return {graph::FramePart::refine, {}};
  }
  if (display_step_ == 0) display_ends_ = display_steps(showing_ms_, frame_overhead_ms_, budget_ms_);
  graph::DisplayStep step{display_step_ == 0 ? 0 : display_ends_[display_step_ - 1], display_ends_[display_step_]};
  display_step_ = display_step_ + 1 == display_ends_.size() ? 0 : display_step_ + 1;
  if (display_step_ == 0) step.last = SIZE_MAX;  // the last step runs whatever is left
  return {graph::FramePart::display, step};
}

bool ViewBudget::present(double now_s, bool picture_changed, bool input) {
  presented_ = present_due(picture_changed, input, now_s - last_presented_s_);
  if (presented_) last_presented_s_ = now_s;
  return presented_;
}

bool ViewBudget::showed_result(graph::FramePart part) const {
  return part == graph::FramePart::whole || (part == graph::FramePart::display && display_step_ == 0);
}

bool ViewBudget::end_frame(const Measured& frame) {
  last_wall_ms_ = frame.wall_ms;
  if (moved_ && frame.rendered) judged_ms_ = frame.wall_ms;
  if (showed_result(frame.part)) {
    last_shown_s_ = frame.now_s;
    accumulated_shown_ = frame.accumulated;
  }
  if (frame.part == graph::FramePart::whole) {
    // A plan's first frame runs every pass and its wall time holds the plan's set-up (pipelines):
    // its GPU time and a frame's usual overhead stand for a whole frame until one is measured, so
    // that a still plan over the budget refines from its second frame, not after another whole one.
    last_whole_ms_ = frame.first_of_plan ? frame.gpu_ms + frame_overhead_ms_ : frame.wall_ms;
    // A frame the executor ran whole though asked for a part (a new plan's first) showed
    // everything: a display it began starts again from its first step next time.
    display_step_ = 0;
  }
  if (showing_ms_.size() != frame.showing_passes) showing_ms_.assign(frame.showing_passes, 0.0);
  if (frame.showing_passes > 0 && frame.showing_ms.size() == frame.showing_passes) {
    for (size_t i = 0; i < showing_ms_.size(); ++i) showing_ms_[i] = frame.showing_ms[i].value_or(showing_ms_[i]);
    frame_overhead_ms_ = display_overhead(frame_overhead_ms_, frame.wall_ms, frame.gpu_ms, presented_);
  }
  if (!setting_.still_values || frame.part != graph::FramePart::refine) return false;
  if (!still_levels_.refined(refining_frame_ms(frame.wall_ms, frame.gpu_ms, presented_, frame_overhead_ms_))) return false;
  setting_.still_level = still_levels_.level();
  return true;
}

void ViewBudget::plan_changed(bool picture_standing, bool showing_kept) {
  budget_.new_plan();
  if (picture_standing) {
    // The plan before's whole frame stands for this one's (over the budget, frames refine at once;
    // within it, the next frame shows the new plan whole), a new mean shows once display_due says
    // so, and a display starts from its first step.
    accumulated_shown_ = 0;
    display_step_ = 0;
  } else if (!showing_kept) {
    last_whole_ms_ = 0;
  }
}

void ViewBudget::new_graph(size_t still_levels) {
  setting_.still_values = false;
  setting_.still_level = 0;
  still_values_wanted_ = still_levels > 0;
  still_levels_ = StillLevels(budget_ms_, std::max<size_t>(1, still_levels));
}

void ViewBudget::refuse_still_values() {
  still_values_wanted_ = false;
  setting_.still_values = false;
}

double ViewBudget::rest_in_s(double now_s) const {
  return at_rest_ ? 0.0 : std::max(0.0, last_move_s_ + still_after_s_ - now_s);
}

std::string still_values_refusal(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const InputError& e) {
    return e.what();
  }
}

}  // namespace caustica::editor
