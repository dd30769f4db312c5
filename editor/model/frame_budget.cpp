#include "frame_budget.h"

#include <algorithm>

namespace caustica::editor {

namespace {
// Raising is worth it only when the richer step is predicted to stay this far under the budget, so
// that the size does not go up and down from frame to frame.
constexpr double kRaiseMargin = 0.8;
// A size step (half the size each way, a quarter of the pixels) is predicted to cost at least this
// many times the next: the part of a frame that does not shrink with the pixels keeps it under 4,
// and on lavapipe the default graph's halvings measured 2.2 to 2.4 (issue 61's drags). A ratio
// measured lower comes from frames still settling after a new plan (the first frames at a step run
// slower, their images new to the heap) and made raises that did not hold.
constexpr double kLeastSizeRatio = 2.0;
// A level is kept when its refining frames' median leaves this much of the budget: the frames
// spread about their median (a p95 a quarter above it on this machine), and the window's answer is
// judged by the slow ones.
constexpr double kLevelMargin = 0.9;
// A richer still level comes back only when predicted this far under the budget: the prediction
// scales its cost measured at another load, and a move that does not hold costs a whole frame.
constexpr double kLevelRaiseMargin = 0.7;
// A raise whose first judged frames go over the budget again cost two new plans (on lavapipe a
// plan's first frame at other while_moving values took 2 to 3 s on a loaded machine): the next
// raise waits this many judged frames, twice as many after each raise that does not hold.
constexpr size_t kHeldAfterFailedRaise = 8, kMostHeld = 64;
}  // namespace

double FrameBudget::ratio_over_next(size_t level) const {
  const bool size_step = kSteps[level + 1].divider != kSteps[level].divider;
  return size_step ? std::max(cost_over_next_[level], kLeastSizeRatio) : cost_over_next_[level];
}

size_t FrameBudget::fitting_level(double frame_ms, size_t cheapest) const {
  size_t level = level_;
  double predicted = frame_ms;
  while (level < cheapest && predicted > budget_ms_) {
    const double ratio = ratio_over_next(level);
    ++level;
    if (ratio <= 1) break;  // not measured: its frames are judged first
    predicted /= ratio;
  }
  return level;
}

FrameBudget::Step FrameBudget::next(double frame_ms, bool moving, bool can_scale, bool can_lower) {
  const size_t before = level_;
  if (!moving || !can_scale || budget_ms_ <= 0) {
    level_ = 0;
    going_down_ = raised_ = false;
    held_ = 0;
  } else if (!first_at_step_) {
    if (going_down_ && level_ > 0) cost_over_next_[level_ - 1] = last_at_step_ms_ > 0 ? last_at_step_ms_ / frame_ms : 0;
    going_down_ = false;
    const size_t cheapest = can_lower ? kSteps.size() - 1 : kSteps.size() - 2;
    ++held_;
    if (frame_ms > budget_ms_ && level_ < cheapest) {
      if (raised_) hold_ = std::min(kMostHeld, std::max(kHeldAfterFailedRaise, 2 * hold_));  // the raise did not hold
      raised_ = false;
      const size_t to = fitting_level(frame_ms, cheapest);
      going_down_ = to == level_ + 1;  // a cost is measured over one step only
      level_ = to;
      held_ = 0;
    } else if (frame_ms <= budget_ms_ && level_ > 0 && held_ > hold_ && ratio_over_next(level_ - 1) > 0 &&
               frame_ms * ratio_over_next(level_ - 1) <= kRaiseMargin * budget_ms_) {
      --level_;
      raised_ = true;
      held_ = 0;
    } else if (raised_ && held_ >= kHeldAfterFailedRaise) {
      raised_ = false;  // the raise held
    }
    last_at_step_ms_ = frame_ms;
  }
  first_at_step_ = level_ != before;
  return step();
}

bool StillLevels::refined(double frame_ms) {
  if (budget_ms_ <= 0 || levels_ <= 1) return false;
  ++held_;
  frames_.push_back(frame_ms);
  if (frames_.size() > kJudged) frames_.erase(frames_.begin());
  if (frames_.size() < kJudged) return false;
  std::vector<double> sorted = frames_;
  std::nth_element(sorted.begin(), sorted.begin() + kJudged / 2, sorted.end());
  const double median = sorted[kJudged / 2];
  const bool over = median > kLevelMargin * budget_ms_ && level_ + 1 < levels_;
  // The cost of a level over the next cheaper one, from the level left and this one: on the second
  // window (the first frames after a new plan run slower, the whole frame's work before them still
  // settling), or on the first where it already moves on. The most ever measured, since the load
  // changes the ratio (a fixed part of each frame does not scale) and a move back on too low a
  // one does not hold.
  if (measuring_cost_ && (held_ >= 2 * kJudged || over)) {
    const bool went_down = left_level_ < level_;
    double& cost = cost_over_next_[std::min(left_level_, level_)];
    cost = std::max(cost, went_down ? judged_ms_ / median : median / judged_ms_);
    measuring_cost_ = false;
  }
  auto move = [&](size_t to) {
    judged_ms_ = median;
    left_level_ = level_;
    measuring_cost_ = true;
    level_ = to;
    frames_.clear();
    held_ = 0;
    return true;
  };
  if (over) {
    if (raised_ && held_ < hold_) hold_ *= 2;  // the move back did not hold
    raised_ = false;
    return move(level_ + 1);
  }
  if (level_ > 0 && held_ >= hold_ && cost_over_next_[level_ - 1] > 0 &&
      median * cost_over_next_[level_ - 1] <= kLevelRaiseMargin * budget_ms_) {
    predicted_ms_ = median * cost_over_next_[level_ - 1];
    raised_ = true;
    return move(level_ - 1);
  }
  return false;
}

std::vector<size_t> display_steps(const std::vector<double>& pass_ms, double overhead_ms, double budget_ms) {
  std::vector<size_t> ends;
  double step_ms = 0;
  for (size_t i = 0; i < pass_ms.size(); ++i) {
    // A pass that costs nothing (skipped, unchanged) joins the next step rather than make a frame of its own.
    if (step_ms > 0 && budget_ms > 0 && overhead_ms + step_ms + pass_ms[i] > budget_ms) {
      ends.push_back(i);
      step_ms = 0;
    }
    step_ms += pass_ms[i];
  }
  ends.push_back(pass_ms.size());
  return ends;
}

double display_overhead(double overhead_ms, double wall_ms, double gpu_ms, bool presented) {
  return presented ? std::max(0.0, wall_ms - gpu_ms) : overhead_ms;
}

bool display_due(double since_shown_s, uint64_t accumulated, uint64_t accumulated_shown) {
  if (since_shown_s < kShowAfter) return false;
  return since_shown_s >= kShowAtMost || accumulated * 10 >= accumulated_shown * 11;
}

bool present_due(bool picture_changed, bool input, double since_presented_s) {
  return picture_changed || input || since_presented_s >= kPanelRefresh;
}

double refining_frame_ms(double wall_ms, double gpu_ms, bool presented, double overhead_ms) {
  return presented ? wall_ms : gpu_ms + overhead_ms;
}

}  // namespace caustica::editor
