#pragma once
// The viewer's frame budget while the view moves, Cycles-style: a frame over the budget lowers the
// quality of the next, by as many steps as the frame predicts it takes to fit (each a new plan whose
// first frame costs more, so one move rather than several), a frame well under it raises it again
// (after a raise that did not hold, only once the step has held a while, longer each time), and the
// first still frame is whole.
// No window and no device here, so that its rules are tested on the CPU with made-up frame times
// (tests/frame_budget_test.cpp); the viewer feeds it the measured ones.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustica::editor {

class FrameBudget {
 public:
  // What a frame renders at: the window's size over `divider` each way, and with `lowered`, the
  // graph's while_moving values.
  struct Step {
    uint32_t divider = 1;
    bool lowered = false;
    bool operator==(const Step&) const = default;
  };

  explicit FrameBudget(double budget_ms) : budget_ms_(budget_ms) {}

  // The step of the next frame, after a frame that took `frame_ms` from input to present. With
  // `moving` (the camera or a light changes in the next frame), `can_scale` (the output reaches the
  // window by a scaling blit) and `can_lower` (the graph declares while_moving values).
  Step next(double frame_ms, bool moving, bool can_scale, bool can_lower);
  Step step() const { return kSteps[level_]; }
  // The viewer made a new plan for another reason (the while_still values, an edit, a reload): the
  // next frame measured is a first one too.
  void new_plan() { first_at_step_ = true; }

 private:
  // From whole to cheapest: each halving of the size each way, then the while_moving values.
  static constexpr std::array<Step, 4> kSteps{{{1, false}, {2, false}, {4, false}, {4, true}}};
  // How many times the frame at `level` costs the one at the next cheaper step, as predicted: the
  // measured ratio, for a size step at least kLeastSizeRatio (frame_budget.cpp); 0 where a step
  // with the while_moving values has not been measured.
  double ratio_over_next(size_t level) const;
  // The step a frame of `frame_ms` over the budget goes down to: the first predicted to fit, or the
  // first whose cost is not known yet, or the cheapest.
  size_t fitting_level(double frame_ms, size_t cheapest) const;
  double budget_ms_;
  size_t level_ = 0;
  // The frame just measured was the first at its step: a new plan, whose first frame runs every
  // pass (the light's too) and says little about the frames after it.
  bool first_at_step_ = true;
  // How much slower each step was than the next cheaper one when the budget last went down to it,
  // measured on frames after the first at each: what raising back is predicted to cost.
  std::array<double, kSteps.size()> cost_over_next_{};
  double last_at_step_ms_ = 0;  // the last representative frame time at the current step
  bool going_down_ = false;     // lowered by one step: its first representative frame sets cost_over_next_
  bool raised_ = false;         // the step was reached by going up, and has not held yet
  size_t held_ = 0;             // judged frames at the current step
  size_t hold_ = 0;             // judged frames a step is held before going up: longer after each raise that did not hold
};

// At rest, which of the graph's while_still values the viewer uses (graph::GraphParameter): a
// parameter may list several, each cheaper than the one before (caustics_progressive: a quarter of
// the photon grid a frame, then a ninth, a sixteenth), so that a refining frame fits the budget on
// a machine slower than the graph's author's, or busier than it was. The viewer starts at the first
// level and moves to the next whenever the median of the last kJudged refining frames at a level
// is over 0.9 of the budget (one slow frame does not decide). It moves back to the richer level
// when the machine got quieter: after kHeldBeforeRaise refining frames at a level, when the last
// kJudged frames' median times the richer level's cost over this one's is predicted within 0.7 of
// the budget. That cost is the most measured after any move between the two (the level left
// against the new one's frames kJudged + 1 to 2 kJudged, both at the load of then). A move back
// that does not hold makes the next wait twice as long, and its frames raise the cost. Where the values are sampling-only
// (ParamDecl::sampling_only: caustic_map.slice_side) the running mean goes on through every move. A
// new graph, or a new budget, starts again at the first.
class StillLevels {
 public:
  static constexpr size_t kJudged = 3;
  static constexpr size_t kHeldBeforeRaise = 30;
  StillLevels(double budget_ms, size_t levels) : budget_ms_(budget_ms), levels_(levels), cost_over_next_(levels, 0.0) {}
  size_t level() const { return level_; }
  size_t levels() const { return levels_; }
  // A refining frame at the current level took `frame_ms` (input to present). True when the next
  // frame is to use another level (level() says which); judged() then gives the median that
  // decided it, and after a move back predicted() what the richer level's frames should take.
  bool refined(double frame_ms);
  double judged() const { return judged_ms_; }
  double predicted() const { return predicted_ms_; }

 private:
  double budget_ms_;
  size_t levels_;
  size_t level_ = 0;
  std::vector<double> frames_;               // the current level's last kJudged refining frames
  double judged_ms_ = 0, predicted_ms_ = 0;  // judged: the median at the level the last move left
  // Per level: its frames' median over the next cheaper level's, the most measured after a move
  // between them (0: not yet).
  std::vector<double> cost_over_next_;
  bool measuring_cost_ = false;  // just moved: the level's second kJudged frames measure cost_over_next_
  size_t left_level_ = 0;        // the level the last move left
  bool raised_ = false;          // the current level was reached by moving back
  size_t held_ = 0;              // refining frames at the current level
  size_t hold_ = kHeldBeforeRaise;
};

// At rest, the steps in which a display frame shows the running result (graph::DisplayStep), so
// that each frame stays within the budget: the showing passes' last times in plan order, and what
// a frame costs besides its passes (recording, the panels, the present). Consecutive passes share a
// step while their sum and the overhead fit; a pass over the budget alone is a step of its own, and
// one that costs nothing (the G-buffer, unchanged at rest) never makes a step alone.
// Returns each step's end (by number among the showing passes); the last is pass_ms.size().
std::vector<size_t> display_steps(const std::vector<double>& pass_ms, double overhead_ms, double budget_ms);
// The overhead display_steps cuts with, after a frame that took `wall_ms` (`gpu_ms` of it on the
// device): measured on frames that went to the window, as a display's last step does; a frame not
// presented (editor::present_due) saves the present and leaves `overhead_ms` as it was.
double display_overhead(double overhead_ms, double wall_ms, double gpu_ms, bool presented);

// At rest, while frames refine apart, whether the next frame is to show the running mean: at least
// kShowAfter after the picture last changed, and then once the mean has grown by a tenth since
// (`accumulated` against `accumulated_shown`: graph::FrameResult::accumulated), or kShowAtMost has
// passed. A mean's picture changes less with each frame as it grows, so later shows come less
// often and more of the time goes into the mean (Cycles' viewport, too, redraws less often as
// samples add up).
inline constexpr double kShowAfter = 0.5, kShowAtMost = 2.0;  // seconds
bool display_due(double since_shown_s, uint64_t accumulated, uint64_t accumulated_shown);

// Whether a frame goes to the window: one that changed the picture does, and one that left it as it
// was (a refining frame, a display step before the last) only after input, so that the panels answer
// at once, or when kPanelRefresh has passed since the last, so that their numbers move. On lavapipe
// under X the copy into the window and the panels' draw cost about a fifth of a refining frame.
inline constexpr double kPanelRefresh = 0.25;  // seconds
bool present_due(bool picture_changed, bool input, double since_presented_s);
// What a refining frame is judged at (StillLevels::refined): its wall time where it went to the
// window, else its device time and the overhead a presented frame adds (display_overhead), since
// one refining frame in a few is presented (the panels, input) and has to fit the budget too.
double refining_frame_ms(double wall_ms, double gpu_ms, bool presented, double overhead_ms);

}  // namespace caustica::editor
