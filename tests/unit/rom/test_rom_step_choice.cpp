// How `nsf calibrate --dt-ratios` picks the ROM step from its table
// (rom/calibration/latent_prior_calibration.h): the largest ratio whose mean δ stays within the
// tolerance of the best ratio's, or within a budget.
#include <gtest/gtest.h>

#include <cmath>

#include "rom/calibration/latent_prior_calibration.h"

namespace nsf {
namespace {

StepCalibration table(std::vector<double> ratios, std::vector<double> mean,
                      std::vector<bool> stopped = {}) {
  StepCalibration s;
  s.ratios = std::move(ratios);
  s.mean = std::move(mean);
  s.stopped = stopped.empty() ? std::vector<bool>(s.mean.size(), false) : std::move(stopped);
  s.tolerance = 1.25;
  return s;
}

TEST(StepChoice, TheLargestRatioWithinTheToleranceOfTheBest) {
  // metal_small's table (2026-11-28): the first is the best; 2Δt is 1.44× it.
  EXPECT_EQ(chosen_step(table({1, 1.4, 2}, {0.00744, 0.00779, 0.01074})), 1.4);
  // sand_paper's bases at two points per cell: 10Δt is the best by far, and 20Δt, within 1.25× of
  // the first but 1.54× the best, is not chosen.
  const StepCalibration sand = table({4, 10, 20}, {0.01632, 0.00939, 0.01448});
  EXPECT_EQ(best_step(sand), 1u);
  EXPECT_DOUBLE_EQ(step_limit(sand), 1.25 * 0.00939);
  EXPECT_EQ(chosen_step(sand), 10);
  // A budget the larger step stays within admits it.
  StepCalibration budget = sand;
  budget.budget = 0.015;
  EXPECT_EQ(chosen_step(budget), 20);
  // A stopped ratio's mean is a lower bound: neither the best nor chosen; a failed one neither.
  EXPECT_EQ(chosen_step(table({1, 2, 3}, {0.01, 0.002, 0.011}, {false, true, false})), 3);
  EXPECT_EQ(chosen_step(table({1, 2, 3}, {0.01, INFINITY, 0.011})), 3);
  EXPECT_EQ(chosen_step(table({1, 2}, {INFINITY, 0.01})), -1);
}

}  // namespace
}  // namespace nsf
