// `exoid reproduce` on a shortened protocol: every table and figure file is produced, the numbers
// are reproducible, and the truths are what the simulator says.
#include "cli_test_support.hpp"
#include "exoid/experiments/protocol/protocol.hpp"
#include "exoid/experiments/protocol/reproduce.hpp"
#include "exoid/experiments/report/table.hpp"

#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/leg/consistency.hpp"
#include "exoid/ident/leg/regressor.hpp"

#include <Eigen/QR>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace exoid::experiments {
namespace {

using exoid::test::runExoid;

using exoid::test::slurp;

TEST(Reproduce, ShortProtocolWritesEveryTableAndFigure) {
  const std::string dir = ::testing::TempDir() + "/exoid_reproduce_short";
  std::filesystem::remove_all(dir);
  testing::internal::CaptureStdout();
  ASSERT_EQ(runExoid({"reproduce", "--out", dir, "--duration", "2", "--pso-iterations", "100"}), 0);
  testing::internal::GetCapturedStdout();
  for (const char* f : {"report.md", "results.json", "estimates.csv", "validation.csv", "series_validation_knee.csv",
                        "series_validation_hip.csv", "series_convergence.csv", "fig_validation_knee.png",
                        "fig_validation_hip.png", "fig_convergence.png", "fig_validation_errors.png",
                        "fig_parameter_errors.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
    EXPECT_GT(std::filesystem::file_size(dir + "/" + f), 100u) << f;
  }
  const std::string md = slurp(dir + "/report.md");
  for (const char* section : {"## Verdict", "## Knee parameters", "## Hip parameters", "## Is the truth inside the RLS box?",
                              "## Validation torque error", "## Scores against ground truth",
                              "## Errors in units of each method's Cramer-Rao bound", "![knee validation]",
                              "## Optimised excitation arm",
                              "paper: LS (Table 4)", "truth: best fit", ", MuJoCo 2.2.", ", Eigen 3.",
                              "Paper's validation error on trajectory 2", "Paper's validation error on trajectory 4",
                              "Table 6 (its LS, PSO and RLS-PSO estimates of X(1:5)) is printed as an image",
                              "processed torque the methods fit"}) {
    EXPECT_NE(md.find(section), std::string::npos) << section;
  }
  // What a new user tripped on: no absolute paths in the report, no "-0.00" read as a sign.
  EXPECT_EQ(md.find(::testing::TempDir()), std::string::npos);
  EXPECT_EQ(md.find("/usr/"), std::string::npos);
  EXPECT_EQ(md.find("/build/"), std::string::npos);
  EXPECT_NE(md.find("(`apal_leg.xml`)"), std::string::npos);
  EXPECT_EQ(md.find("-0.00 "), std::string::npos);
  EXPECT_EQ(fixed(-0.001, 2), "0.00");
  EXPECT_EQ(fixed(-0.006, 2), "-0.01");
  const nlohmann::json j = nlohmann::json::parse(slurp(dir + "/results.json"));
  EXPECT_EQ(j["methods"].size(), allVariants().size());
  EXPECT_TRUE(j["tool"].contains("revision"));
  EXPECT_EQ(j["seed"], 1);
  // The rigid truth is the model's set-B links (paper.md), independent of the run.
  EXPECT_NEAR(j["truth"]["rigid"]["parameters"]["Mxt"].get<double>(), 5.83, 1e-9);
  // The optimised-excitation arm: the same seed and methods, the same rigid truth, its own best fit.
  const auto& arm = j["optimised_excitation_arm"];
  EXPECT_EQ(arm["seed"], 1);
  EXPECT_EQ(arm["methods"].size(), allVariants().size());
  EXPECT_EQ(arm["truth"]["rigid"], j["truth"]["rigid"]);
  EXPECT_NE(arm["truth"]["best_fit"], j["truth"]["best_fit"]);
  EXPECT_TRUE(std::filesystem::exists(dir + "/estimates_optimised.csv"));
}

TEST(Reproduce, TheVerdictJudgesEachJointByItsStatedRuleAndFlagsBounds) {
  // The review read "Lowest validation torque error: ls" while RLS-PSO's knee error was half of
  // LS's: the old verdict summed the joints without saying so. Each joint now gets its line,
  // decided by that joint's torque-space error, and every estimate on its box's bound is named.
  ProtocolConfig c = defaultReproduceConfig();
  c.sim.duration_s = 2.0;
  c.methods.rls_pso.pso.max_iterations = 100;
  c.variants = {Variant::kLs, Variant::kPso, Variant::kRlsPso};
  const ProtocolResult r = runProtocol(c);
  const std::string v = verdict(r);
  EXPECT_NE(v.find("Rule, per joint"), std::string::npos) << v;
  EXPECT_NE(v.find("Joints are not summed"), std::string::npos) << v;
  const VariantScore& ls = r.scores[0];
  const VariantScore& rp = r.scores[2];
  ASSERT_EQ(rp.variant, Variant::kRlsPso);
  const std::pair<const char*, bool> joints[] = {
      {"knee", rp.torque_space_vs_best_fit.knee < ls.torque_space_vs_best_fit.knee},
      {"hip", rp.torque_space_vs_best_fit.hip < ls.torque_space_vs_best_fit.hip}};
  for (const auto& [joint, rls_pso_closer] : joints) {
    const std::size_t at = v.find(std::string("- **") + joint + "**");
    ASSERT_NE(at, std::string::npos) << joint << "\n" << v;
    const std::string line = v.substr(at, v.find('\n', at) - at);
    const std::string claim = std::string("The paper's claim on the ") + joint + ": " + (rls_pso_closer ? "holds" : "does not hold") +
                              " against the truth";
    EXPECT_NE(line.find(claim), std::string::npos) << line;
  }
  for (const VariantScore& s : r.scores) {
    for (const BoundHit& h : boxBoundHits(s.outcome)) {
      EXPECT_NE(v.find(std::string(ident::paramName(h.param)) + " = " + fmt(h.value, 4)), std::string::npos)
          << toString(s.variant) << " " << describe(h) << "\n" << v;
    }
  }
}

// The 'default' arm is identify's default (--knee-data --both-data, no options): its segmental LS
// moved to the nearest physically consistent estimate in its reported errors' metric. Short, noisy
// records (3 s, 5 N m, 0.05 deg) put LS just outside the bounds on most seeds; the arm then returns
// a consistent estimate, not LS's, and counts as plausible when the move is within 2 reported errors.
TEST(Reproduce, TheDefaultArmIsIdentifysDefaultWithItsConsistency) {
  ProtocolConfig c = defaultReproduceConfig();
  c.sim.duration_s = 3.0;
  c.sim.sensors.noise_tau_Nm = 5.0;
  c.sim.sensors.noise_q_deg = 0.05;
  c.variants = {Variant::kDefault};
  int constrained = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    c.seed = seed;
    const ProtocolResult r = runProtocol(c);
    const MethodOutcome& m = r.scores.front().outcome;
    ASSERT_TRUE(m.consistency.has_value()) << "seed " << seed;
    // Plausibility is judged as identify judges it: only violations beyond 2 reported errors count.
    EXPECT_EQ(m.implausible, m.consistency->significant()) << "seed " << seed;
    if (!m.consistency->fit.constrained) continue;
    ++constrained;
    EXPECT_FALSE(Eigen::VectorXd(m.x) == m.consistency->unconstrained) << "seed " << seed;
    EXPECT_TRUE(ident::ConsistencyConditions(r.truths.lt_m).satisfied(Eigen::VectorXd(m.x))) << "seed " << seed;
  }
  EXPECT_GT(constrained, 0);
}

TEST(Reproduce, SameSeedSameNumbersDifferentSeedDiffers) {
  ProtocolConfig c = defaultReproduceConfig();
  c.sim.duration_s = 1.5;
  c.methods.rls_pso.pso.max_iterations = 50;
  c.variants = {Variant::kLs, Variant::kRlsPso};
  const ProtocolResult a = runProtocol(c), b = runProtocol(c);
  ASSERT_EQ(a.scores.size(), 2u);
  for (std::size_t k = 0; k < a.scores.size(); ++k) EXPECT_TRUE(a.scores[k].outcome.x == b.scores[k].outcome.x);
  c.seed = 2;
  const ProtocolResult d = runProtocol(c);
  EXPECT_FALSE(a.scores[0].outcome.x == d.scores[0].outcome.x);
}

TEST(Reproduce, NoiseFreeRigidLegWithExactDerivativesRecoversTheTruth) {
  // No noise, no vibration, no four-bar mass, an ideal torque sensor, exact derivative columns. The simulator's Coulomb
  // term is fc tanh(qd / v0) where the 2-link model has fc sgn(qd), so LS returns the rigid
  // truth plus the LS image of that difference, which the test computes independently:
  // knee stage shift dk = H_k \ (fc2 (tanh - sgn)(qd2)); hip stage shift dh =
  // H_h \ (fc1 (tanh - sgn)(qd1) - H_hk dk). Everything else is exact: roundoff amplified by
  // the condition numbers (~300) leaves ~1e-12; 1e-8 relative is the bound.
  ProtocolConfig c;
  c.sim.duration_s = 4.0;
  c.sim.variant.cylinder_mass_scale = 0.0;
  c.sim.sensors.tau_bandwidth_Hz = 0.0;  // an ideal torque sensor: its anti-aliasing delay is a measurement error
  c.variants = {Variant::kLsExact};
  const ProtocolResult r = runProtocol(c);
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  const double v0 = r.records[0].sim.truth.coulomb_v0_radps;
  auto mismatch = [&](const ident::JointSignals& s, int joint, double fc) {
    return Eigen::VectorXd(s.qd_radps.col(joint).unaryExpr([&](double v) { return fc * (std::tanh(v / v0) - ident::sgn(v)); }));
  };
  const ident::JointSignals& s1 = r.records[0].exact_q;
  const ident::JointSignals& s3 = r.records[2].exact_q;
  const Eigen::MatrixXd Hk = ident::jointRegressor(s1, ident::Joint::kKnee, lc).middleCols(5, 5);
  const Eigen::VectorXd dk = Hk.colPivHouseholderQr().solve(mismatch(s1, 1, r.truths.rigid[ident::kFc2]));
  const Eigen::MatrixXd Hh = ident::jointRegressor(s3, ident::Joint::kHip, lc);
  const Eigen::VectorXd dh = Hh.leftCols(5).colPivHouseholderQr().solve(mismatch(s3, 0, r.truths.rigid[ident::kFc1]) - Hh.middleCols(5, 5) * dk);
  ident::ParamVector expected = r.truths.rigid;
  expected.head<5>() += dh;
  expected.tail<5>() += dk;
  const ident::ParamVector& x = r.scores[0].outcome.x;
  for (int i = 0; i < ident::kNumParams; ++i) {
    EXPECT_NEAR(x[i], expected[i], 1e-8 * std::abs(expected[i])) << ident::paramName(i);
  }
  // The best-fit truth is this very fit (ideal = motor torque on the rigid leg).
  EXPECT_LT(r.scores[0].vs_best_fit.norm_rel, 1e-8);
}

TEST(Reproduce, IdentifiabilityReportsTheSameBoundAsTheProtocol) {
  // The knee stage of the segmental strategy fits record 1's knee equation after the paper's
  // processing: `exoid identifiability` on that record (with the paper's processing named) must
  // report the same noise-limited std for Mxs..fv2 as the protocol (the same computation on the
  // same rows: agreement to rounding, 1e-9 relative). The paper processing is named: identifiability
  // defaults to the parallel one.
  ProtocolConfig c;
  c.sim.duration_s = 3.0;
  c.sim.sensors.noise_tau_Nm = 0.5;
  c.variants = {Variant::kLs};
  const ProtocolResult r = runProtocol(c);
  const std::string dir = ::testing::TempDir();
  const std::string csv = dir + "/exoid_crb_record1.csv", json = dir + "/exoid_crb_record1.json";
  ident::writeDatasetCsv(r.records[0].data, csv);
  ASSERT_EQ(runExoid({"identifiability", "--data", csv, "--noise-tau", "0.5", "--processing", "paper", "--diff", "forward",
                      "--json", json}),
            0);
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  const nlohmann::json& knee = j["blocks"][2];
  ASSERT_EQ(knee["block"], "knee equation, params 6-10");
  for (int i = ident::kShankFirst; i < ident::kNumParams; ++i) {
    const std::string name(ident::paramName(i));
    EXPECT_NEAR(knee["crb_std"][name].get<double>(), r.scores[0].crb_std[i], 1e-9 * r.scores[0].crb_std[i]) << name;
  }
}

TEST(Reproduce, NoiseStdMatchesMonteCarloOnSimulatedRecords) {
  // The bound the sweep reports for the paper's arm, checked where the review found it wrong: on
  // the simulator's own records. Fixed exact states (no angle noise), 240 seeds of white torque
  // noise on records 1 and 3, the real processing and the real segmental LS. (n-1) s^2 / sigma^2
  // is chi-square(n-1); the band holds with probability 1 - 1e-4 per parameter (z = 3.89,
  // Wilson-Hilferty), 1e-3 over the 10.
  ProtocolConfig c;
  c.sim.duration_s = 3.0;
  c.variants = {Variant::kLs};
  const ProtocolResult r = runProtocol(c);
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  const double sigma = 0.5;
  const Eigen::VectorXd predicted = noiseStd(Variant::kLs, r.records, c.signals, sigma);
  std::mt19937_64 gen(8);
  std::normal_distribution<double> noise(0.0, sigma);
  ident::MethodOptions mo;
  mo.report_optimality_gap = false;
  const int n = 240;
  Eigen::MatrixXd draws(ident::kNumParams, n);
  for (int k = 0; k < n; ++k) {
    ident::Dataset d1 = r.records[0].data, d3 = r.records[2].data;
    d1.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d1.size(), 2, [&] { return noise(gen); });
    d3.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d3.size(), 2, [&] { return noise(gen); });
    const ident::Robot leg = ident::twoLinkLeg(lc);
    draws.col(k) = identifySegmented(leg, ident::Method::kLs, ident::recordRows(leg, ident::prepareSignals(d1, c.signals)),
                                     ident::recordRows(leg, ident::prepareSignals(d3, c.signals)), mo).x;
  }
  const double z = 3.89, dof = n - 1.0, v = 2.0 / (9.0 * dof);
  const auto chi2 = [&](double zz) { return dof * std::pow(1.0 - v + zz * std::sqrt(v), 3) / dof; };
  const double lo = std::sqrt(chi2(-z)), hi = std::sqrt(chi2(z));
  const Eigen::VectorXd mean = draws.rowwise().mean();
  for (int i = 0; i < ident::kNumParams; ++i) {
    const double sd = std::sqrt((draws.row(i).array() - mean[i]).square().sum() / dof);
    EXPECT_GT(sd / predicted[i], lo) << ident::paramName(i) << ": " << sd << " vs " << predicted[i];
    EXPECT_LT(sd / predicted[i], hi) << ident::paramName(i) << ": " << sd << " vs " << predicted[i];
  }
}

TEST(Reproduce, BadOptionsFailBeforeWork) {
  testing::internal::CaptureStderr();
  EXPECT_NE(runExoid({"reproduce", "--methods", "magic", "--out", ::testing::TempDir() + "/x"}), 0);
  EXPECT_NE(runExoid({"reproduce", "--noise-tau", "-1"}), 0);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("magic"), std::string::npos) << err;
}

}  // namespace
}  // namespace exoid::experiments
