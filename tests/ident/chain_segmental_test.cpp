// The segmental strategy down any chain: exact records give the exact base parameters, each stage
// fits only what the joints it moves determine (the APAL leg's knee stage: the knee's five), a lock
// that makes a link's inertia and its joint's armature act alike leaves their split to a later
// stage, and stage lists that cannot work are refused with the reason.
#include "exoid/ident/model/chain_segmental.hpp"

#include "exoid/ident/model/chain_processing.hpp"
#include "random_chain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace exoid::ident {
namespace {

using testing::apalChain;
using testing::randomChain;
using testing::randomPhysicalParameters;

// An exact record: joints first..tip follow a two-frequency motion with analytic derivatives,
// the joints above are locked (constant angle, zero rates); torque = W phi, no noise.
ChainStage exactStage(const ChainModel& m, const Eigen::VectorXd& phi, Eigen::Index first, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> amp(0.3, 0.9), freq(0.3, 1.7), phase(0.0, 6.28), lock(-1.0, 1.0);
  const Eigen::Index n = 600, dof = m.dof();
  JointSignals s;
  s.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 0.01 * static_cast<double>(n - 1));
  s.q_rad.resize(n, dof);
  s.qd_radps.resize(n, dof);
  s.qdd_radps2.resize(n, dof);
  s.tau_Nm = Eigen::MatrixXd::Zero(n, dof);
  for (Eigen::Index j = 0; j < dof; ++j) {
    if (j < first) {
      s.q_rad.col(j).setConstant(lock(gen));
      s.qd_radps.col(j).setZero();
      s.qdd_radps2.col(j).setZero();
      continue;
    }
    const double a1 = amp(gen), w1 = 2 * M_PI * freq(gen), p1 = phase(gen), a2 = 0.4 * amp(gen), w2 = 2 * M_PI * freq(gen) * 2.3, p2 = phase(gen);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = s.t_s[i];
      s.q_rad(i, j) = a1 * std::sin(w1 * t + p1) + a2 * std::sin(w2 * t + p2);
      s.qd_radps(i, j) = a1 * w1 * std::cos(w1 * t + p1) + a2 * w2 * std::cos(w2 * t + p2);
      s.qdd_radps2(i, j) = -a1 * w1 * w1 * std::sin(w1 * t + p1) - a2 * w2 * w2 * std::sin(w2 * t + p2);
    }
  }
  ChainStage st;
  st.first_joint = first;
  st.record = chainRows(m, s);
  st.record.y = st.record.W * phi;
  return st;
}

double relativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& truth) {
  return (x - truth).cwiseAbs().maxCoeff() / truth.cwiseAbs().maxCoeff();
}

TEST(ChainSegmental, ApalLegKneeStageFitsTheKneesFiveThenTheHipsFive) {
  const ChainModel m = apalChain(0.45);
  std::mt19937_64 gen(3);
  const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
  const BaseParameters bp = baseParameters(m);
  const std::vector<ChainStage> stages = {exactStage(m, phi, 1, 11), exactStage(m, phi, 0, 12)};
  const ChainSegmentalResult r = identifyChainSegmental(m, bp, stages, Method::kLs, MethodOptions{});
  ASSERT_EQ(r.stages.size(), 2u);
  // Stage 1 fits the knee's equation: five combinations, each a whole base parameter of the shank
  // or the knee (the paper's Mxs, Mys, Js, fc2, fv2), so a search box there is per parameter.
  EXPECT_EQ(r.stages[0].directions.cols(), 5);
  EXPECT_EQ(r.stages[0].rows, 600);
  for (const std::string& name : r.stages[0].names) {
    EXPECT_EQ(name.find("thigh"), std::string::npos) << name;
    EXPECT_EQ(name.find("hip"), std::string::npos) << name;
    EXPECT_EQ(name.find(" + "), std::string::npos) << name << ": not a whole base parameter";
  }
  EXPECT_EQ(r.stages[1].directions.cols(), 5);
  // Exact data: the exact base parameters (least squares over exact rows: rounding only).
  EXPECT_LT(relativeError(r.beta, bp.combination * phi), 1e-10);
}

TEST(ChainSegmental, RandomSpatialChainsDownFourStagesAreExact) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    std::mt19937_64 gen(seed);
    const ChainModel m = randomChain(gen, 4);  // armature on joints 1 and 3
    const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
    const BaseParameters bp = baseParameters(m);
    std::vector<ChainStage> stages;
    for (Eigen::Index first = 3; first >= 0; --first) stages.push_back(exactStage(m, phi, first, 100 * seed + static_cast<std::uint64_t>(first)));
    const ChainSegmentalResult r = identifyChainSegmental(m, bp, stages, Method::kLs, MethodOptions{});
    Eigen::Index total = 0;
    for (const ChainStageResult& s : r.stages) total += s.directions.cols();
    EXPECT_EQ(total, bp.rank) << "seed " << seed;
    EXPECT_LT(relativeError(r.beta, bp.combination * phi), 1e-8) << "seed " << seed;
    // LAD composes the same way (its exact optimum on exact rows is the truth too).
    const ChainSegmentalResult l = identifyChainSegmental(m, bp, stages, Method::kLad, MethodOptions{});
    EXPECT_LT(relativeError(l.beta, bp.combination * phi), 1e-6) << "seed " << seed;
  }
}

TEST(ChainSegmental, ALockThatJoinsInertiaAndArmatureLeavesTheSplitToTheNextStage) {
  // Planar: the APAL chain with knee armature. Hip locked, the knee's acceleration is the shank's:
  // stage 1 fits shank inertia + armature as one combination; the two-joint stage separates them.
  ChainModel m = apalChain(0.45);
  m.joints[1].armature = true;
  std::mt19937_64 gen(5);
  const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
  const BaseParameters bp = baseParameters(m);
  ASSERT_EQ(bp.rank, 11);
  const ChainSegmentalResult r =
      identifyChainSegmental(m, bp, {exactStage(m, phi, 1, 21), exactStage(m, phi, 0, 22)}, Method::kLs, MethodOptions{});
  EXPECT_EQ(r.stages[0].directions.cols(), 5);
  bool joined = false;
  for (const std::string& name : r.stages[0].names) joined = joined || (name.find("knee.Ia") != std::string::npos && name.find(" + ") != std::string::npos);
  EXPECT_TRUE(joined) << "stage 1 should fit the shank's inertia and the knee's armature as one sum";
  EXPECT_EQ(r.stages[1].directions.cols(), 6);
  EXPECT_LT(relativeError(r.beta, bp.combination * phi), 1e-10);
}

TEST(ChainSegmental, RefusesWhatCannotWork) {
  const ChainModel m = apalChain(0.45);
  std::mt19937_64 gen(7);
  const Eigen::VectorXd phi = randomPhysicalParameters(gen, m);
  const BaseParameters bp = baseParameters(m);
  const ChainStage knee = exactStage(m, phi, 1, 1), both = exactStage(m, phi, 0, 2);
  const auto message = [&](const std::vector<ChainStage>& stages) {
    try {
      identifyChainSegmental(m, bp, stages, Method::kLs, MethodOptions{});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no refusal");
  };
  EXPECT_NE(message({}).find("no stages"), std::string::npos);
  EXPECT_NE(message({both, knee}).find("distal joints first"), std::string::npos);
  EXPECT_NE(message({knee}).find("leave 5 combination(s) unidentified"), std::string::npos) << message({knee});
  EXPECT_NE(message({knee, knee}).find("identifies no combination"), std::string::npos);
}

}  // namespace
}  // namespace exoid::ident
