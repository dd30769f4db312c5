// The viewer's frame budget (editor/model/frame_budget.h) on made-up frame times: down as many
// steps as a frame over the budget predicts, up again when the richer step is predicted to stay well under it, never
// judged on the first frame of a new plan, whole again when the view stops.
#include <gtest/gtest.h>

#include <vector>

#include "model/frame_budget.h"

namespace caustica::editor {
namespace {

using Step = FrameBudget::Step;

// Feeds frame times to a budget of 100 ms, the view moving throughout; returns the steps chosen.
std::vector<Step> moving(FrameBudget& budget, const std::vector<double>& frame_ms, bool can_lower = true) {
  std::vector<Step> steps;
  for (double ms : frame_ms) steps.push_back(budget.next(ms, true, true, can_lower));
  return steps;
}

constexpr Step kWhole{1, false}, kHalf{2, false}, kQuarter{4, false}, kLowered{4, true};

TEST(FrameBudget, GoesDownAsManyStepsAsTheFramePredictsItTakesToFit) {
  // A size step is predicted to cost at least twice the next (kLeastSizeRatio), the while_moving
  // values' step nothing until measured; the first frame at each step (a new plan) decides nothing.
  FrameBudget half(100);
  EXPECT_EQ(moving(half, {150, 150}), (std::vector<Step>{kWhole, kHalf}));  // predicted 75 at half
  FrameBudget quarter(100);
  EXPECT_EQ(moving(quarter, {300, 300}), (std::vector<Step>{kWhole, kQuarter}));  // 150 at half, 75 at a quarter
  FrameBudget lowered(100);
  EXPECT_EQ(moving(lowered, {500, 500}), (std::vector<Step>{kWhole, kLowered}));  // 125 at a quarter
  FrameBudget unlowered(100);
  EXPECT_EQ(moving(unlowered, {500, 500}, false), (std::vector<Step>{kWhole, kQuarter}));
  // Frames over the budget at the step reached go on down.
  FrameBudget steps(100);
  EXPECT_EQ(moving(steps, {150, 150, 150, 130, 120, 110}), (std::vector<Step>{kWhole, kHalf, kHalf, kQuarter, kQuarter, kLowered}));
}

// Whole to a quarter, then a frame over the budget there: the while_moving values, one step, whose
// cost over the quarter the next judged frame measures.
std::vector<Step> to_lowered_one_step(FrameBudget& budget) {
  return moving(budget, {300, 300, 120, 120});
}

TEST(FrameBudget, GoesBackUpWhenTheRicherStepIsPredictedWellUnderTheBudget) {
  FrameBudget budget(100);
  to_lowered_one_step(budget);
  ASSERT_EQ(budget.step(), kLowered);
  // The while_moving values made the frame 2x cheaper (120 -> 60): at 60 a return would cost
  // about 120, over the budget; at 30 about 60, within 0.8 of it.
  EXPECT_EQ(moving(budget, {60, 60, 60}), (std::vector<Step>{kLowered, kLowered, kLowered}));
  EXPECT_EQ(moving(budget, {30}), (std::vector<Step>{kQuarter}));
  // The half was never measured: predicted at twice the quarter, 90 ms at 45 (no), 80 at 40 (up).
  EXPECT_EQ(moving(budget, {45, 45, 40}), (std::vector<Step>{kQuarter, kQuarter, kHalf}));
}

TEST(FrameBudget, ARaiseIsPredictedAtNoLessThanTwiceTheSmallerSize) {
  FrameBudget budget(100);
  // Down to half on 150 ms; half-size frames measured at 100 (the first judged one still settling
  // after the new plan) would make the whole predicted at 1.5 times: 45 -> 68 ms. Predicted at
  // twice, 90: no raise.
  EXPECT_EQ(moving(budget, {150, 150, 120, 100}), (std::vector<Step>{kWhole, kHalf, kHalf, kHalf}));
  EXPECT_EQ(moving(budget, {45, 45, 45}), (std::vector<Step>{kHalf, kHalf, kHalf}));
  EXPECT_EQ(moving(budget, {38}), (std::vector<Step>{kWhole}));  // 76 ms predicted
}

TEST(FrameBudget, ARaiseThatDoesNotHoldWaitsLongerBeforeTheNext) {
  FrameBudget budget(100);
  to_lowered_one_step(budget);
  ASSERT_EQ(budget.step(), kLowered);
  // The quarter is predicted at 2 times the lowered frame (120 / 60): at 30, up.
  EXPECT_EQ(moving(budget, {60, 60, 30}), (std::vector<Step>{kLowered, kLowered, kQuarter}));
  // The raise does not hold: its first judged frame is over the budget.
  EXPECT_EQ(moving(budget, {70, 110}), (std::vector<Step>{kQuarter, kLowered}));
  // Predicted at 2 times again (110 / 55), but the next raise waits 8 judged frames.
  EXPECT_EQ(moving(budget, {60, 55}), (std::vector<Step>{kLowered, kLowered}));
  EXPECT_EQ(moving(budget, std::vector<double>(8, 30)),
            (std::vector<Step>{kLowered, kLowered, kLowered, kLowered, kLowered, kLowered, kLowered, kQuarter}));
}

TEST(FrameBudget, HoldsASteadyFrameTimeWithoutGoingUpAndDown) {
  FrameBudget budget(100);
  // Whole frames take 150 ms, half-size ones 60: going back up would cost 150 again.
  std::vector<double> times{150, 150, 60};
  for (int i = 0; i < 20; ++i) times.push_back(60);
  const std::vector<Step> steps = moving(budget, times);
  for (size_t i = 2; i < steps.size(); ++i) EXPECT_EQ(steps[i], kHalf) << "frame " << i;
}

TEST(FrameBudget, WholeAgainWhenTheViewStops) {
  FrameBudget budget(100);
  moving(budget, {300, 300});
  ASSERT_EQ(budget.step(), kQuarter);
  EXPECT_EQ(budget.next(200, false, true, true), kWhole);
}

TEST(FrameBudget, StopsAtAQuarterWithoutWhileMovingValues) {
  FrameBudget budget(100);
  const std::vector<Step> steps = moving(budget, {500, 500, 500, 500, 500, 500, 500, 500}, false);
  EXPECT_EQ(steps.back(), kQuarter);
}

TEST(FrameBudget, NothingChangesWithoutAScalingBlitOrABudget) {
  FrameBudget unscaled(100);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(unscaled.next(500, true, false, true), kWhole);
  FrameBudget unlimited(0);
  EXPECT_EQ(moving(unlimited, {500, 500, 500, 500}), (std::vector<Step>{kWhole, kWhole, kWhole, kWhole}));
}

TEST(FrameBudget, ANewPlanForAnotherReasonIsNotJudgedOnItsFirstFrame) {
  FrameBudget budget(100);
  moving(budget, {50, 50});
  budget.new_plan();  // say the while_still values were dropped when the view began to move
  EXPECT_EQ(moving(budget, {700}), (std::vector<Step>{kWhole}));
  EXPECT_EQ(moving(budget, {150}), (std::vector<Step>{kHalf}));
}

// The showing passes at rest in steps within the budget (the bunny's lighting, refraction and tone
// map at 1280x720 on lavapipe took about 40, 60 and 12 ms, with 10 ms of the frame besides).
// Feeds refining frame times; returns the level after each.
std::vector<size_t> refining(StillLevels& levels, const std::vector<double>& frame_ms) {
  std::vector<size_t> after;
  for (double ms : frame_ms) {
    levels.refined(ms);
    after.push_back(levels.level());
  }
  return after;
}

TEST(StillLevels, RefiningFramesOverTheBudgetTakeTheNextLevelJudgedOnTheirMedian) {
  StillLevels levels(100, 3);
  // One slow frame among three does not decide; a median over 0.9 of the budget does, and the next
  // level is judged on its own frames.
  EXPECT_EQ(refining(levels, {80, 300, 89}), (std::vector<size_t>{0, 0, 0}));
  EXPECT_EQ(refining(levels, {85, 300, 80, 88}), (std::vector<size_t>{0, 0, 0, 0})) << "a level within the budget is kept";
  // A machine that gets busier later: the last three frames decide, whenever they are slow.
  EXPECT_EQ(refining(levels, {300, 300, 300}), (std::vector<size_t>{0, 1, 1}));
  EXPECT_DOUBLE_EQ(levels.judged(), 300);
  StillLevels slow(100, 3);
  EXPECT_EQ(refining(slow, {120, 90, 130}), (std::vector<size_t>{0, 0, 1}));
  EXPECT_DOUBLE_EQ(slow.judged(), 120);
  EXPECT_EQ(refining(slow, {110, 92, 95, 300, 300, 300}), (std::vector<size_t>{1, 1, 2, 2, 2, 2}))
      << "a median of 95 leaves too little of the budget; the last level stays";
  StillLevels one(100, 1);
  EXPECT_EQ(refining(one, {500, 500, 500}), (std::vector<size_t>{0, 0, 0})) << "a single value has nowhere to go";
  StillLevels off(0, 3);
  EXPECT_EQ(refining(off, {500, 500, 500}), (std::vector<size_t>{0, 0, 0})) << "no budget";
}

// A machine that got quieter: after kHeldBeforeRaise refining frames at a level, the richer level
// comes back when its frames are predicted within 0.7 of the budget (this level's median times the
// richer level's cost over this one's, measured on this level's second three frames when the
// viewer moved down; its first ones run slower after the new plan). A move back that does not
// hold doubles the wait for the next.
TEST(StillLevels, AQuieterMachineTakesTheRicherLevelBackPredictedFromTheCostMeasuredGoingDown) {
  StillLevels levels(100, 3);
  EXPECT_EQ(refining(levels, {150, 150, 150}).back(), 1u);
  // The ninth's second three measure the quarter at 150 / 75 = 2 times its cost.
  EXPECT_EQ(refining(levels, {85, 85, 85, 75, 75, 75}).back(), 1u);
  // Quieter: 30 ms predicts 60 for the quarter, but only after 30 frames at the ninth.
  const std::vector<double> quiet(StillLevels::kHeldBeforeRaise - 7, 30.0);
  EXPECT_EQ(refining(levels, quiet).back(), 1u) << "moved back before holding the level";
  EXPECT_EQ(refining(levels, {30}), (std::vector<size_t>{0}));
  EXPECT_DOUBLE_EQ(levels.judged(), 30);
  EXPECT_DOUBLE_EQ(levels.predicted(), 60);
  // The quarter turns out slow again: down at once, and the next move back waits twice as long.
  EXPECT_EQ(refining(levels, {95, 95, 95}).back(), 1u);
  EXPECT_EQ(refining(levels, {40, 40, 40, 40, 40, 40}).back(), 1u);
  const std::vector<double> quieter(2 * StillLevels::kHeldBeforeRaise - 7, 20.0);
  EXPECT_EQ(refining(levels, quieter).back(), 1u) << "a move back that did not hold did not wait longer";
  EXPECT_EQ(refining(levels, {20}), (std::vector<size_t>{0}));
  // The cost is now the 95 / 30 the quarter's frames showed against the ninth's before that move,
  // more than the 95 / 40 measured going down: the most measured counts.
  EXPECT_DOUBLE_EQ(levels.predicted(), 20 * 95 / 30.0);
  StillLevels again(100, 3);
  refining(again, {150, 150, 150, 85, 85, 85, 75, 75, 75});
  EXPECT_EQ(refining(again, std::vector<double>(StillLevels::kHeldBeforeRaise - 6, 30.0)).back(), 0u);
  refining(again, {95, 95, 95, 40, 40, 40, 40, 40, 40});
  EXPECT_EQ(refining(again, std::vector<double>(3 * StillLevels::kHeldBeforeRaise, 28.0)).back(), 1u)
      << "moved back on the cost measured going down (28 ms predicts 66.5 with it, 88.7 with the move's own)";
  // A prediction over 0.7 of the budget keeps the cheaper level however long it holds.
  StillLevels busy(100, 3);
  refining(busy, {150, 150, 150, 75, 75, 75, 75, 75, 75});
  const std::vector<double> steady(3 * StillLevels::kHeldBeforeRaise, 36.0);  // predicts 72
  EXPECT_EQ(refining(busy, steady).back(), 1u);
}

// At rest the picture shows the mean every half second at first, then each time the mean has grown
// by a tenth, and at least every two seconds.
TEST(DisplayDue, ShowsComeLessOftenAsTheMeanGrows) {
  EXPECT_FALSE(display_due(0.4, 20, 10)) << "within half a second of the last";
  EXPECT_TRUE(display_due(0.5, 11, 10));
  EXPECT_FALSE(display_due(1.2, 105, 100)) << "the mean grew by 5%";
  EXPECT_TRUE(display_due(1.2, 110, 100));
  EXPECT_TRUE(display_due(2.0, 101, 100)) << "two seconds passed";
  EXPECT_TRUE(display_due(0.5, 1, 0)) << "nothing shown yet";
}

// A display's steps are cut with the overhead of a frame that went to the window: a refining frame
// not presented, about 11 ms cheaper under Xvfb, would join steps that then go over the budget.
TEST(DisplayOverhead, IsMeasuredOnFramesThatWentToTheWindow) {
  EXPECT_DOUBLE_EQ(display_overhead(12.0, 60.0, 45.0, true), 15.0);
  EXPECT_DOUBLE_EQ(display_overhead(12.0, 46.0, 45.0, false), 12.0) << "a frame not presented";
  EXPECT_DOUBLE_EQ(display_overhead(12.0, 40.0, 45.0, true), 0.0);
}

// A refining frame not presented is judged as if it were (a quarter grid's at 85 ms on the GPU, 1
// ms besides, is 97 ms when one in a few goes to the window at 12 ms besides).
TEST(RefiningFrameMs, IsWhatTheFrameTakesWhenItGoesToTheWindow) {
  EXPECT_DOUBLE_EQ(refining_frame_ms(86.0, 85.0, false, 12.0), 97.0);
  EXPECT_DOUBLE_EQ(refining_frame_ms(99.0, 85.0, true, 12.0), 99.0) << "a presented frame's own wall time";
}

// A frame that left the picture as it was goes to the window only for input or the panels' numbers.
TEST(PresentDue, AFrameThatLeftThePictureIsPresentedOnlyForInputOrThePanel) {
  EXPECT_TRUE(present_due(true, false, 0.0));
  EXPECT_FALSE(present_due(false, false, 0.2));
  EXPECT_TRUE(present_due(false, true, 0.0)) << "input answers within the frame";
  EXPECT_TRUE(present_due(false, false, kPanelRefresh));
}

TEST(DisplaySteps, ShowingPassesShareAStepWhileTheyFitTheBudget) {
  EXPECT_EQ(display_steps({40, 60, 12}, 10, 100), (std::vector<size_t>{1, 3}));
  EXPECT_EQ(display_steps({40, 60, 12}, 10, 200), (std::vector<size_t>{3})) << "all fit one frame";
  EXPECT_EQ(display_steps({40, 60, 12}, 10, 0), (std::vector<size_t>{3})) << "no budget: one frame";
  EXPECT_EQ(display_steps({150, 20, 20}, 10, 100), (std::vector<size_t>{1, 3})) << "a pass over the budget is a step of its own";
  EXPECT_EQ(display_steps({20, 150, 20}, 10, 100), (std::vector<size_t>{1, 2, 3}));
  EXPECT_EQ(display_steps({0, 0, 0}, 10, 100), (std::vector<size_t>{3})) << "passes not yet measured: one frame";
  EXPECT_EQ(display_steps({0, 60, 50}, 10, 100), (std::vector<size_t>{2, 3})) << "a skipped pass goes with the next";
  EXPECT_EQ(display_steps({0, 40, 60, 12}, 10, 1), (std::vector<size_t>{2, 3, 4})) << "every pass over the budget: one a frame";
  EXPECT_EQ(display_steps({}, 10, 100), (std::vector<size_t>{0}));
}

}  // namespace
}  // namespace caustica::editor
