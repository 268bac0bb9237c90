#pragma once
// Small-sample statistics for the sweep summary: mean, sample std, median, Student-t confidence
// intervals, the Wilcoxon signed-rank test for paired comparisons, and the coverage of nominal
// intervals.
#include <vector>

namespace exoid::experiments::stats {

double mean(const std::vector<double>& x);               ///< NaN for an empty sample
double sampleStd(const std::vector<double>& x);          ///< n - 1 denominator; NaN when n < 2
double median(std::vector<double> x);                    ///< mean of the middle two for even n; NaN when empty

/// Regularized incomplete beta function I_x(a, b), a, b > 0, x in [0, 1].
double incompleteBeta(double a, double b, double x);
/// CDF of Student's t with df > 0 degrees of freedom.
double studentTCdf(double t, double df);
/// Quantile of Student's t: studentTCdf(studentTQuantile(p, df), df) = p, p in (0, 1).
double studentTQuantile(double p, double df);

struct ConfidenceInterval {
  int n = 0;
  double mean = 0.0, std = 0.0;  ///< std: sample std (n - 1)
  double low = 0.0, high = 0.0;  ///< mean -+ t_{(1+level)/2, n-1} std / sqrt(n); NaN when n < 2
};
/// Student-t interval of the mean at `level` (e.g. 0.95). NaNs (missing runs) must be removed first.
ConfidenceInterval meanCi(const std::vector<double>& x, double level = 0.95);

/// How often a parameter's nominal 95 % intervals (estimate -+ 1.96 sigma of that run) held the
/// truth over runs, with the Wilson score 95 % interval of that share; and the errors in sigmas:
/// their mean (a bias, in the runs' own sigmas) and their sample std over the mean sigma (1 when
/// sigma is the scatter). NaN where undefined (no runs; the std needs 2).
struct Coverage {
  int n = 0;  ///< runs with a finite error and a finite positive sigma
  double share = 0.0, low = 0.0, high = 0.0;
  double mean_error_over_sigma = 0.0;
  double sd_over_mean_sigma = 0.0;
};
/// errors[k] = estimate - truth and sigmas[k] of run k (same size; pairs without a finite error or a
/// finite positive sigma are skipped).
Coverage coverageOf(const std::vector<double>& errors, const std::vector<double>& sigmas);

struct WilcoxonResult {
  int n_used = 0;        ///< pairs with a non-zero difference
  double w_plus = 0.0;   ///< sum of ranks of positive differences (x - y > 0)
  double p_value = 1.0;  ///< two-sided
  bool exact = false;    ///< exact null distribution (n_used <= 25, no ties) vs normal approximation
};
/// Wilcoxon signed-rank test of x - y (paired, same length). Zero differences are dropped
/// (Wilcoxon's method); tied |differences| get average ranks. Exact two-sided p for n_used <= 25
/// without ties, else the normal approximation with tie and continuity corrections.
/// Throws std::invalid_argument on different lengths.
WilcoxonResult wilcoxonSignedRank(const std::vector<double>& x, const std::vector<double>& y);

/// Holm-Bonferroni adjusted p-values of a family of tests (same order as `p`): sort ascending,
/// p_(i) * (m - i + 1) (i from 1), made monotone by a running maximum, capped at 1. NaNs are
/// left out of the family and stay NaN.
std::vector<double> holmAdjust(const std::vector<double>& p);

/// Minimal detectable mean paired difference at two-sided level alpha and the given power for
/// n pairs whose differences have sample std sd: (t_{1-alpha/2, n-1} + t_{power, n-1}) sd / sqrt(n)
/// (the paired t test's; the Wilcoxon test is at least 86.4 % as efficient for any
/// distribution, 95.5 % for normal differences). NaN when n < 2.
double minimalDetectableDifference(double sd, int n, double alpha = 0.05, double power = 0.8);

}  // namespace exoid::experiments::stats
