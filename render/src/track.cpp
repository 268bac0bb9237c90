#include "exoid/render/track.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace exoid::render {

namespace {

void checkColumn(const std::vector<double>& v, std::size_t n, const std::string& name, bool optional, bool nan_ok = false) {
  if (optional && v.empty()) return;
  if (v.size() != n) {
    throw std::invalid_argument("track: " + name + " has " + core::toText(v.size()) + " samples, the time axis " + core::toText(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i]) && !(nan_ok && std::isnan(v[i]))) {
      throw std::invalid_argument("track: " + name + ": value " + core::toText(i) + " is not finite");
    }
  }
}

std::vector<double> column(const sim::Table& t, const std::string& name) {
  const Eigen::VectorXd c = t.col(name);
  return std::vector<double>(c.data(), c.data() + c.size());
}

}  // namespace

void Track::validate() const {
  const std::size_t n = t_s.size();
  if (n < 2) throw std::invalid_argument("track: expected at least 2 samples, got " + core::toText(n));
  if (joints.empty()) throw std::invalid_argument("track: no joints");
  checkColumn(t_s, n, "time", false);
  for (const TrackJoint& j : joints) {
    checkColumn(j.q_rad, n, j.name + " angle", false);
    checkColumn(j.tau_Nm, n, j.name + " torque", !hasTorque());
    checkColumn(j.tau_pred_Nm, n, j.name + " predicted torque", !hasPrediction(), true);
  }
  if (hasPrediction() && !hasTorque()) throw std::invalid_argument("track: predicted torques need the measured torques");
  checkColumn(base_x_m, n, "pedestal x", true);
  checkColumn(base_z_m, n, "pedestal z", true);
  checkColumn(base_pitch_rad, n, "pedestal pitch", true);
  if (base_x_m.empty() != base_z_m.empty() || base_x_m.empty() != base_pitch_rad.empty()) {
    throw std::invalid_argument("track: the pedestal's x, z and pitch must be all empty or all given");
  }
  const double dt = sampleInterval_s();
  if (!(dt > 0.0)) throw std::invalid_argument("track: time must increase (t_s.front() = " + core::toText(t_s.front()) +
                                                ", t_s.back() = " + core::toText(t_s.back()) + ")");
  for (std::size_t i = 1; i < n; ++i) {
    const double step = t_s[i] - t_s[i - 1];
    if (std::abs(step - dt) > 0.01 * dt) {
      throw std::invalid_argument("track: time is not uniformly sampled: t_s[" + core::toText(i) + "] - t_s[" +
                                  core::toText(i - 1) + "] = " + core::toText(step) + " s, mean interval " +
                                  core::toText(dt) + " s");
    }
  }
}

std::vector<std::vector<double>*> Track::series() {
  std::vector<std::vector<double>*> all = {&t_s, &base_x_m, &base_z_m, &base_pitch_rad};
  for (TrackJoint& j : joints) all.insert(all.end(), {&j.q_rad, &j.tau_Nm, &j.tau_pred_Nm});
  return all;
}

double Track::sampleInterval_s() const {
  if (t_s.size() < 2) throw std::invalid_argument("track: expected at least 2 samples, got " + core::toText(t_s.size()));
  return (t_s.back() - t_s.front()) / static_cast<double>(t_s.size() - 1);
}

double Track::duration_s() const { return static_cast<double>(t_s.size()) * sampleInterval_s(); }

std::size_t Track::rowAt(double t) const {
  const double t0 = t_s.front();
  const double dur = duration_s();
  if (!std::isfinite(t) || t < t0 || t >= t0 + dur) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "frame time %g s is outside the record [%g, %g) s", t, t0, t0 + dur);
    throw std::invalid_argument(msg);
  }
  const double k = std::round((t - t0) / sampleInterval_s());
  return std::min(static_cast<std::size_t>(k), t_s.size() - 1);
}

Track trackFromSimulation(const sim::SimResult& result, const std::string& title) {
  const sim::Table& tab = result.table;
  Track tr;
  tr.title = title;
  tr.t_s = column(tab, "t");
  const bool exact = tab.has("q_hip_true");
  for (const std::string joint : {"hip", "knee"}) {
    tr.joints.push_back({joint, column(tab, exact ? "q_" + joint + "_true" : "q_" + joint), column(tab, "tau_" + joint), {}});
  }
  if (tab.has("base_x")) {
    tr.base_x_m = column(tab, "base_x");
    tr.base_z_m = column(tab, "base_z");
    tr.base_pitch_rad = column(tab, "base_pitch");
    const auto still = [](const std::vector<double>& v) {
      return std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0; });
    };
    if (still(tr.base_x_m) && still(tr.base_z_m) && still(tr.base_pitch_rad)) {
      tr.base_x_m.clear();
      tr.base_z_m.clear();
      tr.base_pitch_rad.clear();
    }
  }
  tr.validate();
  return tr;
}

int frameCount(const Track& track, double fps) {
  if (!std::isfinite(fps) || fps <= 0.0) throw std::invalid_argument("'fps' must be positive, got " + core::toText(fps));
  const double frames = std::floor(track.duration_s() * fps + 1e-9);
  if (frames < 1.0) {
    throw std::invalid_argument("the record (" + core::toText(track.duration_s()) + " s) is shorter than one frame at " +
                                core::toText(fps) + " fps");
  }
  if (frames > 1e7) throw std::invalid_argument("too many frames: " + core::toText(frames));
  return static_cast<int>(frames);
}

}  // namespace exoid::render
