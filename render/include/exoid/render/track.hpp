#pragma once
// The time series a clip replays: joint angles (and the APAL pedestal's coordinates) to pose the
// robot, and the torques the overlay shows. Plain arrays, so simulated runs and recorded datasets (read by
// the caller) enter the same way; render never depends on the identification library.
#include "exoid/sim/simulate.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace exoid::render {

/// One joint of a track: its angle and torques at every sample.
struct TrackJoint {
  std::string name;                 ///< the model's joint ("hip", "knee", "ankle", ...): poses it, labels the overlay
  std::vector<double> q_rad;        ///< the angle (exact states for a simulation)
  std::vector<double> tau_Nm;       ///< measured torque: empty, or full size for every joint
  /// An identified model's predicted torque: empty, or full size for every joint (needs the
  /// measured). NaN = no prediction at that sample (e.g. the edges preprocessing trims).
  std::vector<double> tau_pred_Nm;
};

/// Any robot's record on a uniform time axis: the APAL leg's (hip, knee and its pedestal) or a
/// serial chain's joints.
struct Track {
  std::string title;                          ///< first overlay line, e.g. "trajectory 3 (simulated)"
  std::vector<double> t_s;                    ///< uniformly sampled, increasing
  std::vector<TrackJoint> joints;
  /// The APAL pedestal's mount coordinates (qpos of mount_x, mount_z, mount_pitch): all three
  /// empty (pedestal at rest) or all of size t_s.size().
  std::vector<double> base_x_m, base_z_m, base_pitch_rad;
  /// What the torques shown as measured are, in the overlay: "measured" (as recorded) or, e.g.,
  /// "filtered" (the processed torque an identification fitted).
  std::string torque_name = "measured";
  /// Legend name of the prediction, e.g. "LS".
  std::string prediction_name = "identified";

  std::size_t size() const { return t_s.size(); }
  bool hasBase() const { return !base_x_m.empty(); }
  bool hasTorque() const { return !joints.empty() && !joints.front().tau_Nm.empty(); }
  bool hasPrediction() const { return !joints.empty() && !joints.front().tau_pred_Nm.empty(); }
  /// Every series of the track (time, each joint's, the pedestal's): to cut a window of it.
  std::vector<std::vector<double>*> series();

  /// Throws std::invalid_argument naming the joint and series: sizes, at least 2 samples, at
  /// least one joint, finite values, strictly increasing and uniform time (every interval within
  /// 1 % of the mean).
  void validate() const;
  /// Mean sample interval (s).
  double sampleInterval_s() const;
  /// Record length: size() * sampleInterval_s() (a 1 kHz record of 2000 rows lasts 2 s).
  double duration_s() const;
  /// Row nearest to time t (the recorded state shown at t). Throws std::invalid_argument if t is
  /// outside [t_s.front(), t_s.front() + duration_s()).
  std::size_t rowAt(double t_s_query) const;
};

/// The APAL leg's simulation: the exact states (q_*_true, base_*; pedestal columns dropped when
/// the pedestal never moved) and the measured torques (tau_hip, tau_knee) of joints hip and knee.
Track trackFromSimulation(const sim::SimResult& result, const std::string& title);

/// Frames of a clip at `fps` over the whole track: floor(duration_s * fps) (+1e-9 slack),
/// frame k shown at t_s.front() + k / fps. Throws std::invalid_argument for fps <= 0 or a
/// track shorter than one frame.
int frameCount(const Track& track, double fps);

}  // namespace exoid::render
