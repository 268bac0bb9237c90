#include "exoid/ident/band.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/least_squares.hpp"
#include "exoid/ident/params.hpp"
#include "exoid/ident/segmental.hpp"
#include "exoid/ident/spectrum.hpp"
#include "exoid/ident/standard_errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace exoid::ident {

void BandRule::validate() const {
  auto need = [](bool ok, const char* field, const char* range, double v) {
    if (!ok || !std::isfinite(v)) throw std::invalid_argument(std::string("'") + field + "' must be " + range + ", got " + core::toText(v));
  };
  need(motion_fraction > 0.5 && motion_fraction < 1.0, "motion_fraction", "in (0.5, 1)", motion_fraction);
  need(ladder_ratio > 1.0 && ladder_ratio <= 4.0, "ladder_ratio", "in (1, 4]", ladder_ratio);
  need(max_factor >= 1.0, "max_factor", ">= 1", max_factor);
  need(max_shift_se > 0.0, "max_shift_se", "> 0", max_shift_se);
  need(derivative_factor >= 2.0, "derivative_factor", ">= 2", derivative_factor);
}

std::string BandChoice::describe() const {
  std::ostringstream s;
  s << "motion up to " << core::formatNumber(motion_bandwidth_hz, 3) << " Hz (hip " << core::formatNumber(joint_motion_bandwidth_hz[0], 3)
    << ", knee " << core::formatNumber(joint_motion_bandwidth_hz[1], 3) << " Hz: " << core::formatNumber(100.0 * motion_fraction, 4)
    << " % of the angles' variance); ";
  if (!ladder.empty() && ladder.front().cutoff_hz > motion_bandwidth_hz * (1.0 + 1e-9)) {
    s << "the record's length allows no band below " << core::formatNumber(record_floor_hz, 3)
      << " Hz (the filter's edge trims must leave half of it); ";
  }
  if (limited_by == "drift" && !ladder.empty()) {
    const BandRung& r = ladder.back();
    s << "at " << core::formatNumber(r.cutoff_hz, 3) << " Hz " << paramName(r.worst_param) << " moves "
      << core::formatNumber(r.max_shift_se, 3) << " standard errors from its estimate at "
      << core::formatNumber(ladder.front().cutoff_hz, 3)
      << " Hz (a wider band lets in content the torque does not follow: errors-in-variables), so no wider";
  } else if (limited_by == "cap") {
    s << "estimates stable within " << core::formatNumber(max_shift_se, 3) << " standard error up to the cap of "
      << core::formatNumber(max_factor, 3) << "x the motion's bandwidth";
  } else {
    s << "limited by the sampling rate";
  }
  s << ": torque and columns filtered at " << core::formatNumber(cutoff_hz, 3) << " Hz, angles pre-filtered at "
    << core::formatNumber(derivative_cutoff_hz, 3) << " Hz before differentiating, every " << decimation << ". row kept";
  return s.str();
}

namespace {

// The frequency below which `fraction` of x's mean-removed variance lies (Welch, DC left out;
// linear within a bin).
double bandwidthAt(const Eigen::VectorXd& x, double fs, double fraction) {
  const PowerSpectrum p = welchPsd(x, fs, WelchOptions{});
  const Eigen::Index n = p.density.size();
  const double total = p.density.tail(n - 1).sum();
  if (!(total > 0.0)) return p.df_Hz;  // constant: no motion to speak of
  double cum = 0.0;
  for (Eigen::Index k = 1; k < n; ++k) {
    const double next = cum + p.density[k];
    if (next >= fraction * total) {  // bin k covers [f_k - df/2, f_k + df/2]
      const double share = (fraction * total - cum) / p.density[k];
      return p.frequency_Hz[k] - 0.5 * p.df_Hz + share * p.df_Hz;
    }
    cum = next;
  }
  return p.frequency_Hz[n - 1];
}

SignalOptions atCutoff(const SignalOptions& base, double cutoff_hz, double derivative_factor, double fs) {
  SignalOptions o = base;
  o.processing = Processing::kParallel;
  o.cutoff_from_data = o.derivative_cutoff_from_data = false;
  o.cutoff_hz = cutoff_hz;
  if (base.derivative_cutoff_from_data) {
    o.derivative_cutoff_hz = derivative_factor * cutoff_hz < 0.5 * fs ? derivative_factor * cutoff_hz : 0.0;
  }
  return o;
}

BandRung rung(const Dataset& d, const LegConstants& c, const SignalOptions& o) {
  const SegmentalProblem p = bothEquations(processRecord(d, c, o));
  LsOptions ls;
  ls.max_condition = std::numeric_limits<double>::max();  // judged by the caller, not here
  const LsResult fit = solveLeastSquares(p.H, p.y, ls);
  BandRung r;
  r.cutoff_hz = o.cutoff_hz;
  r.x = fit.x;
  r.std_err = residualCovariance(p.H, p.y - p.H * fit.x, interleavedChannels(p.H.rows())).diagonal().cwiseSqrt();
  for (Eigen::Index u : fit.unidentifiable) r.std_err[u] = std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace

BandChoice chooseBand(const Dataset& d, const LegConstants& c, const SignalOptions& base, const BandRule& rule) {
  rule.validate();
  const double fs = 1.0 / d.sampleInterval_s();
  if (!(fs >= 20.0) || !std::isfinite(fs)) {
    std::ostringstream msg;
    msg << "the record is sampled at " << fs << " Hz: too slow to resolve a motion and choose a band from it (at least "
           "20 Hz); a log sampled that slowly usually has its time column in ms or us (--time-unit ms)";
    throw std::invalid_argument(msg.str());
  }
  SignalOptions probe = base;  // the rate's own checks (e.g. a time column in another unit), any cutoff below it
  probe.cutoff_hz = 0.1 * fs;
  probe.validateFor(fs);
  BandChoice out;
  out.motion_fraction = rule.motion_fraction;
  out.max_factor = rule.max_factor;
  out.max_shift_se = rule.max_shift_se;
  for (int j = 0; j < 2; ++j) out.joint_motion_bandwidth_hz[j] = bandwidthAt(d.q_rad.col(j), fs, rule.motion_fraction);
  out.motion_bandwidth_hz = out.joint_motion_bandwidth_hz.maxCoeff();
  // After decimation by at least 1 the cutoff must stay 2.5 samples per period below fs.
  const double ceiling = 0.2 * fs;
  // The filter's edge trims (3 / cutoff at each end) must leave at least half the record.
  const double floor_hz = 12.0 * fs / static_cast<double>(d.size());
  if (floor_hz > ceiling) {
    throw std::invalid_argument("record too short to choose a band: " + core::toText(d.size()) +
                                " samples; give --cutoff-hz (at least " + core::formatNumber(floor_hz, 3) + " Hz would be needed)");
  }
  out.record_floor_hz = floor_hz;
  const double first = std::clamp(out.motion_bandwidth_hz, floor_hz, ceiling);
  const double cap = std::clamp(rule.max_factor * out.motion_bandwidth_hz, first, ceiling);
  out.limited_by = cap < rule.max_factor * out.motion_bandwidth_hz ? "nyquist" : "cap";
  out.cutoff_hz = first;
  for (double fc = first;; fc = std::min(fc * rule.ladder_ratio, cap)) {
    BandRung r = rung(d, c, atCutoff(base, fc, rule.derivative_factor, fs));
    if (!out.ladder.empty()) {
      const BandRung& f = out.ladder.front();
      for (Eigen::Index i = 0; i < r.x.size(); ++i) {
        if (!std::isfinite(r.std_err[i]) || !std::isfinite(f.std_err[i])) continue;  // not identifiable: no say
        // A change at rounding level is no change (exact data: both the change and the standard
        // error are rounding, and their ratio means nothing).
        const double change = std::abs(r.x[i] - f.x[i]);
        if (change <= 1e-9 * std::max(std::abs(r.x[i]), std::abs(f.x[i]))) continue;
        const double shift = change / r.std_err[i];
        if (shift > r.max_shift_se) {
          r.max_shift_se = shift;
          r.worst_param = static_cast<int>(i);
        }
      }
    }
    out.ladder.push_back(r);
    if (r.max_shift_se > rule.max_shift_se) {
      out.limited_by = "drift";
      break;
    }
    out.cutoff_hz = fc;
    if (fc >= cap) break;
  }
  const SignalOptions chosen = atCutoff(base, out.cutoff_hz, rule.derivative_factor, fs);
  out.derivative_cutoff_hz = chosen.derivative_cutoff_hz;
  out.decimation = chosen.decimationFactor(fs);
  return out;
}

SignalOptions withBand(const SignalOptions& base, const BandChoice& choice) {
  SignalOptions o = base;
  o.cutoff_from_data = o.derivative_cutoff_from_data = false;
  o.cutoff_hz = choice.cutoff_hz;
  if (base.derivative_cutoff_from_data) o.derivative_cutoff_hz = choice.derivative_cutoff_hz;
  return o;
}

}  // namespace exoid::ident
