#include "exoid/ident/signals/preprocess.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/parallel_for.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace exoid::ident {

const char* toString(Processing p) { return p == Processing::kParallel ? "parallel" : "paper"; }

const char* toString(BaseTerms b) {
  switch (b) {
    case BaseTerms::kOff: return "off";
    case BaseTerms::kAuto: return "auto";
    case BaseTerms::kOn: return "on";
    case BaseTerms::kJudged: return "judged";
  }
  return "unknown";
}

const char* const kBaseColumns[3] = {"base_acc_x", "base_acc_z", "base_gyro_y"};

namespace {
const char* const kBaseAlphaColumn = "base_alpha_y";  // optional: the pitch acceleration, recorded
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
  if (decimation < 0) throw std::invalid_argument("'decimation' must be >= 0 (0 = automatic), got " + core::toText(decimation));
  if (block_samples < 1) throw std::invalid_argument("'block_samples' must be >= 1, got " + core::toText(block_samples));
  if (threads < 0) throw std::invalid_argument("'threads' must be >= 0 (0 = the machine's cores), got " + core::toText(threads));
  if (!(derivative_cutoff_hz >= 0.0) || !std::isfinite(derivative_cutoff_hz)) {
    throw std::invalid_argument("'derivative_cutoff_hz' must be >= 0 (0 = no pre-filter)");
  }
  if (filter_order < 1 || filter_order > 8) {
    throw std::invalid_argument("'filter_order' must be in 1..8, got " + core::toText(filter_order));
  }
  if (!std::isfinite(edge_trim_s)) throw std::invalid_argument("'edge_trim_s' must be finite");
  if (base_terms == BaseTerms::kOn && processing != Processing::kParallel) {
    throw std::invalid_argument("'base_terms' = on needs the parallel processing (the paper's has no base-motion terms)");
  }
  if (!(cutoff_hz > 0.0)) {
    throw std::invalid_argument("'cutoff_hz' must be > 0, got " + core::toText(cutoff_hz));
  }
}

void SignalOptions::validateFor(double sample_rate_hz) const {
  validate();
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    throw std::invalid_argument("the record's sample rate must be positive and finite, got " + core::toText(sample_rate_hz) + " Hz");
  }
  if (sample_rate_hz > 1e6) {
    std::ostringstream msg;
    msg << "the record's time step is " << 1.0 / sample_rate_hz << " s (" << sample_rate_hz
        << " Hz): exoid processes records sampled at up to 1 MHz; is its time column in another unit (--time-unit)?";
    throw std::invalid_argument(msg.str());
  }
  const double nyquist = 0.5 * sample_rate_hz;
  auto below = [&](const char* name, double hz) {
    if (hz < nyquist) return;
    std::ostringstream msg;
    msg << "'" << name << "' = " << hz << " Hz must be below the record's Nyquist frequency, " << nyquist
        << " Hz (it is sampled at " << sample_rate_hz << " Hz)";
    if (sample_rate_hz < 20.0) msg << "; a log sampled that slowly usually has its time column in ms or us (--time-unit ms)";
    throw std::invalid_argument(msg.str());
  };
  if (filter) below("cutoff_hz", cutoff_hz);
}

long SignalOptions::edgeTrimSamples(double sample_rate_hz) const {
  if (edge_trim_s >= 0.0) return std::lround(edge_trim_s * sample_rate_hz);
  return filter ? std::lround(3.0 / cutoff_hz * sample_rate_hz) : 2;
}

// Enough rows left once the filter's edges are trimmed and the rows decimated (a clear message, not
// a least-squares size error later).
void checkRecordLength(Eigen::Index n, Eigen::Index trim, int r) {
  if (n - 2 * trim < 20) {
    throw std::invalid_argument("record too short: " + core::toText(n) + " samples, and the processing trims " +
                                core::toText(trim) + " at each end (the filter's edge transients, edge_trim_s) and "
                                "needs 20 more: at least " + core::toText(2 * trim + 20) + " samples");
  }
  if ((n - 2 * trim + r - 1) / r < 20) {
    throw std::invalid_argument("record too short: " + core::toText((n - 2 * trim + r - 1) / r) +
                                " rows after trimming and decimating by " + core::toText(r) + "; need >= 20 (lower 'decimation')");
  }
}

JointSignals prepareSignals(const Dataset& d, const SignalOptions& o) {
  const double dt = d.sampleInterval_s();
  const double fs = 1.0 / dt;
  o.validateFor(fs);
  checkRecordLength(d.size(), o.edgeTrimSamples(fs), 1);
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
    throw std::invalid_argument("record too short: " + core::toText(in.size()) + " samples, and the processing trims " +
                                core::toText(trim) + " at each end (the filter's edge transients, edge_trim_s) and "
                                "needs 20 more: at least " + core::toText(2 * trim + 20) + " samples");
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

namespace {

// States for the parallel processing: recorded derivatives, else five-point differences of the
// (widely pre-filtered) angles; the angles themselves unfiltered.
JointSignals parallelStates(const Dataset& d, const SignalOptions& o, double fs, Eigen::Index from, Eigen::Index to) {
  const Eigen::Index len = to - from;
  JointSignals s;
  s.t_s = d.t_s.segment(from, len);
  s.q_rad = d.q_rad.middleRows(from, len);
  s.tau_Nm = d.tau_Nm.middleRows(from, len);
  const double dt = 1.0 / fs;
  const bool prefilter = o.derivative_cutoff_hz > 0.0 && o.derivative_cutoff_hz < 0.5 * fs;
  const bool base = o.base_terms == BaseTerms::kOn || (whenPresent(o.base_terms) && hasBaseColumns(d));
  if (base) {
    if (!hasBaseColumns(d)) {
      throw std::invalid_argument("base-motion terms requested but the dataset lacks base_acc_x, base_acc_z or base_gyro_y");
    }
    s.base.resize(len, 4);
    for (int k = 0; k < 3; ++k) s.base.col(k) = d.extraColumn(kBaseColumns[k]).segment(from, len);
    const bool recorded_alpha = o.use_recorded_derivatives &&
                                std::find(d.extra_names.begin(), d.extra_names.end(), kBaseAlphaColumn) != d.extra_names.end();
    if (recorded_alpha) {  // recorded, as the joints' accelerations may be
      s.base.col(3) = d.extraColumn(kBaseAlphaColumn).segment(from, len);
    } else {  // the gyro differentiated like the angles' first derivative
      Eigen::MatrixXd w = s.base.col(2);
      if (prefilter) w = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), w);
      s.base.col(3) = differentiate(w, dt, Differentiation::kCentral4);
    }
  }
  if (o.use_recorded_derivatives && d.qd_radps && d.qdd_radps2) {
    s.qd_radps = d.qd_radps->middleRows(from, len);
    s.qdd_radps2 = d.qdd_radps2->middleRows(from, len);
    return s;
  }
  if (o.use_recorded_derivatives && d.qd_radps) {  // recorded velocities only: differentiate them
    s.qd_radps = d.qd_radps->middleRows(from, len);
    Eigen::MatrixXd qd = s.qd_radps;
    if (prefilter) qd = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), qd);
    s.qdd_radps2 = differentiate(qd, dt, Differentiation::kCentral4);
    return s;
  }
  Eigen::MatrixXd q = s.q_rad;
  if (prefilter) q = filtfilt(butterworthLowpass(4, o.derivative_cutoff_hz, fs), q);
  s.qd_radps = differentiate(q, dt, Differentiation::kCentral4);
  s.qdd_radps2 = differentiate(s.qd_radps, dt, Differentiation::kCentral4);
  return s;
}

}  // namespace

Eigen::Index parallelBlockMargin(const SignalOptions& o, double sample_rate_hz) {
  // Long enough for the filters' response to a block's own edges to die out before the rows it
  // keeps: a Butterworth of order N at fc has its slowest poles at -2 pi fc sin(pi / 2N) (+-j ...),
  // so its impulse response decays by e^-46 = 1e-20 in 46 / (2 pi sin(pi / 2N)) periods of fc:
  // 10.4 at order 2 (the default), 19.1 at 4 (the derivative pre-filter), 37.5 at 8.
  const auto periods = [](int order) { return 46.0 / (2.0 * M_PI * std::sin(M_PI / (2.0 * order))); };
  double samples = 0.0;
  if (o.filter) samples = periods(o.filter_order) * sample_rate_hz / o.cutoff_hz;
  if (o.derivative_cutoff_hz > 0.0) samples = std::max(samples, periods(4) * sample_rate_hz / o.derivative_cutoff_hz);
  // Plus the differences' stencils (two samples each side, twice).
  return static_cast<Eigen::Index>(std::ceil(samples)) + 8;
}

JointSignals differentiatedStates(const Dataset& d, const SignalOptions& o) { return differentiatedStates(d, o, 0, d.size()); }

JointSignals differentiatedStates(const Dataset& d, const SignalOptions& o, Eigen::Index from, Eigen::Index to) {
  if (from < 0 || to > d.size() || to - from < 2) {
    throw std::invalid_argument("differentiatedStates: rows [" + core::toText(from) + ", " + core::toText(to) + ") of a record of " +
                                core::toText(d.size()));
  }
  return parallelStates(d, o, 1.0 / d.sampleInterval_s(), from, to);
}

}  // namespace exoid::ident
