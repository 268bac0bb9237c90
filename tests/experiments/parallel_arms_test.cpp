// The protocol's parallel-processing arms (ls-parallel, idim-iv) against the simulator's truth:
// exact on noise-free records of the rigid leg, and on noisy records scattered as the bound says.
#include "exoid/experiments/protocol/controller_io.hpp"
#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/experiments/protocol/protocol.hpp"
#include "exoid/ident/estimators/noise_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace exoid::experiments {
namespace {

// The rigid 2-link leg the regressor describes exactly: no cylinder mass, a welded pedestal, no
// Coulomb friction (the simulator's is fc tanh(qd / v0), the model's fc sgn(qd)), an ideal
// torque sensor (its anti-aliasing filter delays the torque against the motion).
ProtocolConfig rigidLeg(double duration_s) {
  ProtocolConfig c;
  c.sim.duration_s = duration_s;
  c.sim.variant.cylinder_mass_scale = 0.0;
  c.sim.variant.vibration_level = 0.0;
  c.sim.variant.fc_hip_Nm = 0.0;
  c.sim.variant.fc_knee_Nm = 0.0;
  c.sim.sensors.tau_bandwidth_Hz = 0.0;
  c.variants = {Variant::kLsParallel, Variant::kIdimIv};
  return c;
}

// The record with the simulator's own velocities and accelerations as recorded derivative columns.
ident::Dataset withRecordedDerivatives(const ident::Dataset& in) {
  ident::Dataset d = in;
  Eigen::MatrixX2d qd(d.size(), 2), qdd(d.size(), 2);
  qd << d.extraColumn("qd_hip_true"), d.extraColumn("qd_knee_true");
  qdd << d.extraColumn("qdd_hip_true"), d.extraColumn("qdd_knee_true");
  d.qd_radps = qd;
  d.qdd_radps2 = qdd;
  return d;
}

TEST(ParallelArms, ExactOnNoiseFreeSimulatorRecordsWithTheirDerivatives) {
  // tau = Y(q, qd, qdd) x holds at every sample of the simulator's state (MuJoCo's inverse
  // dynamics is the regressor's: RegressorVsMujoco), and the parallel filter keeps it: both arms
  // must return the rigid truth to rounding times conditioning (~1e3), 1e-6 relative promised.
  // Angles alone do not allow this on simulated records (measured: up to 1e-2 relative, friction
  // and Coriolis terms): the controller's sample-and-hold torque makes the acceleration jump at
  // every sample, and difference formulas of the sampled angles average across the jumps.
  ProtocolConfig c = rigidLeg(6.0);
  ProtocolResult r = runProtocol(c);
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  const ident::Robot leg = ident::twoLinkLeg(lc);
  for (Record& rec : r.records) rec.closed_loop.measured = ident::processRecord(withRecordedDerivatives(rec.data), leg, parallelSignals(c.signals));
  const ident::ParamVector& truth = r.truths.rigid;
  ident::MethodOptions mo;
  mo.report_optimality_gap = false;
  const MethodOutcome ls = identifySegmented(leg, ident::Method::kLs, r.records[0].closed_loop.measured, r.records[2].closed_loop.measured, mo);
  const MethodOutcome iv = identifySegmentedIdimIv(leg, r.records[0].closed_loop, r.records[2].closed_loop, c.iv);
  for (const MethodOutcome* m : {&ls, &iv}) {
    ASSERT_TRUE(m->usable()) << m->problems();
    for (int i = 0; i < ident::kNumParams; ++i) {
      if (i == ident::kFc1 || i == ident::kFc2) {
        // Zero in the truth: relative to the torque it would explain, fc vs fv |qd|max ~ 3 rad/s.
        EXPECT_LT(std::abs(m->x[i]), 1e-6 * 3.0 * truth[i + 1]) << ident::paramName(i);
      } else {
        EXPECT_NEAR(m->x[i], truth[i], 1e-6 * std::abs(truth[i])) << ident::toString(m->method) << " " << ident::paramName(i);
      }
    }
  }
  EXPECT_LE(iv.stages[0].estimate.summary.iterations, 2);
}

// Mean and spread of z = (x - x0) / sigma over the seeds (columns).
struct ZStats {
  Eigen::VectorXd mean, sd;
};
ZStats zStats(const Eigen::MatrixXd& z) {
  const double n = static_cast<double>(z.cols());
  ZStats s{z.rowwise().mean(), Eigen::VectorXd(z.rows())};
  for (Eigen::Index i = 0; i < z.rows(); ++i) s.sd[i] = std::sqrt((z.row(i).array() - s.mean[i]).square().sum() / (n - 1));
  return s;
}

constexpr int kSeeds = 50;
constexpr double kZ99 = 2.576;  // two-sided 99 % point of the normal
// The two-sided 99 % band of a sample std over its true value for n draws: sqrt(chi2_{n-1} / (n-1))
// at the 0.5 % and 99.5 % points (Wilson-Hilferty).
double sdBand(int n, double z) {
  const double v = 2.0 / (9.0 * (n - 1));
  return std::sqrt(std::pow(1.0 - v + z * std::sqrt(v), 3));
}

TEST(ParallelArms, DefaultProcessingIsUnbiasedAndAsPreciseAsItsBoundUnderTorqueNoise) {
  // exoid identify's default (parallel processing, LS) on 200 seeds of white torque-sensor noise
  // (0.5 N m) added to the records of the rigid leg: every parameter's mean error from the
  // noise-free estimate lies within the 99 % band of a mean, and its spread within chi-square's
  // 99 % band around the bound the protocol reports (noiseStd). Measured: sd / bound 1.00-1.02 over
  // 400 seeds (0.80-0.86 over the first 50: the band of 50 seeds is 0.75-1.26).
  ProtocolConfig c = rigidLeg(4.0);
  c.variants = {Variant::kLsParallel};
  const ProtocolResult r = runProtocol(c);
  const ident::LegConstants lc{r.truths.lt_m, r.truths.g_mps2};
  const ident::ParamVector x0 = r.scores[0].outcome.x;
  const double sigma = 0.5;
  const Eigen::VectorXd bound = noiseStd(Variant::kLsParallel, r.records, c.signals, sigma);
  const int seeds = 200;  // cheap (no simulation per seed): a sharper band than the required 50
  std::mt19937_64 gen(20261201);
  std::normal_distribution<double> noise(0.0, sigma);
  ident::MethodOptions mo;
  mo.report_optimality_gap = false;
  Eigen::MatrixXd z(ident::kNumParams, seeds);
  for (int k = 0; k < seeds; ++k) {
    ident::Dataset d1 = r.records[0].data, d3 = r.records[2].data;
    d1.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d1.size(), 2, [&] { return noise(gen); });
    d3.tau_Nm += Eigen::MatrixX2d::NullaryExpr(d3.size(), 2, [&] { return noise(gen); });
    const ident::SignalOptions o = parallelSignals(c.signals);
    const ident::Robot leg = ident::twoLinkLeg(lc);
    const MethodOutcome m = identifySegmented(leg, ident::Method::kLs, ident::processRecord(d1, leg, o), ident::processRecord(d3, leg, o), mo);
    z.col(k) = (m.x - x0).cwiseQuotient(bound);
  }
  const ZStats s = zStats(z);
  std::printf("[ info ] sd / bound: min %.3f max %.3f; |mean z| max %.3f\n", s.sd.minCoeff(), s.sd.maxCoeff(), s.mean.cwiseAbs().maxCoeff());
  for (int i = 0; i < ident::kNumParams; ++i) {
    EXPECT_LT(std::abs(s.mean[i]), kZ99 * s.sd[i] / std::sqrt(double(seeds))) << ident::paramName(i) << " mean z " << s.mean[i];
    EXPECT_GT(s.sd[i], sdBand(seeds, -kZ99)) << ident::paramName(i);
    EXPECT_LT(s.sd[i], sdBand(seeds, kZ99)) << ident::paramName(i);
  }
}

TEST(ParallelArms, IdimIvRemovesTheBiasEncoderNoiseGivesLeastSquaresInClosedLoop) {
  // The simulator's encoder noise (0.005 deg + 0.00275 deg quantisation) enters the regressor
  // AND, through the PID, the torque: the two are correlated and LS is biased (measured: -1.7
  // sigma on every inertial parameter over these 50 seeds). IDIM-IV's instruments come from
  // noise-free closed-loop simulations: its mean error must lie within the 99 % band of a mean of
  // 50. Its spread exceeds the torque-noise bound (the controller's reaction to encoder noise is
  // extra torque the bound leaves out, and IV is less efficient than LS): measured 1.1-1.5.
  //
  // The same records answer for exoid identify's defaults (Variant::kDefault, the band chosen from
  // each record): the band keeps the errors-in-variables bias below the bound, |mean z| < 1 on
  // every parameter, where LS in the fixed 10 Hz band is off by more than its band of a mean.
  ProtocolConfig quiet = rigidLeg(4.0);
  quiet.variants = {Variant::kLsParallel, Variant::kIdimIv, Variant::kDefault};
  const ProtocolResult ref = runProtocol(quiet);
  Eigen::MatrixXd z_ls(ident::kNumParams, kSeeds), z_iv(ident::kNumParams, kSeeds), z_def(ident::kNumParams, kSeeds);
  for (int k = 0; k < kSeeds; ++k) {
    ProtocolConfig c = quiet;
    c.seed = 1000 + static_cast<std::uint64_t>(k);
    c.sim.sensors.noise_q_deg = 0.005;
    c.sim.sensors.quantisation_deg = 0.00274658;
    c.sim.sensors.noise_tau_Nm = 0.5;
    const ProtocolResult r = runProtocol(c);
    z_ls.col(k) = (r.scores[0].outcome.x - ref.scores[0].outcome.x).cwiseQuotient(r.scores[0].crb_std);
    z_iv.col(k) = (r.scores[1].outcome.x - ref.scores[1].outcome.x).cwiseQuotient(r.scores[1].crb_std);
    z_def.col(k) = (r.scores[2].outcome.x - ref.scores[2].outcome.x).cwiseQuotient(r.scores[2].crb_std);
    for (const Stage& st : r.scores[1].outcome.stages) EXPECT_LE(st.estimate.summary.iterations, 5) << st.name;
  }
  const ZStats ls = zStats(z_ls), iv = zStats(z_iv);
  std::printf("[ info ] LS mean z %.2f..%.2f; IDIM-IV |mean z| max %.3f, sd %.2f..%.2f\n", ls.mean.minCoeff(), ls.mean.maxCoeff(),
              iv.mean.cwiseAbs().maxCoeff(), iv.sd.minCoeff(), iv.sd.maxCoeff());
  for (int i = 0; i < ident::kNumParams; ++i) {
    EXPECT_LT(std::abs(iv.mean[i]), kZ99 * iv.sd[i] / std::sqrt(double(kSeeds))) << ident::paramName(i) << " mean z " << iv.mean[i];
    EXPECT_LT(iv.sd[i], 2.0) << ident::paramName(i);
  }
  const ZStats def = zStats(z_def);
  std::printf("[ info ] default (band from the record) mean z %.2f..%.2f, sd %.2f..%.2f\n", def.mean.minCoeff(), def.mean.maxCoeff(),
              def.sd.minCoeff(), def.sd.maxCoeff());
  for (int i = 0; i < ident::kNumParams; ++i) EXPECT_LT(std::abs(def.mean[i]), 1.0) << ident::paramName(i) << " mean z " << def.mean[i];
  // The finding IV answers: LS's knee inertial parameters are off by more than their band.
  for (int i : {ident::kMxs, ident::kMys, ident::kJs}) {
    EXPECT_GT(std::abs(ls.mean[i]), kZ99 * ls.sd[i] / std::sqrt(double(kSeeds))) << ident::paramName(i);
  }
}

TEST(ParallelArms, SimulatedRecordsCarryTheirControllerForIdimIv) {
  // What exoid simulate writes is what the protocol uses: the metadata rebuild the same law.
  ProtocolConfig c = rigidLeg(1.0);
  c.variants = {Variant::kLsParallel};
  const ProtocolResult r = runProtocol(c);
  for (int k : {0, 2}) {
    const ident::Controller m = controllerFromMetadata(r.records[static_cast<std::size_t>(k)].data, "record");
    const ident::Controller& p = r.records[static_cast<std::size_t>(k)].closed_loop.controller;
    EXPECT_EQ(m.kp_Nm_per_rad, p.kp_Nm_per_rad);
    EXPECT_EQ(m.ki_Nm_per_rad_s, p.ki_Nm_per_rad_s);
    EXPECT_EQ(m.kd_Nms_per_rad, p.kd_Nms_per_rad);
    EXPECT_EQ(m.derivative_cutoff_hz, p.derivative_cutoff_hz);
    EXPECT_EQ(m.integral_limit_Nm, p.integral_limit_Nm);
    EXPECT_EQ(m.derivative, ident::DerivativeSource::kErrorDifference);
    EXPECT_EQ(m.feedforward, ident::Feedforward::kModel);
    EXPECT_EQ(m.isLocked(0), k == 0);  // trajectory 1 holds the hip, 3 swings it
    EXPECT_EQ(p.isLocked(0), k == 0);
  }
}

}  // namespace
}  // namespace exoid::experiments

namespace exoid::experiments {
namespace {

TEST(DesignedExcitation, ReplacesTheIdentificationRecordsOnly) {
  ident::ExcitationOptions o;
  o.restarts = 1;
  o.max_evaluations = 300;
  const ident::LegConstants lc{0.45, 9.81};
  const ident::ParamVector nominal = ident::toParamVector(ident::defaultLeg());
  ProtocolConfig c = rigidLeg(3.0);
  c.variants = {Variant::kLs};
  const ident::Robot leg = ident::twoLinkLeg(lc);
  c.both_excitation = ident::designExcitation(o, leg, nominal, ident::ExcitationLimits::twoLinkLeg()).trajectory;
  o.locked_joints = 1;
  o.locked_at_rad = Eigen::VectorXd::Constant(1, -10.0 * M_PI / 180.0);
  c.knee_excitation = ident::designExcitation(o, leg, nominal, ident::ExcitationLimits::twoLinkLeg()).trajectory;
  const ProtocolResult r = runProtocol(c);
  EXPECT_EQ(r.records[0].data.metadata("trajectory").value_or(""), "fourier");
  EXPECT_EQ(r.records[0].data.metadata("hip_locked").value_or(""), "true");
  EXPECT_EQ(r.records[2].data.metadata("trajectory").value_or(""), "fourier");
  EXPECT_EQ(r.records[1].data.metadata("trajectory").value_or(""), "2");  // validation stays the paper's
  EXPECT_EQ(r.records[3].data.metadata("trajectory").value_or(""), "4");
  ASSERT_TRUE(r.scores[0].outcome.usable()) << r.scores[0].outcome.problems();
  // A knee excitation that moves the hip is refused before any work.
  ProtocolConfig bad = c;
  bad.knee_excitation = c.both_excitation;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::experiments
