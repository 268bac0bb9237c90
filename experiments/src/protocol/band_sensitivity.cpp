#include "exoid/experiments/protocol/band_sensitivity.hpp"

#include "exoid/experiments/report/table.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace exoid::experiments {

std::optional<BandSensitivity> bandSensitivity(const std::vector<ident::Dataset>& data, const std::vector<ident::SignalOptions>& signals,
                                               const std::vector<std::optional<ident::BandChoice>>& bands, bool derivative_follows,
                                               const ident::Robot& robot, const Eigen::VectorXd& x, const Eigen::VectorXd& std_err) {
  if (std::none_of(bands.begin(), bands.end(), [](const auto& b) { return b.has_value(); })) return std::nullopt;
  BandSensitivity out;
  out.factor = 1.25;  // a quarter wider
  out.names = robot.names();
  std::vector<ident::RecordRows> rows;
  for (std::size_t k = 0; k < data.size(); ++k) {
    ident::SignalOptions o = signals[k];
    if (bands[k]) {
      const double fs = 1.0 / data[k].sampleInterval_s();
      o.cutoff_hz = std::min(o.cutoff_hz * out.factor, 0.2 * fs);
      if (derivative_follows) o.derivative_cutoff_hz = ident::derivativeCutoffFor(o.cutoff_hz, fs);
    }
    rows.push_back(ident::processRecord(data[k], robot, o));
  }
  const ident::RecordRows p = ident::stackRecords(rows);
  ident::LsOptions lo;
  lo.max_condition = std::numeric_limits<double>::max();
  const Eigen::VectorXd wider = ident::solveLeastSquares(p.W, p.y, lo).x;
  out.shift_se.resize(wider.size());
  for (Eigen::Index i = 0; i < wider.size(); ++i) {
    const double se = std_err[i], change = wider[i] - x[i];
    // A parameter without a finite, positive standard error has no scale to judge a change by.
    out.shift_se[i] = se > 0.0 && std::isfinite(se) ? change / se : 0.0;
    if (std::abs(out.shift_se[i]) > 1.0) out.over_one.push_back(out.names[static_cast<std::size_t>(i)]);
  }
  return out;
}

std::vector<std::string> describe(const BandSensitivity& s) {
  std::string line = "band sensitivity (every record's cutoff x" + fmt(s.factor, 3) + ", LS refitted; change in standard errors):";
  for (Eigen::Index i = 0; i < s.shift_se.size(); ++i) line += " " + s.names[static_cast<std::size_t>(i)] + " " + fixed(s.shift_se[i], 2);
  if (s.over_one.empty()) return {line};
  std::string names;
  for (const std::string& n : s.over_one) names += (names.empty() ? "" : ", ") + n;
  return {line, "warning: a wider band moves " + names + " by more than one standard error: their errors-in-variables bias may exceed their noise"};
}

nlohmann::json toJson(const BandSensitivity& s) {
  nlohmann::json sh = nlohmann::json::object();
  for (Eigen::Index i = 0; i < s.shift_se.size(); ++i) sh[s.names[static_cast<std::size_t>(i)]] = s.shift_se[i];
  return {{"cutoff_factor", s.factor}, {"shift_standard_errors", sh}, {"over_one_standard_error", s.over_one}};
}

}  // namespace exoid::experiments
