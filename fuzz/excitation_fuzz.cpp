// An excitation design (JSON, `exoid simulate --excitation`, sweeps, reproduce; written by exoid
// excite or by hand): read into a valid trajectory of named joints or refused naming the file and
// key; what is read writes back and reads again to the same bits.
#include "fuzz_support.hpp"

#include "exoid/experiments/protocol/excitation_io.hpp"
#include "exoid/sim/trajectory_json.hpp"

#include <set>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = exoid::fuzz::asFile(data, size, ".json");
  exoid::sim::NamedTrajectory t;
  try {
    t = exoid::experiments::readExcitationFile(path);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  t.series.validate();  // what was read is a trajectory the simulators can run
  EXOID_FUZZ_CHECK(static_cast<int>(t.joints.size()) == t.series.dof());
  EXOID_FUZZ_CHECK(std::set<std::string>(t.joints.begin(), t.joints.end()).size() == t.joints.size());
  const exoid::sim::NamedTrajectory again = exoid::sim::trajectoryFromJson(exoid::sim::trajectoryJson(t.series, t.joints));
  EXOID_FUZZ_CHECK(again.joints == t.joints && again.series.locked_joints == t.series.locked_joints);
  EXOID_FUZZ_CHECK(again.series.f0_hz == t.series.f0_hz && again.series.offset_rad == t.series.offset_rad);
  EXOID_FUZZ_CHECK(again.series.a_rad == t.series.a_rad && again.series.b_rad == t.series.b_rad);
  return 0;
}
