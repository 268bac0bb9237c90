#pragma once
// The segmental strategy's estimate against one fit of its last stage's records (every joint
// moving), on every leg. An earlier stage can absorb a term the model leaves out (a rotor's
// inertia folded into the link it turns by a hip-locked stage; the later stages' parameters then
// take what their equations miss) where no stage's own consistency sees it (docs/findings.md,
// section 11): the one fit of the last records is judged too, and the two estimates compared.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace exoid::experiments {

/// The |z| beyond which `tests` two-sided tests together name a difference as often as one test at
/// `significance_sigmas` does: P(|Z| > z) = P(|Z| > significance) / tests (Bonferroni).
double bonferroniZ(double significance_sigmas, int tests);

struct StagesAgainstOneFit {
  Eigen::VectorXd one_fit, one_fit_std_error;
  /// (stages - one fit) / sqrt(se_stages^2 + se_one_fit^2): the difference's variance is at most
  /// the sum, the records being shared and the errors correlated positively.
  Eigen::VectorXd z;
  double threshold = 0.0;            ///< bonferroniZ(significance, parameters)
  std::vector<Eigen::Index> beyond;  ///< |z| > threshold, largest first
  Eigen::Index largest = 0;
  /// The one fit's physical consistency was judged (not with --no-consistency).
  bool consistency_judged = true;
  /// Why the one fit has no physically consistent body (its own identify would exit 3); empty: it
  /// has, or it was not judged.
  std::string one_fit_inconsistency;
};
/// Throws std::invalid_argument when the sizes differ or an entry is not finite.
StagesAgainstOneFit compareStagesWithOneFit(const Eigen::VectorXd& stages, const Eigen::VectorXd& stages_se, const Eigen::VectorXd& one_fit,
                                            const Eigen::VectorXd& one_fit_se, double significance_sigmas);

/// The one fit explains its records to rounding (||y - W x|| <= sqrt(eps) ||y||: exact data, no
/// term left out, the errors rounding too): nothing to judge.
bool explainedToRounding(const Eigen::MatrixXd& W, const Eigen::VectorXd& y, const Eigen::VectorXd& x);
/// Says on stdout that the check was not made and why; the JSON that records it.
nlohmann::json notJudged(const std::string& why);

/// The printed account (one line, `names` the parameters).
std::string describe(const StagesAgainstOneFit& c, const std::vector<std::string>& names);
nlohmann::json toJson(const StagesAgainstOneFit& c, const std::vector<std::string>& names);
/// identify's exit-3 reason when the one fit has no consistent body (empty when it has): the
/// stages would hide what one fit shows. `hint`: the option that adds the term explaining it, if found.
std::string stagesHidProblem(const StagesAgainstOneFit& c, const std::string& hint);

}  // namespace exoid::experiments
