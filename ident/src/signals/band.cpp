#include "exoid/ident/signals/band.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/parallel_for.hpp"
#include "exoid/ident/signals/spectrum.hpp"

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
  need(pilot_factor >= 1.0, "pilot_factor", ">= 1", pilot_factor);
  need(scan_band_hz > 0.0, "scan_band_hz", "> 0", scan_band_hz);
  need(inconsistency_ratio > 1.0, "inconsistency_ratio", "> 1", inconsistency_ratio);
  need(max_factor >= 1.0, "max_factor", ">= 1", max_factor);
  need(derivative_factor >= 2.0, "derivative_factor", ">= 2", derivative_factor);
  need(first_moving_joint >= 0, "first_moving_joint", ">= 0", static_cast<double>(first_moving_joint));
  need(pilot_max_samples >= 0, "pilot_max_samples", ">= 0", static_cast<double>(pilot_max_samples));
}

double BandScan::ratio() const {
  if (!(measured_rms_Nm > 0.0)) return predicted_rms_Nm > 0.0 ? std::numeric_limits<double>::infinity() : 1.0;
  return predicted_rms_Nm / measured_rms_Nm;
}

std::string BandChoice::describe() const {
  std::ostringstream s;
  s << "motion up to " << core::formatNumber(motion_bandwidth_hz, 3) << " Hz (";
  for (Eigen::Index j = 0; j < joint_motion_bandwidth_hz.size(); ++j) {
    s << (j ? ", " : "") << (static_cast<std::size_t>(j) < joints.size() ? joints[static_cast<std::size_t>(j)] : "joint " + std::to_string(j))
      << " " << core::formatNumber(joint_motion_bandwidth_hz[j], 3);
  }
  s << " Hz: " << core::formatNumber(100.0 * motion_fraction, 4)
    << " % of the angles' variance, pooled); ";
  if (record_floor_hz > motion_bandwidth_hz) {
    s << "the record's length allows no band below " << core::formatNumber(record_floor_hz, 3)
      << " Hz (the filter's edge trims must leave half of it); ";
  }
  if (limited_by == "consistency" && !scan.empty()) {
    s << "from " << core::formatNumber(scan.back().from_hz, 3) << " Hz the states predict " << core::formatNumber(scan.back().ratio(), 3)
      << "x the torque measured (content the torque does not follow: errors-in-variables), so no wider";
  } else if (limited_by == "motion" && !scan.empty()) {
    s << "the states predict " << core::formatNumber(scan.back().ratio(), 3) << "x the torque measured right above "
      << (record_floor_hz > motion_bandwidth_hz ? "the lowest band the record's length allows: the band stops there"
                                                : "the motion: the band stops at the motion's");
  } else if (limited_by == "length") {
    s << "the lowest band the record's length allows is above the cap of " << core::formatNumber(max_factor, 3)
      << "x the motion's bandwidth: the band is that lowest one";
  } else if (limited_by == "cap") {
    s << "the torque follows the states up to the cap of " << core::formatNumber(max_factor, 3) << "x the motion's bandwidth";
  } else {
    s << "limited by the sampling rate";
  }
  if (pilot_samples < samples) {
    s << " (the pilot read the record's central " << pilot_samples << " of " << samples << " samples)";
  }
  s << ": torque and columns filtered at " << core::formatNumber(cutoff_hz, 3) << " Hz, angles pre-filtered at "
    << core::formatNumber(derivative_cutoff_hz, 3) << " Hz before differentiating, every " << decimation << ". row kept";
  return s.str();
}

namespace {

// The frequency below which `fraction` of a spectrum's power lies (DC left out; linear within a
// bin).
double bandwidthAt(const PowerSpectrum& p, double fraction) {
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

double bandPower(const PowerSpectrum& p, double from, double to) {
  double sum = 0.0;
  for (Eigen::Index k = 1; k < p.density.size(); ++k) {
    if (p.frequency_Hz[k] >= from && p.frequency_Hz[k] < to) sum += p.density[k];
  }
  return sum * p.df_Hz;
}

SignalOptions atCutoff(const SignalOptions& base, double cutoff_hz, const BandRule& rule, double fs) {
  SignalOptions o = base;
  o.processing = Processing::kParallel;
  o.cutoff_from_data = o.derivative_cutoff_from_data = false;
  o.cutoff_hz = cutoff_hz;
  if (base.derivative_cutoff_from_data) o.derivative_cutoff_hz = derivativeCutoffFor(cutoff_hz, fs, rule);
  return o;
}

// Each joint's angle spectrum (Welch, default options).
// Each joint's on its own thread (up to `threads`, 0 = the machine's cores), into its own slot.
std::vector<PowerSpectrum> angleSpectra(const Dataset& d, int threads = 0) {
  const double fs = 1.0 / d.sampleInterval_s();
  std::vector<PowerSpectrum> out(static_cast<std::size_t>(d.q_rad.cols()));
  core::parallelFor(out.size(), threads, [&](std::size_t j) { out[j] = welchPsd(d.q_rad.col(static_cast<Eigen::Index>(j)), fs, WelchOptions{}); });
  return out;
}

double pooledBandwidth(const std::vector<PowerSpectrum>& spectra, double fraction) {
  if (!(fraction > 0.5 && fraction < 1.0)) throw std::invalid_argument("motion bandwidth: fraction must be in (0.5, 1), got " + core::toText(fraction));
  PowerSpectrum pooled = spectra.front();
  for (std::size_t j = 1; j < spectra.size(); ++j) pooled.density += spectra[j].density;
  return bandwidthAt(pooled, fraction);
}

}  // namespace

double motionBandwidth(const Dataset& d, double fraction) { return pooledBandwidth(angleSpectra(d), fraction); }

BandChoice chooseBandWith(const Dataset& d, const SignalOptions& base, const BandRule& rule, const PilotFit& pilot_fit) {
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
  out.joints = d.joints;
  const std::vector<PowerSpectrum> angles = angleSpectra(d, base.threads);
  out.joint_motion_bandwidth_hz.resize(d.q_rad.cols());
  for (Eigen::Index j = 0; j < d.q_rad.cols(); ++j) {
    out.joint_motion_bandwidth_hz[j] = bandwidthAt(angles[static_cast<std::size_t>(j)], rule.motion_fraction);
  }
  // The motion's: both angles' power pooled, so a joint held still (its angle is encoder noise,
  // spread up to Nyquist) does not set it.
  out.motion_bandwidth_hz = pooledBandwidth(angles, rule.motion_fraction);
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
  out.limited_by = floor_hz >= rule.max_factor * out.motion_bandwidth_hz ? "length"
                  : cap < rule.max_factor * out.motion_bandwidth_hz                ? "nyquist"
                                                                                    : "cap";
  // The pilot: least squares in a band just wider than the motion.
  const SignalOptions pilot = atCutoff(base, std::min(rule.pilot_factor * first, ceiling), rule, fs);
  out.pilot_cutoff_hz = pilot.cutoff_hz;
  out.samples = d.size();
  out.pilot_samples = d.size();
  if (rule.pilot_max_samples > 0) {
    const double at_least = std::ceil(24.0 * fs / first);
    out.pilot_samples = std::min(d.size(), std::max(rule.pilot_max_samples, static_cast<Eigen::Index>(std::min(at_least, 1e15))));
  }
  const PilotTorques torques = out.pilot_samples == d.size()
                                   ? pilot_fit(d, pilot)
                                   : pilot_fit(d.window((d.size() - out.pilot_samples) / 2, out.pilot_samples), pilot);
  // Every joint's predicted and measured torque spectrum on its own thread, summed in joint order.
  const Eigen::Index joints = torques.predicted_Nm.cols();
  std::vector<PowerSpectrum> spectra(static_cast<std::size_t>(2 * joints));
  core::parallelFor(spectra.size(), base.threads, [&](std::size_t k) {
    const Eigen::MatrixXd& torque = k % 2 == 0 ? torques.predicted_Nm : torques.measured_Nm;
    spectra[k] = welchPsd(torque.col(static_cast<Eigen::Index>(k / 2)), fs, WelchOptions{});
  });
  PowerSpectrum predicted = spectra[0], measured = spectra[1];
  for (Eigen::Index j = 1; j < joints; ++j) {
    predicted.density += spectra[static_cast<std::size_t>(2 * j)].density;
    measured.density += spectra[static_cast<std::size_t>(2 * j + 1)].density;
  }
  out.cutoff_hz = cap;
  for (double from = first; from < cap - 1e-9; from += rule.scan_band_hz) {
    BandScan b;
    b.from_hz = from;
    b.to_hz = std::min(from + rule.scan_band_hz, cap);  // nothing above the cap has a say
    b.predicted_rms_Nm = std::sqrt(bandPower(predicted, b.from_hz, b.to_hz));
    b.measured_rms_Nm = std::sqrt(bandPower(measured, b.from_hz, b.to_hz));
    out.scan.push_back(b);
    if (b.ratio() > rule.inconsistency_ratio) {
      out.cutoff_hz = from;
      out.limited_by = from <= first + 1e-9 ? "motion" : "consistency";
      break;
    }
  }
  const SignalOptions chosen = atCutoff(base, out.cutoff_hz, rule, fs);
  out.derivative_cutoff_hz = chosen.derivative_cutoff_hz;
  out.decimation = chosen.decimationFactor(fs);
  return out;
}

double derivativeCutoffFor(double cutoff_hz, double sample_rate_hz, const BandRule& rule) {
  const double fd = rule.derivative_factor * cutoff_hz;
  return fd < 0.5 * sample_rate_hz ? fd : 0.0;
}

SignalOptions withBand(const SignalOptions& base, const BandChoice& choice) {
  SignalOptions o = base;
  o.cutoff_from_data = o.derivative_cutoff_from_data = false;
  o.cutoff_hz = choice.cutoff_hz;
  if (base.derivative_cutoff_from_data) o.derivative_cutoff_hz = choice.derivative_cutoff_hz;
  return o;
}

}  // namespace exoid::ident
