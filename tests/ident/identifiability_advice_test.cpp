// The identifiability report in words: each case names the parameter, its confusion partner and
// the motion that would help.
#include "exoid/ident/design/identifiability_advice.hpp"
#include "exoid/ident/leg/regressor.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace exoid::ident {
namespace {


std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& l : v) s += l + "\n";
  return s;
}

TEST(IdentifiabilityAdvice, AFixedHipLeavesTheThighUnidentifiable) {
  const JointSignals s = test::exactRecord(1, defaultLeg(), test::kLeg.gravity_mps2, 4.0);
  const Eigen::MatrixXd H = stackedRegressor(s, test::kLeg);
  const IdentifiabilityReport r = analyzeIdentifiability(H, stackedTorque(s), 0.5);
  const std::string a = joined(identifiabilityAdvice(H, r, twoLinkLeg(test::kLeg), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_NE(a.find("cannot be identified from this record"), std::string::npos) << a;
  EXPECT_NE(a.find("fc1 cannot be identified"), std::string::npos) << a;  // the hip never moves
  EXPECT_NE(a.find("reverse direction"), std::string::npos) << a;
}

TEST(IdentifiabilityAdvice, ThePapersSineIsPoorlyConditionedAndSaysWhatToDo) {
  // Trajectory 3's hip equation: one 1 Hz sine, scaled condition number ~250.
  const JointSignals s = test::exactRecord(3, defaultLeg(), test::kLeg.gravity_mps2, 4.0);
  const Eigen::MatrixXd H = jointRegressor(s, Joint::kHip, test::kLeg).leftCols(5);
  const IdentifiabilityReport r = analyzeIdentifiability(H, s.tau_Nm.col(0), 0.5);
  ASSERT_GT(r.condition_number, 100.0);
  const std::string a = joined(identifiabilityAdvice(H, r, twoLinkLeg(test::kLeg), {0, 1, 2, 3, 4}));
  EXPECT_NE(a.find("The excitation is poor: condition number"), std::string::npos) << a;
  EXPECT_NE(a.find("exoid excite"), std::string::npos) << a;
}

TEST(IdentifiabilityAdvice, AWellConditionedRecordSaysSo) {
  // Orthogonal columns: condition 1, tiny stds.
  Eigen::MatrixXd H(400, 2);
  for (Eigen::Index i = 0; i < 400; ++i) H.row(i) << std::sin(0.05 * double(i)), std::cos(0.05 * double(i));
  const IdentifiabilityReport r = analyzeIdentifiability(H, H * Eigen::Vector2d(5, 5), 0.01);
  const auto a = identifiabilityAdvice(H, r, twoLinkLeg(test::kLeg), {kJt, kJs});
  ASSERT_EQ(a.size(), 1u);
  EXPECT_NE(a[0].find("Well excited"), std::string::npos) << a[0];
  test::expectInvalidArgumentMentioning([&] { identifiabilityAdvice(H, r, twoLinkLeg(test::kLeg), {kJt}); }, "disagree in size");
}

TEST(IdentifiabilityAdvice, WithoutAReferenceJudgesByCollinearityNotByARelativeStd) {
  // Columns at |cos| = 0.99 (R^2 = 0.9801 > 0.95): poorly determined whatever the parameters'
  // values, which a NaN reference (none known) leaves out of the judgement. Whole periods make
  // sin and cos exactly orthogonal, so the angle is exact.
  Eigen::MatrixXd H(400, 2);
  for (Eigen::Index i = 0; i < 400; ++i) {
    const double w = 2.0 * M_PI * 3.0 * double(i) / 400.0;
    const double s = std::sin(w), c = std::cos(w);
    H.row(i) << s, 0.99 * s + std::sqrt(1.0 - 0.99 * 0.99) * c;
  }
  const Eigen::VectorXd none = Eigen::VectorXd::Constant(2, std::numeric_limits<double>::quiet_NaN());
  const IdentifiabilityReport r = analyzeIdentifiability(H, H * Eigen::Vector2d(5, 5), 0.01, none);
  ASSERT_TRUE(std::isnan(r.crb_rel_std[0]));
  const auto a = identifiabilityAdvice(H, r, twoLinkLeg(test::kLeg), {kJt, kJs});
  ASSERT_GE(a.size(), 2u);
  EXPECT_NE(a[0].find("Jt is poorly determined: 98.01 % of its column is explained"), std::string::npos) << a[0];
  EXPECT_NE(a[0].find("7.09x"), std::string::npos) << a[0];  // 1 / sqrt(1 - 0.9801)
  EXPECT_EQ(a[0].find("relative std"), std::string::npos) << a[0];
}

TEST(IdentifiabilityAdvice, NamesAnyChainsParametersAndTheMotionTheirKindNeeds) {
  // The 2-link leg as a chain in its base parameters, a knee armature among them: a column copied
  // from another cannot be identified, and the advice names it as the chain does and says what
  // motion its kind needs; the X basis gives each of its parameters the kind its name says.
  const Robot chain = chainRobot(twoLinkChain(test::kLeg, true));
  const auto index = [&](const std::string& lead) {
    const auto& n = chain.names();
    const auto it = std::find_if(n.begin(), n.end(), [&](const std::string& s) { return s.rfind(lead, 0) == 0; });
    EXPECT_NE(it, n.end()) << lead;
    return static_cast<int>(it - n.begin());
  };
  const std::vector<ParameterKind> kinds = parameterKinds(chain);
  EXPECT_EQ(kinds[static_cast<std::size_t>(index("knee.fc"))], ParameterKind::kCoulomb);
  EXPECT_EQ(kinds[static_cast<std::size_t>(index("knee.Ia"))], ParameterKind::kArmature);
  EXPECT_EQ(kinds[static_cast<std::size_t>(index("shank.mx"))], ParameterKind::kFirstMoment);
  const int p = chain.parameters();
  std::vector<int> all(static_cast<std::size_t>(p));
  for (int i = 0; i < p; ++i) all[static_cast<std::size_t>(i)] = i;
  Eigen::MatrixXd H(300, p);
  for (Eigen::Index i = 0; i < H.rows(); ++i) {
    for (int j = 0; j < p; ++j) H(i, j) = std::sin(0.37 * double((i + 1) * (j + 2)) + 0.1 * double(j * j));
  }
  for (const char* lead : {"knee.fc", "knee.Ia"}) {
    Eigen::MatrixXd copied = H;
    const int k = index(lead);
    copied.col(k) = H.col(k == 0 ? 1 : 0);
    const IdentifiabilityReport r = analyzeIdentifiability(copied, copied * Eigen::VectorXd::Ones(p), 0.01);
    const std::string a = joined(identifiabilityAdvice(copied, r, chain, all));
    EXPECT_NE(a.find(chain.names()[static_cast<std::size_t>(k)] + " cannot be identified"), std::string::npos) << a;
    EXPECT_NE(a.find(std::string(lead) == "knee.fc" ? "reverse direction" : "accelerating differently"), std::string::npos) << a;
  }
  const Robot x = twoLinkLeg(test::kLeg, true);
  const std::vector<ParameterKind> xk = parameterKinds(x);
  const std::vector<ParameterKind> expected = {ParameterKind::kFirstMoment, ParameterKind::kFirstMoment, ParameterKind::kInertia,
                                               ParameterKind::kCoulomb,     ParameterKind::kViscous,     ParameterKind::kFirstMoment,
                                               ParameterKind::kFirstMoment, ParameterKind::kInertia,     ParameterKind::kCoulomb,
                                               ParameterKind::kViscous,     ParameterKind::kArmature};
  EXPECT_EQ(xk, expected);
  test::expectInvalidArgumentMentioning([&] { identifiabilityAdvice(H.leftCols(1), analyzeIdentifiability(H.leftCols(1), H.col(0), 0.01), x, {11}); },
                                        "not the robot's");
}

}  // namespace
}  // namespace exoid::ident
