#include "exoid/experiments/protocol/band_sensitivity.hpp"

#include "exoid/core/format.hpp"
#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::experiments {

std::optional<BandRefit> refitInAWiderBand(const std::vector<ident::Dataset>& data, const std::vector<ident::SignalOptions>& signals,
                                           const std::vector<std::optional<ident::BandChoice>>& bands, bool derivative_follows,
                                           const ident::Robot& robot, const ident::RecordRows& fitted) {
  if (std::none_of(bands.begin(), bands.end(), [](const auto& b) { return b.has_value(); })) return std::nullopt;
  if (fitted.record_rows.size() != data.size()) throw std::invalid_argument("band sensitivity: the fitted rows are not one record each");
  BandRefit out;
  // A log longer than its band's pilot window is compared on that window: a bias's shift does not
  // shrink with the record's length, and the window keeps a long log's second pass as cheap as its pilot.
  bool windowed = false;
  std::vector<ident::RecordRows> wide;
  std::vector<Eigen::Index> narrow_rows;  // rows of `fitted` in the comparison
  const Eigen::Index dof = fitted.dof;
  Eigen::Index first_sample = 0;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const Eigen::Index n = data[k].size(), samples = fitted.record_rows[k] / dof;
    const Eigen::Index m = std::min(n, bands[k] ? bands[k]->pilot_samples : ident::BandRule{}.pilot_max_samples);
    const bool window = m > 0 && m < n;
    windowed = windowed || window;
    std::optional<ident::Dataset> central;  // a window's copy; a whole record is read in place
    if (window) central = data[k].window((n - m) / 2, m);
    const ident::Dataset& d = central ? *central : data[k];
    wide.push_back(ident::processRecord(d, robot, widerBand(signals[k], bands[k], derivative_follows, 1.0 / d.sampleInterval_s(), out.factor)));
    for (Eigen::Index i = first_sample; i < first_sample + samples; ++i) {
      const double t = fitted.states.t_s[i];
      if (window && (t < d.t_s[0] || t > d.t_s[d.size() - 1])) continue;
      for (Eigen::Index j = 0; j < dof; ++j) narrow_rows.push_back(i * dof + j);
    }
    first_sample += samples;
  }
  ident::LsOptions lo;
  lo.max_condition = std::numeric_limits<double>::max();
  const ident::RecordRows w = ident::stackRecords(wide);
  out.wider = ident::solveLeastSquares(w.W, w.y, lo).x;
  if (windowed) out.narrow = ident::solveLeastSquares(fitted.W(narrow_rows, Eigen::all), fitted.y(narrow_rows), lo).x;
  return out;
}

ident::SignalOptions widerBand(const ident::SignalOptions& used, const std::optional<ident::BandChoice>& band, bool derivative_follows,
                               double fs_hz, double factor) {
  ident::SignalOptions o = used;
  if (!band) return o;
  o.cutoff_hz = std::min(o.cutoff_hz * factor, 0.2 * fs_hz);
  if (derivative_follows) o.derivative_cutoff_hz = ident::derivativeCutoffFor(o.cutoff_hz, fs_hz);
  return o;
}

BandSensitivity bandSensitivity(const BandRefit& refit, const ident::Robot& robot, const Eigen::VectorXd& x, const Eigen::VectorXd& std_err) {
  BandSensitivity out;
  out.factor = refit.factor;
  out.names = robot.names();
  out.on_windows = refit.narrow.has_value();
  const Eigen::VectorXd& base = refit.narrow ? *refit.narrow : x;
  out.shift_se.resize(refit.wider.size());
  for (Eigen::Index i = 0; i < refit.wider.size(); ++i) {
    const double se = std_err[i], change = refit.wider[i] - base[i];
    // A parameter without a finite, positive standard error has no scale to judge a change by.
    out.shift_se[i] = se > 0.0 && std::isfinite(se) ? change / se : 0.0;
    if (std::abs(out.shift_se[i]) > 1.0) out.over_one.push_back(out.names[static_cast<std::size_t>(i)]);
  }
  return out;
}

std::vector<std::string> describe(const BandSensitivity& s) {
  std::string line = "band sensitivity (every record's cutoff x" + fmt(s.factor, 3) + ", LS refitted" +
                     (s.on_windows ? " on the central window its band was chosen on" : "") + "; change in standard errors):";
  for (Eigen::Index i = 0; i < s.shift_se.size(); ++i) line += " " + s.names[static_cast<std::size_t>(i)] + " " + fixed(s.shift_se[i], 2);
  if (s.over_one.empty()) return {line};
  const std::string names = core::joined(s.over_one);
  return {line, "warning: a wider band moves " + names + " by more than one standard error: their errors-in-variables bias may exceed their noise"};
}

nlohmann::json toJson(const BandSensitivity& s) {
  nlohmann::json sh = nlohmann::json::object();
  for (Eigen::Index i = 0; i < s.shift_se.size(); ++i) sh[s.names[static_cast<std::size_t>(i)]] = s.shift_se[i];
  return {{"cutoff_factor", s.factor}, {"shift_standard_errors", sh}, {"over_one_standard_error", s.over_one}, {"on_pilot_windows", s.on_windows}};
}

}  // namespace exoid::experiments
