// The simulated rig's torques are motion, not controller chatter: with the reproduce settings,
// at most 5 % of each joint torque's variance lies above 10 Hz (Welch), recorded and ideal alike.
#include "exoid/experiments/protocol/reproduce.hpp"
#include "exoid/experiments/protocol/sim_bridge.hpp"

#include <gtest/gtest.h>

namespace exoid::experiments {
namespace {

TEST(SpectralTarget, ReproduceRigTorquesAreBelowFivePercentAbove10Hz) {
  for (const int trajectory : {1, 3}) {
    sim::SimConfig c = defaultReproduceConfig().sim;
    c.trajectory = trajectory;
    c.seed = 3;
    const ident::Dataset d = toDataset(sim::simulate(c));
    const std::map<std::string, double> hf = torqueVarianceAbove(d);
    // Trajectory 1 locks the hip: no hip motor torque is recorded there (only sensor noise).
    const std::vector<std::string> cols = trajectory == 1
                                              ? std::vector<std::string>{"tau_knee", "tau_knee_ideal"}
                                              : std::vector<std::string>{"tau_hip", "tau_knee", "tau_hip_ideal", "tau_knee_ideal"};
    for (const std::string& col : cols) {
      ASSERT_TRUE(hf.count(col)) << col;
      EXPECT_LE(hf.at(col), 0.05) << "trajectory " << trajectory << ", " << col;
    }
  }
}

}  // namespace
}  // namespace exoid::experiments
