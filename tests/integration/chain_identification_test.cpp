// A chain other than the APAL leg, end to end through the library: the serial-chain simulator
// (sim) records the built-in hip-knee-ankle leg, ident processes the record and fits its base
// parameters, against the truth read from the model (experiments' bridge). Two yardsticks: exact
// data give the truth exactly; torque-sensor noise alone gives errors distributed as the
// Cramer-Rao bound says (least squares is then the efficient, unbiased estimator).
#include "exoid/experiments/protocol/robot_loader.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/base_estimate.hpp"
#include "exoid/ident/signals/processing.hpp"
#include "exoid/sim/motor_rig.hpp"
#include "exoid/sim/model.hpp"
#include "exoid/sim/serial_chain.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace exoid;

ident::Dataset datasetOf(const sim::ChainSimResult& r, const ident::ChainModel& model) {
  ident::CsvReadOptions o;
  o.joints = model.jointNames();
  return ident::parseDatasetText(sim::tableCsv(r.table), "leg3 record", o);
}

struct Leg3 {
  sim::SerialChain chain = sim::serialChainFromFile(sim::modelPathFor("leg3"));
  ident::ChainModel model = experiments::chainModel(chain);
  Eigen::VectorXd phi = experiments::standardParameters(chain);
  ident::Robot robot = ident::chainRobot(model);
  const ident::BaseParameters& base = robot.basis;
  Eigen::VectorXd beta() const { return base.combination * phi; }
};

sim::ChainSimConfig exactConfig(double duration_s) {
  sim::ChainSimConfig c;
  c.model_path = sim::modelPathFor("leg3");
  c.duration_s = duration_s;
  c.coulomb_v0_radps = 0.0;  // the regressor's sgn(qd): exact rows
  c.record_derivatives = true;
  c.trajectory = sim::defaultChainTrajectory(sim::serialChainFromFile(c.model_path), 1);
  return c;
}

// Every base parameter within 1e-6 (relative to its own size, absolute for those that are 0)
// with identify's defaults: parallel processing, band chosen from the record. The rows are
// exact (filter(tau) = filter(W) phi for any linear filter), so what remains is rounding.
TEST(ChainIdentification, ExactSimulatedDataGiveEveryBaseParameterExactly) {
  const Leg3 leg;
  ASSERT_EQ(leg.base.rank, 17);
  const sim::ChainSimResult r = sim::simulateChain(exactConfig(20.0));
  ident::SignalOptions o;
  o.processing = ident::Processing::kParallel;
  o.cutoff_from_data = o.derivative_cutoff_from_data = true;
  std::optional<ident::BandChoice> band;
  const ident::RecordRows rec = ident::processRecord(datasetOf(r, leg.model), leg.robot, o, {}, &band);
  ASSERT_TRUE(band.has_value());
  const ident::ChainEstimate est = ident::estimateChain(leg.robot, rec, leg.phi);
  const Eigen::VectorXd truth = leg.beta();
  for (int i = 0; i < leg.base.rank; ++i) {
    EXPECT_NEAR(est.beta[i], truth[i], 1e-6 * std::max(1.0, std::abs(truth[i]))) << leg.base.names[static_cast<std::size_t>(i)];
  }
  ASSERT_TRUE(est.consistent.has_value());
  EXPECT_EQ(est.consistent->status, ident::ConsistentFitStatus::kLeastSquaresConsistent);
}

// The rig's vibration moves the chain's base: at level 1 the stand's mount (models/leg3.xml) sways
// under the leg's reactions, the record carries the base IMU, and a fit that ignores the base
// motion is no longer exact (its residual is the base motion's torque: at least 1e-6 N m RMS,
// and 1e4 x the exact fit's rounding). With
// the base-motion terms, in the base parameters of a moving base (the hip's rotor inertia then
// separates from the thigh's), exact data give every one of them to 1e-6 again. At level 0 the
// mount is removed: no base columns, the still base.
TEST(ChainIdentification, VibrationMovesTheBaseAndTheBaseTermsRecoverExactness) {
  const Leg3 leg;
  sim::ChainSimConfig c = exactConfig(20.0);
  c.vibration_level = 1.0;
  c.sensors.imu_acc_noise_mps2 = 0.0;
  c.sensors.imu_gyro_noise_radps = 0.0;
  const sim::ChainSimResult r = sim::simulateChain(c);
  const ident::Dataset d = datasetOf(r, leg.model);
  ASSERT_TRUE(ident::hasBaseColumns(d));
  EXPECT_GT(r.table.col("base_pitch").cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_GT(r.table.col("base_x").cwiseAbs().maxCoeff(), 1e-7);

  ident::SignalOptions o;
  o.processing = ident::Processing::kParallel;
  o.cutoff_from_data = o.derivative_cutoff_from_data = true;
  ident::BaseParameterOptions moving;
  moving.planar_base_motion = true;
  const ident::Robot robot = ident::chainRobot(leg.model, moving);
  EXPECT_EQ(robot.basis.rank, leg.base.rank + 1);
  o.base_terms = ident::BaseTerms::kOff;
  const ident::ChainEstimate still = ident::estimateChain(leg.robot, ident::processRecord(d, leg.robot, o), leg.phi);
  o.base_terms = ident::BaseTerms::kOn;
  const ident::ChainEstimate est = ident::estimateChain(robot, ident::processRecord(d, robot, o), leg.phi);
  EXPECT_GT(still.ls.residual_rms, 1e-6);
  EXPECT_GT(still.ls.residual_rms, 1e4 * est.ls.residual_rms);
  const Eigen::VectorXd truth = robot.basis.combination * leg.phi;
  for (int i = 0; i < robot.basis.rank; ++i) {
    EXPECT_NEAR(est.beta[i], truth[i], 1e-6 * std::max(1.0, std::abs(truth[i]))) << robot.basis.names[static_cast<std::size_t>(i)];
  }

  c.vibration_level = 0.0;
  c.duration_s = 1.0;
  EXPECT_FALSE(ident::hasBaseColumns(datasetOf(sim::simulateChain(c), leg.model)));
}

// Torque-sensor noise alone (sigma 0.3 N m, white), exact states (recorded derivatives), no
// filter: y = Wb beta + e with e white and independent of Wb, so LS is unbiased with covariance
// sigma^2 (Wb' Wb)^-1, the CRB. Over 50 seeds each base parameter's error, in units of its
// bound, has mean 0 and standard deviation 1 (the states, hence Wb, are the same for every seed:
// the controller does not read the torque sensor). Bands: 99 % jointly over the 17 parameters and
// the two statistics (Bonferroni, two-sided 0.01 / 34 each): |mean| <= 3.62 / sqrt(50); the
// sample standard deviation within [sqrt(20.92 / 49), sqrt(93.11 / 49)] (chi-square, 49 degrees
// of freedom, at 0.0147 % and 99.985 %).
TEST(ChainIdentification, TorqueNoiseGivesErrorsAsTheCramerRaoBoundSays) {
  const Leg3 leg;
  const Eigen::VectorXd truth = leg.beta();
  constexpr int kSeeds = 50;
  const double sigma = 0.3;
  Eigen::MatrixXd z(kSeeds, leg.base.rank);
  for (int s = 0; s < kSeeds; ++s) {
    sim::ChainSimConfig c = exactConfig(8.0);
    c.sensors.noise_tau_Nm = sigma;
    c.seed = static_cast<std::uint64_t>(100 + s);
    c.actuator_bandwidth_hz = 0.0;  // a staircase torque: one integration step per sample (the rows are exact either way)
    const sim::ChainSimResult r = sim::simulateChain(c);
    ident::SignalOptions o;
    o.processing = ident::Processing::kParallel;
    o.filter = false;
    o.edge_trim_s = 0.0;
    const ident::RecordRows rec = ident::processRecord(datasetOf(r, leg.model), leg.robot, o);
    const Eigen::MatrixXd& Wb = rec.W;
    const Eigen::MatrixXd crb = sigma * sigma * (Wb.transpose() * Wb).inverse();
    ident::ChainEstimateOptions eo;
    eo.consistent = false;
    const ident::ChainEstimate est = ident::estimateChain(leg.robot, rec, leg.phi, eo);
    z.row(s) = ((est.beta - truth).array() / crb.diagonal().array().sqrt()).transpose();
  }
  for (int i = 0; i < leg.base.rank; ++i) {
    const double mean = z.col(i).mean();
    const double sd = std::sqrt((z.col(i).array() - mean).square().sum() / (kSeeds - 1));
    const std::string& name = leg.base.names[static_cast<std::size_t>(i)];
    EXPECT_LE(std::abs(mean), 3.62 / std::sqrt(static_cast<double>(kSeeds))) << name;
    EXPECT_GE(sd, std::sqrt(20.92 / 49.0)) << name;
    EXPECT_LE(sd, std::sqrt(93.11 / 49.0)) << name;
  }
}

}  // namespace
