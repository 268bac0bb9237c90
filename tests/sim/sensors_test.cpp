#include "exoid/sim/sensors.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace exoid::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kN = 20000;  // samples per statistic
constexpr double kDt = 1e-3;  // s, the simulator's sample interval
// 5-sigma bounds: a correct implementation fails with probability ~6e-7 per check; the seeds
// are fixed, so the tests are deterministic anyway.
constexpr double kSigmas = 5.0;

// The generator itself is tested in tests/core/random_test.cpp; here, the simulator's streams.
TEST(RandomStreams, EachNoiseSourceHasItsOwnStream) {
  EXPECT_NE(streamSeed(7, kStreamEncoder), streamSeed(7, kStreamTorque));
  EXPECT_NE(streamSeed(7, kStreamFloor), streamSeed(7, kStreamImu));
  EXPECT_EQ(streamSeed(7, kStreamEncoder), core::deriveSeed(7, 1));
}

TEST(SensorsTest, QuantisationOnlyIsUniformWithinHalfACount) {
  SensorOptions o;
  o.quantisation_deg = 0.01;
  Sensors s(o, 2, 3, kDt);
  Rng truth(11);
  const double r = o.quantisation_deg * kDeg, a = r / 2;
  double se2 = 0;
  for (int i = 0; i < kN; ++i) {
    const Eigen::Vector2d q(2 * truth.uniform() - 1, 2 * truth.uniform());
    const Eigen::Vector2d m = s.angles(q);
    for (int j = 0; j < 2; ++j) {
      const double e = m[j] - q[j];
      ASSERT_LE(std::abs(e), a * (1 + 1e-9));
      // readings are whole counts
      ASSERT_NEAR(m[j] / r, std::nearbyint(m[j] / r), 1e-6);
      se2 += e * e;
    }
  }
  // E[e^2] = a^2/3 = r^2/12; Var[e^2] = a^4/5 - a^4/9 = 4 a^4 / 45.
  const double n = 2.0 * kN;
  EXPECT_NEAR(se2 / n, r * r / 12, kSigmas * std::sqrt(4.0 / 45) * a * a / std::sqrt(n));
}

TEST(SensorsTest, AngleNoiseHasTheSetStandardDeviation) {
  SensorOptions o;
  o.noise_q_deg = 0.02;
  Sensors s(o, 2, 5, kDt);
  const double sigma = o.noise_q_deg * kDeg;
  double se = 0, se2 = 0;
  const Eigen::Vector2d q(-0.5, 1.3);
  for (int i = 0; i < kN; ++i) {
    const Eigen::Vector2d e = s.angles(q) - q;
    se += e.sum();
    se2 += e.squaredNorm();
  }
  const double n = 2.0 * kN;
  EXPECT_NEAR(se / n, 0.0, kSigmas * sigma / std::sqrt(n));
  // sample variance: std = sigma^2 sqrt(2 / n)
  EXPECT_NEAR(se2 / n, sigma * sigma, kSigmas * sigma * sigma * std::sqrt(2.0 / n));
}

TEST(SensorsTest, TorqueNoiseAndBias) {
  SensorOptions o;
  o.noise_tau_Nm = 0.5;
  o.tau_bias_Nm = {0.3, -0.2};
  Sensors s(o, 2, 9, kDt);
  const Eigen::Vector2d tau(10.0, -4.0);
  s.resetTorqueFilters(tau);  // a constant torque: the anti-aliasing filter passes it unchanged
  Eigen::Vector2d se = Eigen::Vector2d::Zero(), se2 = Eigen::Vector2d::Zero();
  for (int i = 0; i < kN; ++i) {
    const Eigen::Vector2d e = s.torques(tau) - tau;
    se += e;
    se2 += e.cwiseAbs2();
  }
  for (int j = 0; j < 2; ++j) {
    const double mean = se[j] / kN, bias = o.tau_bias_Nm[j];
    EXPECT_NEAR(mean, bias, kSigmas * o.noise_tau_Nm / std::sqrt(kN));
    const double var = se2[j] / kN - mean * mean;
    EXPECT_NEAR(var, 0.25, kSigmas * 0.25 * std::sqrt(2.0 / kN));
  }
}

TEST(SensorsTest, NoiseFreeSensorsAreExact) {
  SensorOptions ideal;
  ideal.tau_bandwidth_Hz = 0.0;  // no anti-aliasing filter
  ideal.imu_acc_noise_mps2 = ideal.imu_gyro_noise_radps = 0.0;
  Sensors s(ideal, 2, 1, kDt);
  EXPECT_EQ(s.imu(Eigen::Vector3d(0.1, 9.81, -0.01)), Eigen::Vector3d(0.1, 9.81, -0.01));
  const Eigen::Vector2d q(0.123456789, -1.5);
  EXPECT_EQ(s.angles(q), q);
  EXPECT_EQ(s.torques(q), q);
}

TEST(SensorsTest, StreamsAreIndependentOfOtherSettings) {
  // Turning on torque noise must not change the encoder readings of the same seed.
  SensorOptions a;
  a.noise_q_deg = 0.01;
  SensorOptions b = a;
  b.noise_tau_Nm = 1.0;
  Sensors sa(a, 2, 77, kDt), sb(b, 2, 77, kDt);
  for (int i = 0; i < 100; ++i) {
    sb.torques(Eigen::Vector2d::Zero());
    EXPECT_EQ(sa.angles(Eigen::Vector2d(0.1, 0.2)), sb.angles(Eigen::Vector2d(0.1, 0.2)));
  }
}

TEST(SensorsTest, TorqueFilterIsTheBilinearButterworth) {
  // Steady-state response to a sine at f: the bilinear transform maps it to the continuous
  // Butterworth at wa = (2/dt) tan(w dt/2): |H| = 1/sqrt(1 + (wa/wn)^4), phase
  // -atan2(sqrt(2) wa/wn, 1 - (wa/wn)^2); exact up to the rounding of the sums (1e-9).
  // At 1 Hz this is the continuous filter's delay sqrt(2)/wn to O((w/wn)^2) = 2.5e-5 relative.
  SensorOptions o;  // 200 Hz
  const double wn = 2 * M_PI * o.tau_bandwidth_Hz;
  for (const double f : {o.tau_bandwidth_Hz, 1.0}) {
    Sensors s(o, 2, 1, kDt);
    const double w = 2 * M_PI * f;
    double corr_sin = 0, corr_cos = 0;
    const int settle = 5000, n = 20000;  // whole periods of 1 Hz and 200 Hz
    for (int k = 0; k < settle + n; ++k) {
      const double t = k * kDt;
      const double y = s.torques(Eigen::Vector2d(std::sin(w * t), 0.0))[0];
      if (k >= settle) {
        corr_sin += y * std::sin(w * t);
        corr_cos += y * std::cos(w * t);
      }
    }
    const double amp = 2.0 * std::hypot(corr_sin, corr_cos) / n;
    const double phase = std::atan2(corr_cos, corr_sin);
    const double r = (2.0 / kDt) * std::tan(w * kDt / 2) / wn;
    EXPECT_NEAR(amp, 1.0 / std::sqrt(1.0 + r * r * r * r), 1e-9) << f << " Hz";
    EXPECT_NEAR(phase, -std::atan2(std::sqrt(2.0) * r, 1.0 - r * r), 1e-9) << f << " Hz";
    if (f == 1.0) {
      EXPECT_NEAR(-phase / w, std::sqrt(2.0) / wn, 2.5e-5 * std::sqrt(2.0) / wn);
    }
  }
}

TEST(SensorsTest, ImuNoiseHasTheSetStandardDeviations) {
  SensorOptions o;
  Sensors s(o, 2, 4, kDt);
  const Eigen::Vector3d truth(0.2, 9.81, 0.01);
  Eigen::Vector3d se2 = Eigen::Vector3d::Zero();
  for (int i = 0; i < kN; ++i) se2 += (s.imu(truth) - truth).cwiseAbs2();
  const double sd[3] = {o.imu_acc_noise_mps2, o.imu_acc_noise_mps2, o.imu_gyro_noise_radps};
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(se2[j] / kN, sd[j] * sd[j], kSigmas * sd[j] * sd[j] * std::sqrt(2.0 / kN));
  }
}

TEST(SensorsTest, EncoderBacklashIsAPlayOperator) {
  // A 1 Hz sine of 0.3 rad through 0.5 deg of play: the reading lags the joint by b/2 while it
  // moves, stands still at each reversal until the joint has moved b, and never strays more than
  // b/2 (the definition of a play operator).
  SensorOptions o;
  o.encoder_backlash_deg = 0.5;
  Sensors s(o, 2, 3, kDt);
  const double b = 0.5 * kDeg;
  double worst = 0.0;
  int standing = 0;
  Eigen::Vector2d prev;
  for (int i = 0; i < 2000; ++i) {
    const double q = 0.3 * std::sin(2 * M_PI * 1.0 * i * kDt);
    const Eigen::Vector2d r = s.angles(Eigen::Vector2d(q, -q));
    worst = std::max(worst, std::abs(r[0] - q));
    if (i > 0 && r[0] == prev[0]) ++standing;
    if (i == 100) {
      EXPECT_NEAR(r[0], q - 0.5 * b, 1e-12);  // moving up: lags by b/2
    }
    if (i == 500) {
      EXPECT_NEAR(r[0], q + 0.5 * b, 1e-12);  // moving down: leads by b/2
    }
    prev = r;
  }
  EXPECT_LE(worst, 0.5 * b * (1 + 1e-12));
  // At each of the 4 reversals it stands from the peak until the joint is back by b: near a peak
  // of 0.3 sin(w t), 0.3 w^2 t^2 / 2 = b, t = sqrt(2 b / (0.3 w^2)) = 38.4 samples; plus the
  // start, where it stands until the joint has moved b/2 (2.3 samples). One sample of rounding
  // per stand.
  const double per_reversal = std::sqrt(2.0 * b / (0.3 * std::pow(2 * M_PI, 2))) / kDt;
  const double at_start = 0.5 * b / (0.3 * 2 * M_PI) / kDt;
  EXPECT_NEAR(standing, 4.0 * per_reversal + at_start, 5.0);
  o.encoder_backlash_deg = -1.0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(SensorsTest, ValidationNamesTheField) {
  SensorOptions o;
  o.noise_tau_Nm = -1;
  try {
    o.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'noise_tau_Nm'"), std::string::npos);
  }
  o = {};
  o.quantisation_deg = std::nan("");
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::sim
