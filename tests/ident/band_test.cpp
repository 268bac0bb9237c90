// The band chosen from the record: as wide as the torque follows the states (exact data: the cap,
// and exact parameters), narrower where the angles carry motion the measured torque does not
// follow (errors-in-variables), and clear refusals where no band can be chosen.
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/processing.hpp"

#include "exoid/ident/estimators/least_squares.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace exoid::ident {
namespace {

SignalOptions identifyDefaults() {
  SignalOptions o;
  o.processing = Processing::kParallel;
  o.differentiation = Differentiation::kCentral4;
  o.cutoff_from_data = o.derivative_cutoff_from_data = true;
  return o;
}

const Robot& leg() {
  static const Robot robot = twoLinkLeg(LegConstants{});
  return robot;
}

ParamVector fit(const Dataset& d, const SignalOptions& o) {
  const RecordRows p = processRecord(d, leg(), o);
  return solveLeastSquares(p.W, p.y).x;
}

TEST(Band, ExactDataGetTheCapAndTheExactParameters) {
  // The two-frequency record (highest 1.9 Hz) from its angles alone: the torque follows the states
  // in every band, so the band is the cap, 5x the motion's, and LS recovers X.
  const Dataset d = test::multisineRecord(10.0, true, false);
  const BandChoice b = chooseBand(d, leg(), identifyDefaults());
  EXPECT_EQ(b.limited_by, "cap") << b.describe();
  EXPECT_GT(b.motion_bandwidth_hz, 1.3);
  EXPECT_LT(b.motion_bandwidth_hz, 2.5);
  EXPECT_NEAR(b.cutoff_hz, 5.0 * b.motion_bandwidth_hz, 1e-9);
  EXPECT_NEAR(b.derivative_cutoff_hz, 5.0 * b.cutoff_hz, 1e-9);
  const ParamVector truth = toParamVector(defaultLeg());
  const ParamVector x = fit(d, withBand(identifyDefaults(), b));
  // From angles alone: five-point differences and the pre-filter's (1/5)^8 leave 1e-6 relative
  // (parallel_processing_test), the same promise as the fixed band's.
  for (int i = 0; i < kNumParams; ++i) EXPECT_NEAR(x[i], truth[i], 1e-6 * std::abs(truth[i])) << paramName(i);
  // processRecord makes the same choice itself when the options leave it to the data.
  EXPECT_EQ(fit(d, identifyDefaults()), x);
}

TEST(Band, AngleMotionTheTorqueDoesNotFollowStopsTheBand) {
  // A 5.5 Hz, 0.2 mrad wobble on both encoders that the torque does not contain (a motor-side
  // encoder in a gear's backlash, say): differentiated twice it is 0.24 rad/s^2, foreign to the
  // torque. The band must stop below it, and LS there is closer to the truth than in a band that
  // lets it in.
  Dataset d = test::multisineRecord(10.0, true, false);
  for (Eigen::Index i = 0; i < d.size(); ++i) d.q_rad.row(i).array() += 2e-4 * std::sin(2 * M_PI * 5.5 * d.t_s[i]);
  const BandChoice b = chooseBand(d, leg(), identifyDefaults());
  EXPECT_EQ(b.limited_by, "consistency") << b.describe();
  EXPECT_LT(b.cutoff_hz, 5.5) << b.describe();
  EXPECT_NE(b.describe().find("errors-in-variables"), std::string::npos);
  const ParamVector truth = toParamVector(defaultLeg());
  SignalOptions wide = identifyDefaults();
  wide.cutoff_from_data = false;
  wide.cutoff_hz = 5.0 * b.motion_bandwidth_hz;
  const ParamVector chosen = fit(d, withBand(identifyDefaults(), b)), wider = fit(d, wide);
  EXPECT_LT((chosen - truth).cwiseQuotient(truth).cwiseAbs().maxCoeff(), (wider - truth).cwiseQuotient(truth).cwiseAbs().maxCoeff());
}

TEST(Band, ALongRecordsPilotReadsItsCentralWindowAndChoosesTheSameBand) {
  // A 300 s record with the 5.5 Hz wobble: the pilot and the scan read its central 131 s (the
  // rule's default window), and the band is the one the whole record's pilot gives; the motion's
  // bandwidth is still the whole record's, and a record shorter than the window is read whole.
  Dataset d = test::multisineRecord(300.0, true, false);
  for (Eigen::Index i = 0; i < d.size(); ++i) d.q_rad.row(i).array() += 2e-4 * std::sin(2 * M_PI * 5.5 * d.t_s[i]);
  const BandChoice windowed = chooseBand(d, leg(), identifyDefaults());
  BandRule whole_rule;
  whole_rule.pilot_max_samples = 0;
  const BandChoice whole = chooseBand(d, leg(), identifyDefaults(), whole_rule);
  EXPECT_EQ(windowed.samples, d.size());
  EXPECT_EQ(windowed.pilot_samples, BandRule{}.pilot_max_samples);
  EXPECT_EQ(whole.pilot_samples, d.size());
  EXPECT_NE(windowed.describe().find("central 131072 of 300000 samples"), std::string::npos) << windowed.describe();
  EXPECT_EQ(windowed.motion_bandwidth_hz, whole.motion_bandwidth_hz);
  EXPECT_EQ(windowed.limited_by, whole.limited_by);
  EXPECT_EQ(windowed.cutoff_hz, whole.cutoff_hz) << windowed.describe() << "\n" << whole.describe();
  const Dataset short_record = test::multisineRecord(10.0, true, false);
  EXPECT_EQ(chooseBand(short_record, leg(), identifyDefaults()).pilot_samples, short_record.size());
}

TEST(Band, AJointHeldStillDoesNotSetTheMotionsBandwidth) {
  // Knee alone (the hip held at -0.4 rad, plus encoder-level noise that spreads its spectrum to
  // Nyquist): the motion's bandwidth is the knee's, and the knee-only scan ignores the hip torque.
  Dataset d = test::multisineRecord(10.0, false, false);
  for (Eigen::Index i = 0; i < d.size(); ++i) d.q_rad(i, 0) += 1e-7 * std::sin(2 * M_PI * 321.0 * d.t_s[i]);
  BandRule knee;
  knee.first_moving_joint = 1;
  const BandChoice b = chooseBand(d, leg(), identifyDefaults(), knee);
  EXPECT_LT(b.motion_bandwidth_hz, 2.5) << b.describe();
  EXPECT_GT(b.joint_motion_bandwidth_hz[0], 100.0);
}

TEST(Band, AGivenDerivativeCutoffIsKeptAndAnUnfilteredRecordHasNoBandToChoose) {
  const Dataset d = test::multisineRecord(10.0, true, false);
  SignalOptions o = identifyDefaults();
  o.filter = false;                       // --no-filter
  o.derivative_cutoff_from_data = false;  // --derivative-cutoff-hz 30
  o.derivative_cutoff_hz = 30.0;
  const SignalOptions r = resolveSignalOptions(d, leg(), o);
  EXPECT_EQ(r.derivative_cutoff_hz, 30.0);
  EXPECT_FALSE(r.cutoff_from_data);
  // A given cutoff with the derivative pre-filter left to the data: 5x it.
  SignalOptions g = identifyDefaults();
  g.cutoff_from_data = false;
  g.cutoff_hz = 4.0;
  EXPECT_EQ(resolveSignalOptions(d, leg(), g).derivative_cutoff_hz, 20.0);
}

TEST(Band, RefusalsSayWhy) {
  Dataset slow = test::multisineRecord(10.0);
  slow.t_s *= 1000.0;  // milliseconds read as seconds: 1 Hz sampling
  test::expectInvalidArgumentMentioning([&] { chooseBand(slow, leg(), identifyDefaults()); }, "--time-unit ms");
  const Dataset shortRecord = test::multisineRecord(0.05);
  test::expectInvalidArgumentMentioning([&] { chooseBand(shortRecord, leg(), identifyDefaults()); }, "give --cutoff-hz");
  BandRule bad;
  bad.inconsistency_ratio = 1.0;
  test::expectInvalidArgumentMentioning([&] { chooseBand(test::multisineRecord(10.0), leg(), identifyDefaults(), bad); },
                                        "'inconsistency_ratio' must be > 1");
}

}  // namespace
}  // namespace exoid::ident
