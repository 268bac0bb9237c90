#include "exoid/ident/signals/base_terms.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace exoid::ident {

namespace {

// Sum of squared held-out torque errors over `folds` contiguous blocks of samples.
double heldOutSquaredError(const RecordRows& rows, Eigen::Index first, int folds) {
  const Eigen::Index samples = rows.samples(), dof = rows.dof;
  LsOptions ls;
  ls.max_condition = std::numeric_limits<double>::max();  // its prediction is judged, not its parameters
  double sse = 0.0;
  for (int k = 0; k < folds; ++k) {
    const Eigen::Index from = samples * k / folds, to = samples * (k + 1) / folds;
    std::vector<Eigen::Index> train, test;
    for (Eigen::Index s = 0; s < samples; ++s) {
      for (Eigen::Index j = first; j < dof; ++j) (s >= from && s < to ? test : train).push_back(s * dof + j);
    }
    const Eigen::VectorXd theta = solveLeastSquares(rows.W(train, Eigen::all), rows.y(train), ls).x;
    sse += (rows.y(test) - rows.W(test, Eigen::all) * theta).squaredNorm();
  }
  return sse;
}

}  // namespace

std::string BaseTermsChoice::describe() const {
  if (folds == 0) return "kept (" + core::toText(samples) + " samples: too few to judge)";
  return std::string(use ? "kept" : "dropped") + ": held-out torque RMS " + core::formatNumber(held_out_rms_with_Nm, 4) + " N m with them, " +
         core::formatNumber(held_out_rms_without_Nm, 4) + " N m without (" + core::toText(folds) + " contiguous blocks)";
}

BaseTermsChoice chooseBaseTerms(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule, int folds) {
  if (!hasBaseColumns(d)) throw std::invalid_argument("chooseBaseTerms: the record has no IMU columns (base_acc_x, base_acc_z, base_gyro_y)");
  if (o.processing != Processing::kParallel) throw std::invalid_argument("chooseBaseTerms: base-motion terms need the parallel processing");
  if (folds < 2) throw std::invalid_argument("chooseBaseTerms: folds must be >= 2, got " + core::toText(folds));
  const Eigen::Index n = rule.pilot_max_samples > 0 ? std::min(d.size(), rule.pilot_max_samples) : d.size();
  const Dataset judged = n == d.size() ? d : d.window((d.size() - n) / 2, n);
  SignalOptions with = o, without = o;
  with.base_terms = BaseTerms::kOn;
  without.base_terms = BaseTerms::kOff;
  const RecordRows rows_with = processRecord(judged, robot, with, rule), rows_without = processRecord(judged, robot, without, rule);
  BaseTermsChoice c;
  c.samples = rows_with.samples();
  const Eigen::Index first = rule.first_moving_joint, equations = robot.dof() - first;
  if (c.samples * equations * (folds - 1) / folds < 2 * static_cast<Eigen::Index>(robot.parameters())) return c;
  c.folds = folds;
  c.equations = c.samples * equations;
  const double count = static_cast<double>(c.equations);
  c.held_out_rms_with_Nm = std::sqrt(heldOutSquaredError(rows_with, first, folds) / count);
  c.held_out_rms_without_Nm = std::sqrt(heldOutSquaredError(rows_without, first, folds) / count);
  c.use = !(c.held_out_rms_with_Nm > c.held_out_rms_without_Nm);
  return c;
}

std::optional<BaseTermsChoice> pooledBaseTerms(const std::vector<std::optional<BaseTermsChoice>>& choices) {
  std::optional<BaseTermsChoice> pooled;
  double with = 0.0, without = 0.0;
  for (const std::optional<BaseTermsChoice>& c : choices) {
    if (!c || c->folds == 0) continue;
    if (!pooled) pooled = BaseTermsChoice{};
    pooled->folds = c->folds;
    pooled->samples += c->samples;
    pooled->equations += c->equations;
    with += c->held_out_rms_with_Nm * c->held_out_rms_with_Nm * static_cast<double>(c->equations);
    without += c->held_out_rms_without_Nm * c->held_out_rms_without_Nm * static_cast<double>(c->equations);
  }
  if (!pooled) return pooled;
  pooled->held_out_rms_with_Nm = std::sqrt(with / static_cast<double>(pooled->equations));
  pooled->held_out_rms_without_Nm = std::sqrt(without / static_cast<double>(pooled->equations));
  pooled->use = !(pooled->held_out_rms_with_Nm > pooled->held_out_rms_without_Nm);
  return pooled;
}

std::optional<BaseTermsChoice> shareBaseTerms(std::vector<SignalOptions>& signals, const std::vector<std::optional<BaseTermsChoice>>& choices) {
  std::optional<bool> first;
  bool differ = false;
  for (const std::optional<BaseTermsChoice>& c : choices) {
    if (!c) continue;
    if (first && *first != c->use) differ = true;
    if (!first) first = c->use;
  }
  if (!differ) return std::nullopt;
  std::optional<BaseTermsChoice> pooled = pooledBaseTerms(choices);
  if (!pooled) return pooled;  // none judged (a choice that drops them always is)
  for (std::size_t k = 0; k < choices.size() && k < signals.size(); ++k) {
    if (choices[k]) signals[k].base_terms = pooled->use ? BaseTerms::kAuto : BaseTerms::kOff;
  }
  return pooled;
}

}  // namespace exoid::ident
