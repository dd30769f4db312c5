#pragma once
// The viewer's frame budget as one controller: what each frame renders at (the moving step, the
// while_still values and their level), which part of the work a still frame does (refine or show,
// and a display's steps), and whether it goes to the window. The viewer feeds it what it measures
// and knows each frame and obeys its answers; no window and no device here, so that its rules are
// tested on the CPU with recorded input traces (tests/view_budget_test.cpp).
//
// Its rules, in the order a frame meets them:
// - Quality is judged on frames that moved and rendered: a frame with nothing to render (an idle
//   frame between two input events) neither raises nor lowers the moving step.
// - A gap between input events is not rest: the moving step holds until nothing has moved for
//   still_after. Then the view is at rest: whole again, with the while_still values where the graph
//   declares them (one new plan, the moving picture standing while it refines).
// - At rest, refining frames choose the while_still level (StillLevels), and a plan that refines
//   apart refines and now and then shows in display steps (display_due, display_steps).
// - A frame goes to the window when present_due says so.
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "graph/executor.h"
#include "model/frame_budget.h"

namespace caustica::editor {

class ViewBudget {
 public:
  // budget_ms: --budget (0: off); still_after_ms: --still-after; start_s: the clock now (seconds,
  // the clock the viewer passes from then on), from which the first rest is counted.
  ViewBudget(double budget_ms, double still_after_ms, double start_s);

  // What a frame renders at; a change is a new plan.
  struct Setting {
    FrameBudget::Step step;
    bool still_values = false;  // the graph's while_still values,
    size_t still_level = 0;     // those of this level (StillLevels)
    bool operator==(const Setting&) const = default;
  };
  // The answer before a frame: its setting, whether that asks for a new plan, and whether the
  // picture before stands while the new plan refines (a change at rest, of quality alone).
  struct Decision {
    Setting setting;
    bool new_plan = false;
    bool picture_stands = false;
  };
  // Before a frame, once its input is known. `moved`: the camera or a light changes in it;
  // `can_scale`, `can_lower`: as FrameBudget::next.
  Decision begin_frame(double now_s, bool moved, bool can_scale, bool can_lower);

  // The part of the work the frame does. `must_show`: a screenshot, the inspector or the last
  // frame wants the result; `refines_apart`, `converging`, `accumulated`: the plan's and the last
  // frame's (graph::Plan, graph::FrameResult).
  struct Part {
    graph::FramePart part = graph::FramePart::whole;
    graph::DisplayStep step;
  };
  Part frame_part(double now_s, bool must_show, bool refines_apart, bool converging, uint64_t accumulated);

  // Whether the frame goes to the window (present_due); remembered for what it is measured at.
  bool present(double now_s, bool picture_changed, bool input);
  // The frame's result showed nothing new and is not presented after all (the plan changed under it).
  void not_presented() { presented_ = false; }

  // After a frame, what it took.
  struct Measured {
    double now_s = 0;
    double wall_ms = 0, gpu_ms = 0;
    bool rendered = false;  // a pass ran
    graph::FramePart part = graph::FramePart::whole;
    bool first_of_plan = false;  // the plan's first frame (graph::FrameResult::frame.index == 0)
    uint64_t accumulated = 0;
    // Where the plan refines apart, its showing passes (by number among them, graph::DisplayStep)
    // and their times in this frame: 0 for one that keeps its result while nothing changes, none
    // for one that did not run (its last time holds). Empty when the frame's passes are not the
    // plan's (it changed under the frame).
    size_t showing_passes = 0;
    std::vector<std::optional<double>> showing_ms;
  };
  // Returns true when the next frame is to use another while_still level (a new plan whose picture
  // stands, its showing passes kept: plan_changed(true, true)).
  bool end_frame(const Measured& frame);

  // The viewer made a new plan (for the budget or another reason: an edit, a reload, a resize).
  // `picture_standing`: the plan before's picture stands for it; `showing_kept`: it differs in what
  // refines only (a still level), so the last whole frame's time still holds.
  void plan_changed(bool picture_standing, bool showing_kept);
  // A new graph: its values as set, and its while_still values (`still_levels` of them; 0: none)
  // may be tried again from the first level.
  void new_graph(size_t still_levels);
  // The device cannot run the while_still values (still_values_refusal): the values as set, until
  // the graph changes.
  void refuse_still_values();

  // Whether frames are to go on without input: the view is not yet at rest, or is at rest but
  // without the while_still values it will take. rest_in_s: the seconds until it is at rest (0:
  // now or already).
  bool rest_pending() const { return !at_rest_ || still_values_due(); }
  double rest_in_s(double now_s) const;

  const Setting& setting() const { return setting_; }
  bool moved() const { return moved_; }
  bool presented() const { return presented_; }
  double last_wall_ms() const { return last_wall_ms_; }
  double budget_ms() const { return budget_ms_; }
  const StillLevels& still_levels() const { return still_levels_; }
  // The display under way's number of steps (display_steps).
  size_t display_frames() const { return display_ends_.size(); }
  // Whether the frame just run changed the picture: one that ran whole, or a display's last step.
  bool showed_result(graph::FramePart part) const;

 private:
  bool still_values_due() const { return still_values_wanted_ && !setting_.still_values; }

  double budget_ms_, still_after_s_;
  FrameBudget budget_;
  Setting setting_;
  bool moved_ = false;                // the frame under way moved
  double last_move_s_;                // when something last moved (the start, before that)
  bool at_rest_ = false;              // the setting is the rest one (still_after has passed)
  std::optional<double> judged_ms_;   // the last moving frame that rendered: what the step is judged on next
  bool still_values_wanted_ = false;  // the graph declares while_still values the device has not refused
  StillLevels still_levels_;
  double last_wall_ms_ = 0;   // the last frame's, input to present
  double last_whole_ms_ = 0;  // the last frame's of this plan that ran whole; its first's estimated
  double last_presented_s_ = -1e300, last_shown_s_ = -1e300;
  bool presented_ = false;
  uint64_t accumulated_shown_ = 0;    // the frames in the running mean the last shown frame showed
  std::vector<double> showing_ms_;    // the showing passes' last times
  double frame_overhead_ms_ = 0;      // display_overhead
  std::vector<size_t> display_ends_;  // the steps of the display under way (display_steps)
  size_t display_step_ = 0;           // its next step; 0: none under way
};

// Whether a still-values plan's failure (`failure`, caught from configuring it) is the device
// refusing them: the compile's InputError naming what the device lacks (exact photons without
// VK_KHR_ray_query). Returns its message, for the viewer to say and go on with the values as set;
// anything else (a DeviceError: the device failed) is rethrown, and ends the viewer with exit 3.
std::string still_values_refusal(const std::exception_ptr& failure);

}  // namespace caustica::editor
