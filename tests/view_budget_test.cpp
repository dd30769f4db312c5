// The viewer's budget controller (editor/model/view_budget.h) on the CPU: its rules one by one, and
// recorded input traces (every frame, 10 Hz, 60 Hz, bursts, a stop after a move) driven through a
// model of the viewer's frame loop with frame costs measured on lavapipe (the default graph at
// 1280x720). Each trace prints the moving frames' p95 under the rules before the controller (each
// frame judged on the one before, whatever it did; whole again at the first frame without input)
// and under the controller's, for docs/interactive.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/error.h"
#include "model/view_budget.h"

namespace caustica::editor {
namespace {

using Step = FrameBudget::Step;
constexpr Step kWholeStep{1, false}, kHalfStep{2, false};
constexpr double kNever = std::numeric_limits<double>::infinity();

// What a frame costs (ms) on the default graph at 1280x720 on lavapipe (the drags of 29 November,
// docs/interactive.md): by step, a plan's first frame 1.8 times that (its images new to the heap),
// and a frame with nothing to render (input that moved nothing, the frames after input).
double step_ms(Step step) {
  if (step.lowered) return 45;
  return step.divider == 1 ? 260 : step.divider == 2 ? 115 : 60;
}
constexpr double kFirstOfPlan = 1.8, kIdleMs = 9;

struct Frame {
  double start_s, ms;
  bool moved;
  Step step;
};

// The rules before the controller, as viewer.cpp applied them: each frame after one drawn judged
// on that one's wall time, whether it moved or rendered anything.
class OldRules {
 public:
  ViewBudget::Decision begin(double, bool moved) {
    const Step step = measured_ ? budget_.next(last_ms_, moved, true, true) : step_;
    measured_ = false;
    const bool changed = !(step == step_);
    step_ = step;
    if (changed) budget_.new_plan();
    return {{step, false, 0}, changed, !moved};
  }
  void end(double, double ms, bool, bool) {
    last_ms_ = ms;
    measured_ = true;
  }
  double rest_in_s(double) const { return kNever; }  // it drew the frames after input alone

 private:
  FrameBudget budget_{100};
  Step step_;
  double last_ms_ = 0;
  bool measured_ = false;
};

// The controller, fed as the viewer feeds it.
class NewRules {
 public:
  ViewBudget::Decision begin(double now_s, bool moved) {
    const ViewBudget::Decision decision = budget_.begin_frame(now_s, moved, true, true);
    if (decision.new_plan) budget_.plan_changed(decision.picture_stands, false);
    return decision;
  }
  void end(double now_s, double ms, bool rendered, bool first) {
    ViewBudget::Measured m;
    m.now_s = now_s;
    m.wall_ms = ms;
    m.gpu_ms = ms - kIdleMs;
    m.rendered = rendered;
    m.first_of_plan = first;
    budget_.end_frame(m);
  }
  double rest_in_s(double now_s) const { return budget_.rest_pending() ? budget_.rest_in_s(now_s) : kNever; }
  ViewBudget budget_{100, 300, 0};
};

// The viewer's frame loop (Viewer::run): a frame on input and two more after it, one when the view
// comes to rest, none faster than 60 a second; input that comes during a frame moves the next.
template <class Rules>
std::vector<Frame> drive(Rules& rules, const std::vector<double>& input_s, double end_s) {
  constexpr int kFramesAfterInput = 3;
  std::vector<Frame> frames;
  double t = 0, last_start = -1;
  size_t next = 0;
  int redraw = kFramesAfterInput;
  while (t < end_s) {
    bool moved = false;
    for (; next < input_s.size() && input_s[next] <= t; ++next) moved = true;
    if (moved) redraw = kFramesAfterInput;
    if (redraw == 0 && rules.rest_in_s(t) > 0) {
      const double wake = std::min({next < input_s.size() ? input_s[next] : end_s, t + rules.rest_in_s(t), end_s});
      t = std::max(wake, t + 1e-6);
      continue;
    }
    redraw = std::max(redraw, 1);
    t = std::max(t, last_start + 1.0 / 60);
    const ViewBudget::Decision decision = rules.begin(t, moved);
    const bool rendered = moved || decision.new_plan;
    const double ms = rendered ? step_ms(decision.setting.step) * (decision.new_plan ? kFirstOfPlan : 1) : kIdleMs;
    frames.push_back({t, ms, moved, decision.setting.step});
    last_start = t;
    t += ms / 1000;
    rules.end(t, ms, rendered, decision.new_plan);
    --redraw;
  }
  return frames;
}

// The moving frames' 95th percentile, as tools/drag.sh computes it.
double moving_p95(const std::vector<Frame>& frames) {
  std::vector<double> ms;
  for (const Frame& f : frames) {
    if (f.moved) ms.push_back(f.ms);
  }
  if (ms.empty()) return 0;
  std::sort(ms.begin(), ms.end());
  return ms[static_cast<size_t>(0.95 * static_cast<double>(ms.size() - 1))];
}

// Input events `count` of them, `rate` a second, from `start_s`.
std::vector<double> events(double start_s, double rate, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(start_s + i / rate);
  return out;
}

// Drives a trace under both rules, prints their p95, and returns the controller's frames.
std::vector<Frame> compare(const char* name, const std::vector<double>& input_s, double end_s, double* p95_before = nullptr) {
  OldRules old_rules;
  NewRules new_rules;
  const std::vector<Frame> before = drive(old_rules, input_s, end_s), after = drive(new_rules, input_s, end_s);
  std::printf("[ trace    ] %s: moving frames p95 %.0f ms before, %.0f ms after\n", name, moving_p95(before), moving_p95(after));
  if (p95_before) *p95_before = moving_p95(before);
  return after;
}

// Rule: quality is judged on frames that moved and rendered; frames with nothing to render between
// two moving frames neither raise nor lower the step.
TEST(ViewBudget, AFrameWithNothingToRenderNeitherRaisesNorLowersTheStep) {
  NewRules rules;
  ViewBudget& budget = rules.budget_;
  double t = 1;
  auto frame = [&](bool moved, double ms, bool rendered) {
    const ViewBudget::Decision d = rules.begin(t, moved);
    t += ms / 1000;
    rules.end(t, ms, rendered, d.new_plan);
    return d.setting.step;
  };
  frame(true, 135, true);  // a plan's first frame: not judged
  frame(true, 130, true);
  EXPECT_EQ(frame(true, 65, true), kHalfStep);  // down a step on the whole frame over the budget
  frame(true, 50, true);                        // the half step's first frame: not judged
  frame(true, 50, true);                        // measures the whole step at 130 / 50 times the half
  for (int i = 0; i < 2; ++i) EXPECT_EQ(frame(false, kIdleMs, false), kHalfStep);
  // Judged on the 50 ms frame that moved, not on the idle frames of 9 ms, which would predict a
  // whole frame well within the budget.
  EXPECT_EQ(frame(true, 50, true), kHalfStep);
  EXPECT_EQ(budget.setting().step, kHalfStep);
}

// Rule: a gap between input events is not rest until still_after has passed; then one new plan,
// whole, with the while_still values, the moving picture standing.
TEST(ViewBudget, AGapBetweenInputEventsIsNotRestUntilStillAfter) {
  ViewBudget budget(100, 300, 0);
  budget.new_graph(1);
  ViewBudget::Measured slow;
  slow.wall_ms = 150;
  slow.rendered = true;
  for (double t : {1.0, 1.2, 1.4}) {
    budget.begin_frame(t, true, true, true);
    budget.end_frame(slow);
  }
  ASSERT_EQ(budget.setting().step, kHalfStep);
  const ViewBudget::Decision gap = budget.begin_frame(1.6, false, true, true);
  EXPECT_FALSE(gap.new_plan);
  EXPECT_EQ(gap.setting.step, kHalfStep);
  EXPECT_TRUE(budget.rest_pending());
  EXPECT_NEAR(budget.rest_in_s(1.6), 0.1, 1e-9);
  const ViewBudget::Decision rest = budget.begin_frame(1.7, false, true, true);
  EXPECT_TRUE(rest.new_plan);
  EXPECT_TRUE(rest.picture_stands);
  EXPECT_EQ(rest.setting.step, kWholeStep);
  EXPECT_TRUE(rest.setting.still_values);
  EXPECT_FALSE(budget.rest_pending());
  EXPECT_FALSE(budget.begin_frame(1.8, false, true, true).new_plan);
}

// Rule: moving every frame (a scripted orbit), the step goes down to where frames fit and stays.
TEST(ViewBudget, TraceEveryFrameMoving) {
  double before = 0;
  const std::vector<Frame> frames = compare("every frame", events(0.5, 1000, 3000), 3.5, &before);
  EXPECT_LE(moving_p95(frames), before);
  EXPECT_LE(moving_p95(frames), 100);
}

// Rule: a hand's 10 Hz drag keeps its step between events (the case: before, every event
// after an idle frame started again at full size).
TEST(ViewBudget, TraceTenHzDrag) {
  double before = 0;
  const std::vector<Frame> frames = compare("10 Hz drag", events(0.5, 10, 80), 9.5, &before);
  EXPECT_LE(moving_p95(frames), 100);
  EXPECT_GT(before, 100) << "the trace no longer shows what the old rules got wrong";
  // After the first events' frames (a plan's first frame is not judged), no moving frame at full size.
  const auto whole =
      std::count_if(frames.begin(), frames.end(), [](const Frame& f) { return f.moved && f.start_s > 1 && f.step == kWholeStep; });
  EXPECT_EQ(whole, 0);
}

// Rule: 60 Hz input (a fast mouse) moves almost every frame: as every frame moving.
TEST(ViewBudget, TraceSixtyHzInput) {
  double before = 0;
  const std::vector<Frame> frames = compare("60 Hz input", events(0.5, 60, 180), 4.0, &before);
  EXPECT_LE(moving_p95(frames), before);
  EXPECT_LE(moving_p95(frames), 100);
}

// The step of the last moving frame that started before `t_s`.
Step moving_step_before(const std::vector<Frame>& frames, double t_s) {
  Step step;
  for (const Frame& f : frames) {
    if (f.moved && f.start_s < t_s) step = f.step;
  }
  return step;
}

// Rule: bursts of input with gaps shorter than still_after hold the step across the gaps; a gap
// longer than still_after is rest, and the next burst starts whole again.
TEST(ViewBudget, TraceBursts) {
  std::vector<double> input;
  for (double start : {0.5, 0.95, 1.4, 3.0, 3.45}) {
    const std::vector<double> burst = events(start, 30, 6);
    input.insert(input.end(), burst.begin(), burst.end());
  }
  double before = 0;
  const std::vector<Frame> frames = compare("bursts", input, 4.5, &before);
  EXPECT_LE(moving_p95(frames), before);
  for (const Frame& f : frames) {
    // The bursts at 0.95 and 1.4 s began 0.28 s after the one before ended: not rest.
    if (f.moved && ((f.start_s >= 0.95 && f.start_s < 1.0) || (f.start_s >= 1.4 && f.start_s < 1.45))) {
      EXPECT_EQ(f.step, moving_step_before(frames, f.start_s > 1.4 ? 1.4 : 0.95)) << "at " << f.start_s;
      EXPECT_FALSE(f.step == kWholeStep) << "at " << f.start_s;
    }
  }
  const auto after_rest = std::find_if(frames.begin(), frames.end(), [](const Frame& f) { return f.start_s >= 3.0; });
  ASSERT_NE(after_rest, frames.end());
  EXPECT_EQ(after_rest->step, kWholeStep);
}

// Rule: a stop after a move holds the moving step until still_after has passed, then renders one
// whole frame (a new plan) and nothing more.
TEST(ViewBudget, TraceStopAfterMove) {
  const std::vector<Frame> frames = compare("stop after a move", events(0.5, 10, 20), 4.0);
  const double last_input = 0.5 + 19 / 10.0;
  size_t whole_at_rest = 0;
  for (const Frame& f : frames) {
    if (f.moved || f.start_s <= last_input) continue;
    if (f.start_s < last_input + 0.3) {
      EXPECT_EQ(f.step, moving_step_before(frames, last_input + 1e-9)) << "at " << f.start_s;
      EXPECT_FALSE(f.step == kWholeStep) << "at " << f.start_s;
    }
    if (f.step == kWholeStep && f.ms > kIdleMs) ++whole_at_rest;
  }
  EXPECT_EQ(whole_at_rest, 1u);
  EXPECT_EQ(frames.back().step, kWholeStep);
}

// Rule: only the device's refusal of the while_still values (the compile's InputError) is taken
// as one; a device failure is not (exit 3).
TEST(ViewBudget, OnlyAnInputErrorRefusesTheWhileStillValues) {
  EXPECT_EQ(still_values_refusal(std::make_exception_ptr(InputError("needs VK_KHR_ray_query"))), "needs VK_KHR_ray_query");
  EXPECT_THROW(still_values_refusal(std::make_exception_ptr(DeviceError("VK_ERROR_DEVICE_LOST"))), DeviceError);
}

}  // namespace
}  // namespace caustica::editor
