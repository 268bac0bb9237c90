#include "exoid/experiments/protocol/fit_records.hpp"

#include "exoid/experiments/protocol/log_input.hpp"
#include "exoid/experiments/protocol/options.hpp"
#include "exoid/experiments/report/table.hpp"

#include <iostream>
#include <stdexcept>

namespace exoid::experiments {

namespace {

// One record's processing as identify's JSON gives it: cutoffs, decimation, whether the band was
// chosen from the data (then what limited it, the pilot and the consistency scan) and the
// base-motion terms' use (and their choice, when judged).
nlohmann::json recordProcessingJson(const ident::Dataset& d, const ident::SignalOptions& used, const std::optional<ident::BandChoice>& band,
                                    const std::optional<ident::BaseTermsChoice>& base_terms) {
  nlohmann::json b = {{"cutoff_hz", used.cutoff_hz},
                      {"derivative_cutoff_hz", used.derivative_cutoff_hz},
                      {"decimation", used.decimationFactor(1.0 / d.sampleInterval_s())},
                      {"chosen_from_data", band.has_value()},
                      {"base_terms_used", usesBaseMotion(d, used)}};
  if (band) {
    b["motion_bandwidth_hz"] = band->motion_bandwidth_hz;
    b["joint_motion_bandwidth_hz"] =
        std::vector<double>(band->joint_motion_bandwidth_hz.data(), band->joint_motion_bandwidth_hz.data() + band->joint_motion_bandwidth_hz.size());
    b["limited_by"] = band->limited_by;
    b["reason"] = band->describe();
    b["pilot_cutoff_hz"] = band->pilot_cutoff_hz;
    b["pilot_samples"] = band->pilot_samples;  // the pilot's central window (all samples when shorter)
    nlohmann::json scan = nlohmann::json::array();
    for (const ident::BandScan& r : band->scan) {
      scan.push_back({{"from_hz", r.from_hz}, {"to_hz", r.to_hz}, {"predicted_rms_Nm", r.predicted_rms_Nm}, {"measured_rms_Nm", r.measured_rms_Nm}});
    }
    b["consistency_scan"] = scan;
  }
  if (base_terms) b["base_terms_choice"] = toJson(*base_terms);
  return b;
}

}  // namespace

ident::SignalOptions FitRecords::validationSignals(const ident::SignalOptions& given) const {
  ident::SignalOptions o = bands.front() ? ident::withBand(given, *bands.front()) : given;
  o.base_terms = signals.front().base_terms;
  return o;
}

FitRecords processFitRecords(const std::vector<std::string>& files, const std::vector<ident::Dataset>& data, const ident::Robot& robot,
                             const ident::SignalOptions& options, const ident::BandRule& rule, const ident::Robot* band_robot) {
  if (files.size() != data.size() || data.empty()) {
    throw std::invalid_argument("processFitRecords: " + std::to_string(files.size()) + " file names for " + std::to_string(data.size()) +
                                " records (one per record, at least one)");
  }
  const auto naming = [&](std::size_t r, const std::invalid_argument& e) {
    return std::invalid_argument(files[r] + ": " + e.what() + timeUnitHint(data[r]));
  };
  FitRecords out;
  out.bands.resize(data.size());
  out.base_terms.resize(data.size());
  for (std::size_t r = 0; r < data.size(); ++r) {
    try {
      out.signals.push_back(ident::resolveSignalOptions(data[r], band_robot ? *band_robot : robot, options, rule, &out.bands[r], &out.base_terms[r]));
    } catch (const std::invalid_argument& e) {
      throw naming(r, e);
    }
    if (out.bands[r]) {
      std::cout << wrapped(files[r] + ": band: " + out.bands[r]->describe() + " (--cutoff-hz, --derivative-cutoff-hz, --decimation override)") << '\n';
    }
    if (out.base_terms[r]) std::cout << wrapped(files[r] + ": " + baseTermsNote(*out.base_terms[r])) << '\n';
  }
  // Records fitted together take one choice of the base-motion terms.
  out.shared = ident::shareBaseTerms(out.signals, out.base_terms);
  if (out.shared) std::cout << wrapped(sharedBaseTermsNote(*out.shared)) << '\n';
  for (std::size_t r = 0; r < data.size(); ++r) {
    try {
      out.rows.push_back(ident::processRecord(data[r], robot, out.signals[r]));
    } catch (const std::invalid_argument& e) {
      throw naming(r, e);
    }
    out.json[files[r]] = recordProcessingJson(data[r], out.signals[r], out.bands[r], out.base_terms[r]);
    out.json[files[r]]["samples"] = data[r].size();
    out.json[files[r]]["rows"] = out.rows.back().y.size();
  }
  return out;
}

}  // namespace exoid::experiments
