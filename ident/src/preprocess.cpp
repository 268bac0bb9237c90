#include "exoid/ident/preprocess.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

const char* toString(Processing p) { return p == Processing::kParallel ? "parallel" : "paper"; }

const char* toString(BaseTerms b) {
  switch (b) {
    case BaseTerms::kOff: return "off";
    case BaseTerms::kAuto: return "auto";
    case BaseTerms::kOn: return "on";
  }
  return "unknown";
}

namespace {
const char* const kBaseColumns[3] = {"base_acc_x", "base_acc_z", "base_gyro_y"};
}

bool hasBaseColumns(const Dataset& d) {
  for (const char* name : kBaseColumns) {
    if (std::find(d.extra_names.begin(), d.extra_names.end(), name) == d.extra_names.end()) return false;
  }
  return true;
}

int SignalOptions::decimationFactor(double sample_rate_hz) const {
  if (decimation > 0) return decimation;
  if (!filter) return 1;  // no anti-aliasing filter: keep every row
  // The relative 1e-9 keeps a rate computed as 999.9999999 Hz from 1 kHz timestamps at factor 20.
  return std::max(1, static_cast<int>(std::floor(sample_rate_hz / (5.0 * cutoff_hz) * (1.0 + 1e-9))));
}

void SignalOptions::validate() const {
  if (decimation < 0) throw std::invalid_argument("'decimation' must be >= 0 (0 = automatic), got " + std::to_string(decimation));
  if (!(derivative_cutoff_hz >= 0.0) || !std::isfinite(derivative_cutoff_hz)) {
    throw std::invalid_argument("'derivative_cutoff_hz' must be >= 0 (0 = no pre-filter)");
  }
  if (filter_order < 1 || filter_order > 8) {
    throw std::invalid_argument("'filter_order' must be in 1..8, got " + std::to_string(filter_order));
  }
  if (!std::isfinite(edge_trim_s)) throw std::invalid_argument("'edge_trim_s' must be finite");
  if (base_terms == BaseTerms::kOn && processing != Processing::kParallel) {
    throw std::invalid_argument("'base_terms' = on needs the parallel processing (the paper's has no base-motion terms)");
  }
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
  } else if (o.use_recorded_derivatives && d.qd_radps) {  // recorded velocities only: differentiate them
    s.qd_radps = smooth(*d.qd_radps);
    s.qdd_radps2 = smooth(differentiate(s.qd_radps, dt, o.differentiation));
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
    throw std::invalid_argument("record too short: " + std::to_string(in.size()) + " samples, and the processing trims " +
                                std::to_string(trim) + " at each end (the filter's edge transients, edge_trim_s) and "
                                "needs 20 more: at least " + std::to_string(2 * trim + 20) + " samples");
  }
  JointSignals s;
  s.t_s = in.t_s.segment(trim, keep);
  s.q_rad = in.q_rad.middleRows(trim, keep);
  s.qd_radps = in.qd_radps.middleRows(trim, keep);
  s.qdd_radps2 = in.qdd_radps2.middleRows(trim, keep);
  s.tau_Nm = in.tau_Nm.middleRows(trim, keep);
  if (in.base.rows() > 0) s.base = in.base.middleRows(trim, keep);
  return s;
}

ProcessedRecord regressorRecord(const JointSignals& s, const LegConstants& c) {
  return {jointRegressor(s, Joint::kHip, c), jointRegressor(s, Joint::kKnee, c), s.tau_Nm, s.qdd_radps2.col(1), s};
}

namespace {

// Rows [trim, n - trim) of x, every r-th.
Eigen::MatrixXd trimAndDecimate(const Eigen::MatrixXd& x, Eigen::Index trim, int r) {
  const Eigen::Index keep = x.rows() - 2 * trim;
  const Eigen::Index out_rows = (keep + r - 1) / r;
  Eigen::MatrixXd out(out_rows, x.cols());
  for (Eigen::Index i = 0; i < out_rows; ++i) out.row(i) = x.row(trim + i * r);
  return out;
}

// States for the parallel processing: recorded derivatives, else five-point differences of the
// (widely pre-filtered) angles; the angles themselves unfiltered.
JointSignals parallelStates(const Dataset& d, const SignalOptions& o, double fs) {
  JointSignals s;
  s.t_s = d.t_s;
  s.q_rad = d.q_rad;
  s.tau_Nm = d.tau_Nm;
  const double dt = 1.0 / fs;
  const bool prefilter = o.derivative_cutoff_hz > 0.0 && o.derivative_cutoff_hz < 0.5 * fs;
  const bool base = o.base_terms == BaseTerms::kOn || (o.base_terms == BaseTerms::kAuto && hasBaseColumns(d));
  if (base) {
    if (!hasBaseColumns(d)) {
      throw std::invalid_argument("base-motion terms requested but the dataset lacks base_acc_x, base_acc_z or base_gyro_y");
    }
    s.base.resize(d.size(), 4);
    s.base.col(0) = d.extraColumn(kBaseColumns[0]);
    s.base.col(1) = d.extraColumn(kBaseColumns[1]);
    s.base.col(2) = d.extraColumn(kBaseColumns[2]);
    // Pitch acceleration: the gyro differentiated like the angles' first derivative.
    Eigen::MatrixXd w = s.base.col(2);
    if (prefilter) w = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), w);
    s.base.col(3) = differentiate(w, dt, Differentiation::kCentral4);
  }
  if (o.use_recorded_derivatives && d.qd_radps && d.qdd_radps2) {
    s.qd_radps = *d.qd_radps;
    s.qdd_radps2 = *d.qdd_radps2;
    return s;
  }
  if (o.use_recorded_derivatives && d.qd_radps) {  // recorded velocities only: differentiate them
    s.qd_radps = *d.qd_radps;
    Eigen::MatrixXd qd = *d.qd_radps;
    if (prefilter) qd = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), qd);
    s.qdd_radps2 = differentiate(qd, dt, Differentiation::kCentral4);
    return s;
  }
  Eigen::MatrixXd q = d.q_rad;
  if (prefilter) q = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), q);
  s.qd_radps = differentiate(q, dt, Differentiation::kCentral4);
  s.qdd_radps2 = differentiate(s.qd_radps, dt, Differentiation::kCentral4);
  return s;
}

}  // namespace

ProcessedRecord processRecord(const Dataset& d, const LegConstants& c, const SignalOptions& o) {
  o.validate();
  if (o.processing == Processing::kPaper) return regressorRecord(prepareSignals(d, o), c);
  const double fs = 1.0 / d.sampleInterval_s();
  return parallelProcess(parallelStates(d, o, fs), c, o, fs);
}

ProcessedRecord parallelProcess(const JointSignals& s, const LegConstants& c, const SignalOptions& o,
                                double sample_rate_hz) {
  o.validate();
  const double fs = sample_rate_hz;
  // Hip rows, knee rows, torques and the armature column side by side: one filter pass over all.
  Eigen::MatrixXd all(s.size(), 2 * kNumParams + 3);
  all << jointRegressor(s, Joint::kHip, c), jointRegressor(s, Joint::kKnee, c), s.tau_Nm, s.qdd_radps2.col(1);
  if (o.filter) all = filtfilt(butterworthLowpass(o.filter_order, o.cutoff_hz, fs), all);
  const Eigen::Index trim = o.edgeTrimSamples(fs);
  if (s.size() - 2 * trim < 20) {
    throw std::invalid_argument("record too short: " + std::to_string(s.size()) + " samples, and the processing trims " +
                                std::to_string(trim) + " at each end (the filter's edge transients, edge_trim_s) and "
                                "needs 20 more: at least " + std::to_string(2 * trim + 20) + " samples");
  }
  const int r = o.decimationFactor(fs);
  const Eigen::MatrixXd kept = trimAndDecimate(all, trim, r);
  if (kept.rows() < 20) {
    throw std::invalid_argument("record too short: " + std::to_string(kept.rows()) + " rows after trimming and decimating by " +
                                std::to_string(r) + "; need >= 20 (lower 'decimation')");
  }
  ProcessedRecord out;
  out.hip = kept.leftCols(kNumParams);
  out.knee = kept.middleCols(kNumParams, kNumParams);
  out.tau_Nm = kept.middleCols(2 * kNumParams, 2);
  out.knee_armature = kept.col(2 * kNumParams + 2);
  JointSignals& st = out.states;
  st.t_s = trimAndDecimate(s.t_s, trim, r).col(0);
  st.q_rad = trimAndDecimate(s.q_rad, trim, r);
  st.qd_radps = trimAndDecimate(s.qd_radps, trim, r);
  st.qdd_radps2 = trimAndDecimate(s.qdd_radps2, trim, r);
  st.tau_Nm = out.tau_Nm;
  if (s.base.rows() > 0) st.base = trimAndDecimate(s.base, trim, r);
  return out;
}

ProcessedRecord stackRecords(const std::vector<ProcessedRecord>& records) {
  if (records.empty()) throw std::invalid_argument("stackRecords: no records");
  if (records.size() == 1) return records.front();
  Eigen::Index n = 0;
  const bool base = records.front().states.base.rows() > 0;
  for (const ProcessedRecord& r : records) {
    if ((r.states.base.rows() > 0) != base) {
      throw std::invalid_argument("stackRecords: some records have base-motion columns and others not");
    }
    n += r.size();
  }
  ProcessedRecord out;
  out.hip.resize(n, kNumParams);
  out.knee.resize(n, kNumParams);
  out.tau_Nm.resize(n, 2);
  out.knee_armature.resize(n);
  JointSignals& st = out.states;
  st.t_s.resize(n);
  st.q_rad.resize(n, 2);
  st.qd_radps.resize(n, 2);
  st.qdd_radps2.resize(n, 2);
  st.tau_Nm.resize(n, 2);
  if (base) st.base.resize(n, 4);
  Eigen::Index at = 0;
  for (const ProcessedRecord& r : records) {
    const Eigen::Index m = r.size();
    out.hip.middleRows(at, m) = r.hip;
    out.knee.middleRows(at, m) = r.knee;
    out.tau_Nm.middleRows(at, m) = r.tau_Nm;
    out.knee_armature.segment(at, m) = r.knee_armature.size() == m ? r.knee_armature : Eigen::VectorXd::Zero(m);
    if (r.states.size() != m) throw std::invalid_argument("stackRecords: a record's states do not align with its rows");
    {
      st.t_s.segment(at, m) = r.states.t_s;
      st.q_rad.middleRows(at, m) = r.states.q_rad;
      st.qd_radps.middleRows(at, m) = r.states.qd_radps;
      st.qdd_radps2.middleRows(at, m) = r.states.qdd_radps2;
      st.tau_Nm.middleRows(at, m) = r.states.tau_Nm;
      if (base) st.base.middleRows(at, m) = r.states.base;
    }
    at += m;
  }
  return out;
}

}  // namespace exoid::ident
