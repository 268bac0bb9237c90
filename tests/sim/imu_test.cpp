// The pedestal IMU's analytic readings against MuJoCo's own accelerometer and gyro sensors on the
// same site (an independent computation: MuJoCo's spatial-acceleration recursion).
#include "exoid/sim/imu.hpp"

#include "exoid/sim/four_bar.hpp"
#include "test_support.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

namespace exoid::sim {
namespace {

class ImuTest : public test::MujocoTest {};

// The default model with an accelerometer and a gyro on the IMU site, written next to the test's
// temporary files.
std::string modelWithImuSensors() {
  std::string xml = readFileBytes(defaultModelPath());
  const std::string sensors =
      "  <sensor>\n    <accelerometer name='acc' site='imu'/>\n    <gyro name='gyro' site='imu'/>\n  </sensor>\n";
  xml.insert(xml.rfind("</mujoco>"), sensors);
  const std::string path = ::testing::TempDir() + "/exoid_imu_sensors.xml";
  std::ofstream(path) << xml;
  return path;
}

TEST_F(ImuTest, MatchesMujocoAccelerometerAndGyro) {
  // Both read the same mjData after mj_forward; they differ only by rounding (1e-9 m/s^2 on
  // readings of ~10 m/s^2; the base accelerations themselves are ~0.1-10 m/s^2 here).
  ModelVariant v;
  v.vibration_level = 3.0;  // a soft mount: visible base motion
  const LegModel leg = loadLeg(modelWithImuSensors(), v);
  mjModel* m = leg.model.get();
  DataPtr data = makeData(m);
  mjData* d = data.get();
  const FourBar fb(m, leg.idx);
  setLegState(m, d, leg.idx, fb, {-0.3, 0.8}, {0.0, 0.0});
  const int acc = m->sensor_adr[mj_name2id(m, mjOBJ_SENSOR, "acc")];
  const int gyro = m->sensor_adr[mj_name2id(m, mjOBJ_SENSOR, "gyro")];
  double peak = 0.0, peak_rate = 0.0;
  for (int k = 0; k < 400; ++k) {
    const double t = 1e-3 * k;
    d->ctrl[leg.idx.act[0]] = 60.0 * std::sin(2 * M_PI * 3.0 * t);
    d->ctrl[leg.idx.act[1]] = 15.0 * std::sin(2 * M_PI * 5.0 * t);
    mj_forward(m, d);
    const Eigen::Vector3d mine = pedestalImuTruth(m, d, leg.idx);
    EXPECT_NEAR(mine[0], d->sensordata[acc + 0], 1e-9) << "t = " << t;
    EXPECT_NEAR(mine[1], d->sensordata[acc + 2], 1e-9) << "t = " << t;
    EXPECT_NEAR(mine[2], d->sensordata[gyro + 1], 1e-12) << "t = " << t;
    peak = std::max(peak, std::abs(mine[0]));
    peak_rate = std::max(peak_rate, std::abs(mine[2]));
    mj_step(m, d);
  }
  EXPECT_GT(peak, 0.05);  // the base does accelerate
  EXPECT_GT(peak_rate, 1e-4);
}

TEST_F(ImuTest, WeldedPedestalReadsGravityAlone) {
  const LegModel leg = loadLeg(defaultModelPath(), ModelVariant{});
  DataPtr d = makeData(leg.model.get());
  mj_forward(leg.model.get(), d.get());
  const Eigen::Vector3d r = pedestalImuTruth(leg.model.get(), d.get(), leg.idx);
  EXPECT_EQ(r, Eigen::Vector3d(0.0, 9.81, 0.0));
}

}  // namespace
}  // namespace exoid::sim
