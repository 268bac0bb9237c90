// The stages against one fit (stages_check.hpp): the Bonferroni threshold in closed form, the
// comparison's numbers by hand, and its false-alarm rate on honest errors by Monte Carlo.
#include "exoid/experiments/protocol/stages_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace exoid::experiments {
namespace {

double twoSidedTail(double z) { return std::erfc(z / std::sqrt(2.0)); }

TEST(StagesCheck, TheThresholdSharesOneTestsTailAmongTheParameters) {
  EXPECT_NEAR(bonferroniZ(2.0, 1), 2.0, 1e-12);
  for (int n : {2, 10, 17, 36}) {
    const double z = bonferroniZ(2.0, n);
    EXPECT_NEAR(twoSidedTail(z) * n, twoSidedTail(2.0), 1e-12 * twoSidedTail(2.0)) << n;
  }
  EXPECT_NEAR(bonferroniZ(2.0, 17), 3.0, 0.01);  // the value leg3's 17 base parameters print
  EXPECT_GE(bonferroniZ(50.0, 10), 50.0);        // where the tail underflows: never below one test's
}

TEST(StagesCheck, DifferencesAreInBothErrorsAndNamedLargestFirst) {
  const Eigen::VectorXd stages = (Eigen::VectorXd(3) << 1.0, 2.0, 3.0).finished();
  const Eigen::VectorXd one = (Eigen::VectorXd(3) << 1.3, 2.0, 2.0).finished();
  const Eigen::VectorXd se_stages = (Eigen::VectorXd(3) << 0.03, 1.0, 0.06).finished();
  const Eigen::VectorXd se_one = (Eigen::VectorXd(3) << 0.04, 1.0, 0.08).finished();
  const StagesAgainstOneFit c = compareStagesWithOneFit(stages, se_stages, one, se_one, 2.0);
  EXPECT_NEAR(c.z[0], -0.3 / 0.05, 1e-12);
  EXPECT_NEAR(c.z[1], 0.0, 1e-12);
  EXPECT_NEAR(c.z[2], 1.0 / 0.1, 1e-12);
  ASSERT_EQ(c.beyond.size(), 2u);
  EXPECT_EQ(c.beyond[0], 2);
  EXPECT_EQ(c.beyond[1], 0);
  EXPECT_EQ(c.largest, 2);
  EXPECT_TRUE(stagesHidProblem(c, "").empty());  // differences alone are printed, not an exit code
  StagesAgainstOneFit hid = c;
  hid.one_fit_inconsistency = "has no physically consistent body within 9 standard errors";
  EXPECT_NE(stagesHidProblem(hid, "rerun with --armature knee").find("rerun with --armature knee"), std::string::npos);
  EXPECT_THROW(compareStagesWithOneFit(stages, se_stages.head(2), one, se_one, 2.0), std::invalid_argument);
  Eigen::VectorXd infinite = se_one;
  infinite[1] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(compareStagesWithOneFit(stages, se_stages, one, infinite, 2.0), std::invalid_argument);
}

// Independent estimates with honest errors (the difference's variance is the sum): any of 17
// parameters beyond the threshold as often as one test at 2 sigma at most, 1 - (1 - p / 17)^17 =
// 4.46 %; 20,000 draws put the rate within 0.5 % of it (3.4 binomial standard deviations).
TEST(StagesCheck, HonestErrorsRaiseAFalseAlarmAsOftenAsOneTest) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  const int n = 17, draws = 20000;
  const Eigen::VectorXd se_stages = Eigen::VectorXd::LinSpaced(n, 0.1, 2.0), se_one = Eigen::VectorXd::LinSpaced(n, 3.0, 0.5);
  int alarms = 0;
  for (int d = 0; d < draws; ++d) {
    Eigen::VectorXd stages(n), one(n);
    for (int i = 0; i < n; ++i) {
      stages[i] = 5.0 + se_stages[i] * normal(rng);
      one[i] = 5.0 + se_one[i] * normal(rng);
    }
    alarms += compareStagesWithOneFit(stages, se_stages, one, se_one, 2.0).beyond.empty() ? 0 : 1;
  }
  const double expected = 1.0 - std::pow(1.0 - twoSidedTail(2.0) / n, n);
  EXPECT_NEAR(static_cast<double>(alarms) / draws, expected, 0.005);
}

}  // namespace
}  // namespace exoid::experiments
