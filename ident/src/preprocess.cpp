#include "exoid/ident/preprocess.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

void SignalOptions::validate() const {
  if (filter_order < 1 || filter_order > 8) {
    throw std::invalid_argument("'filter_order' must be in 1..8, got " + std::to_string(filter_order));
  }
  if (!std::isfinite(edge_trim_s)) throw std::invalid_argument("'edge_trim_s' must be finite");
  if (!(cutoff_hz > 0.0)) {
    throw std::invalid_argument("'cutoff_hz' must be > 0, got " + std::to_string(cutoff_hz));
  }
}

long SignalOptions::edgeTrimSamples(double sample_rate_hz) const {
  if (edge_trim_s >= 0.0) return std::lround(edge_trim_s * sample_rate_hz);
  return filter ? std::lround(3.0 / cutoff_hz * sample_rate_hz) : 2;
}

JointSignals recordedSignals(const Dataset& d) {
  if (!d.qd_radps || !d.qdd_radps2) {
    throw std::invalid_argument("dataset has no qd_hip/qd_knee/qdd_hip/qdd_knee columns");
  }
  JointSignals s;
  s.t_s = d.t_s;
  s.q_rad = d.q_rad;
  s.qd_radps = *d.qd_radps;
  s.qdd_radps2 = *d.qdd_radps2;
  s.tau_Nm = d.tau_Nm;
  return s;
}

JointSignals prepareSignals(const Dataset& d, const SignalOptions& o) {
  o.validate();
  const double dt = d.sampleInterval_s();
  const double fs = 1.0 / dt;
  const bool recorded = o.use_recorded_derivatives && d.qd_radps && d.qdd_radps2;
  SosFilter lowpass;
  if (o.filter) lowpass = butterworthLowpass(o.filter_order, o.cutoff_hz, fs);
  auto smooth = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd { return o.filter ? filtfilt(lowpass, x) : x; };

  JointSignals s;
  s.t_s = d.t_s;
  s.q_rad = smooth(d.q_rad);
  if (recorded) {
    s.qd_radps = smooth(*d.qd_radps);
    s.qdd_radps2 = smooth(*d.qdd_radps2);
  } else {
    s.qd_radps = smooth(differentiate(s.q_rad, dt, o.differentiation));
    s.qdd_radps2 = smooth(differentiate(s.qd_radps, dt, o.differentiation));
  }
  s.tau_Nm = o.filter && o.filter_torque ? smooth(d.tau_Nm) : Eigen::MatrixXd(d.tau_Nm);
  return trimEdges(s, o.edgeTrimSamples(fs));
}

JointSignals trimEdges(const JointSignals& in, Eigen::Index trim) {
  const Eigen::Index keep = in.size() - 2 * trim;
  if (trim < 0 || keep < 20) {
    throw std::invalid_argument("record too short: " + std::to_string(in.size()) + " samples leave " +
                                std::to_string(keep) + " after trimming " + std::to_string(trim) +
                                " at each end (edge_trim_s); need >= 20");
  }
  JointSignals s;
  s.t_s = in.t_s.segment(trim, keep);
  s.q_rad = in.q_rad.middleRows(trim, keep);
  s.qd_radps = in.qd_radps.middleRows(trim, keep);
  s.qdd_radps2 = in.qdd_radps2.middleRows(trim, keep);
  s.tau_Nm = in.tau_Nm.middleRows(trim, keep);
  return s;
}

}  // namespace exoid::ident
