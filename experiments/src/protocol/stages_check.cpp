#include "exoid/experiments/protocol/stages_check.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/normal_tail.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace exoid::experiments {

double bonferroniZ(double significance_sigmas, int tests) {
  const auto tail = core::normalUpperTail;
  const double target = tail(significance_sigmas) / std::max(tests, 1);
  // Never below one test's z; sqrt(2 ln tests) more is enough for any count an int holds.
  double lo = significance_sigmas, hi = significance_sigmas + 10.0;
  for (int k = 0; k < 100; ++k) (tail(0.5 * (lo + hi)) > target ? lo : hi) = 0.5 * (lo + hi);
  return hi;
}

StagesAgainstOneFit compareStagesWithOneFit(const Eigen::VectorXd& stages, const Eigen::VectorXd& stages_se, const Eigen::VectorXd& one_fit,
                                            const Eigen::VectorXd& one_fit_se, double significance_sigmas) {
  const Eigen::Index n = stages.size();
  if (n == 0 || stages_se.size() != n || one_fit.size() != n || one_fit_se.size() != n) {
    throw std::invalid_argument("compareStagesWithOneFit: the estimates and their errors must have the same, non-zero size");
  }
  if (!stages.allFinite() || !stages_se.allFinite() || !one_fit.allFinite() || !one_fit_se.allFinite()) {
    throw std::invalid_argument("compareStagesWithOneFit: every estimate and error must be finite");
  }
  StagesAgainstOneFit c;
  c.one_fit = one_fit;
  c.one_fit_std_error = one_fit_se;
  c.z = (stages - one_fit).cwiseQuotient((stages_se.array().square() + one_fit_se.array().square()).sqrt().matrix());
  c.threshold = bonferroniZ(significance_sigmas, static_cast<int>(n));
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index i, Eigen::Index j) { return std::abs(c.z[i]) > std::abs(c.z[j]); });
  c.largest = order.front();
  for (Eigen::Index i : order) {
    if (std::abs(c.z[i]) > c.threshold) c.beyond.push_back(i);
  }
  return c;
}

bool explainedToRounding(const Eigen::MatrixXd& W, const Eigen::VectorXd& y, const Eigen::VectorXd& x) {
  return (y - W * x).norm() <= std::sqrt(std::numeric_limits<double>::epsilon()) * y.norm();
}

nlohmann::json notJudged(const std::string& why) {
  std::cout << "one fit of the last stage's records: not judged (" << why << ")\n";
  return {{"judged", false}, {"why", why}};
}

std::string describe(const StagesAgainstOneFit& c, const std::vector<std::string>& names) {
  std::string s = "one fit of the last stage's records against the stages: largest difference " + core::formatNumber(std::abs(c.z[c.largest]), 3) +
                  " of both errors (" + names[static_cast<std::size_t>(c.largest)] + "), threshold " + core::formatNumber(c.threshold, 3) +
                  " (Bonferroni of --significance over " + core::toText(c.z.size()) + " parameters)";
  if (!c.beyond.empty()) {
    s += "; beyond it:";
    for (std::size_t k = 0; k < c.beyond.size(); ++k) {
      s += (k ? ", " : " ") + names[static_cast<std::size_t>(c.beyond[k])] + " (" + core::formatNumber(c.z[c.beyond[k]], 3) + ")";
    }
    s += ": the errors do not cover the records' difference (model error that differs between them, or a term an earlier stage absorbed)";
  }
  s += !c.consistency_judged            ? "; the one fit's consistency not judged (--no-consistency)"
       : c.one_fit_inconsistency.empty() ? "; the one fit is physically consistent"
                                         : "; the one fit " + c.one_fit_inconsistency;
  return s;
}

nlohmann::json toJson(const StagesAgainstOneFit& c, const std::vector<std::string>& names) {
  nlohmann::json beyond = nlohmann::json::array();
  for (Eigen::Index i : c.beyond) beyond.push_back(names[static_cast<std::size_t>(i)]);
  return {{"judged", true},
          {"one_fit", std::vector<double>(c.one_fit.data(), c.one_fit.data() + c.one_fit.size())},
          {"one_fit_std_error", std::vector<double>(c.one_fit_std_error.data(), c.one_fit_std_error.data() + c.one_fit_std_error.size())},
          {"z", std::vector<double>(c.z.data(), c.z.data() + c.z.size())},
          {"largest_abs_z", std::abs(c.z[c.largest])},
          {"threshold", c.threshold},
          {"beyond", beyond},
          {"one_fit_consistent", c.consistency_judged ? nlohmann::json(c.one_fit_inconsistency.empty()) : nlohmann::json()},
          {"rule", "z = (stages - one fit) / sqrt(se_stages^2 + se_one_fit^2), named beyond the Bonferroni threshold of --significance over "
                   "the parameters (printed, not an exit code); exit 3 when the one fit is not physically consistent, as its own identify "
                   "judges it (a chain: its nearest consistent body further than the noise explains, by draws about it, or an armature "
                   "the records show; the APAL leg: a physical condition violated beyond --significance)"}};
}

std::string stagesHidProblem(const StagesAgainstOneFit& c, const std::string& hint) {
  if (c.one_fit_inconsistency.empty()) return "";
  return "one fit of the last stage's records " + c.one_fit_inconsistency +
         ": an earlier stage may have absorbed a term the model leaves out (the stages' own consistency need not show it); " +
         (hint.empty() ? std::string("model the missing term (an armature on a joint the model gives none, for one)") : hint);
}

}  // namespace exoid::experiments
