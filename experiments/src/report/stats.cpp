#include "exoid/experiments/report/stats.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/normal_tail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace exoid::experiments::stats {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Continued fraction of the incomplete beta (Numerical Recipes' betacf, modified Lentz).
double betaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300, kEps = 1e-16;
  const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
  double c = 1.0, d = 1.0 - qab * x / qap;
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < kEps) break;
  }
  return h;
}

double normalCdf(double z) { return core::normalUpperTail(-z); }
}  // namespace

double mean(const std::vector<double>& x) {
  if (x.empty()) return kNaN;
  return std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
}

double median(std::vector<double> x) {
  if (x.empty()) return kNaN;
  std::sort(x.begin(), x.end());
  const std::size_t h = x.size() / 2;
  return x.size() % 2 ? x[h] : 0.5 * (x[h - 1] + x[h]);
}

double sampleStd(const std::vector<double>& x) {
  if (x.size() < 2) return kNaN;
  const double m = mean(x);
  double s = 0.0;
  for (double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size() - 1));
}

double incompleteBeta(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !(x >= 0.0 && x <= 1.0)) {
    throw std::invalid_argument("incompleteBeta: expected a, b > 0 and x in [0, 1], got a = " + core::toText(a) +
                                ", b = " + core::toText(b) + ", x = " + core::toText(x));
  }
  if (x == 0.0 || x == 1.0) return x;
  const double lbeta = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b);
  const double front = std::exp(lbeta + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * betaContinuedFraction(a, b, x) / a;
  return 1.0 - front * betaContinuedFraction(b, a, 1.0 - x) / b;
}

double studentTCdf(double t, double df) {
  if (!(df > 0.0)) throw std::invalid_argument("studentTCdf: df must be > 0, got " + core::toText(df));
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double tail = 0.5 * incompleteBeta(0.5 * df, 0.5, df / (df + t * t));  // P(T > |t|)
  return t >= 0.0 ? 1.0 - tail : tail;
}

double studentTQuantile(double p, double df) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("studentTQuantile: p must be in (0, 1), got " + core::toText(p));
  if (p == 0.5) return 0.0;
  // Bracket, then bisect to full precision (the CDF is monotone; ~100 halvings at most).
  double lo = 0.0, hi = 1.0;
  const double target = std::max(p, 1.0 - p);
  while (studentTCdf(hi, df) < target) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentTCdf(mid, df) < target ? lo : hi) = mid;
  }
  const double q = 0.5 * (lo + hi);
  return p > 0.5 ? q : -q;
}

Coverage coverageOf(const std::vector<double>& errors, const std::vector<double>& sigmas) {
  constexpr double kZ = 1.959963984540054;  // the normal's 97.5 % quantile
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> e, z, s;
  int held = 0;
  for (std::size_t k = 0; k < errors.size() && k < sigmas.size(); ++k) {
    if (!std::isfinite(errors[k]) || !std::isfinite(sigmas[k]) || !(sigmas[k] > 0.0)) continue;
    e.push_back(errors[k]);
    s.push_back(sigmas[k]);
    z.push_back(errors[k] / sigmas[k]);
    if (std::abs(z.back()) <= kZ) ++held;
  }
  Coverage c;
  c.n = static_cast<int>(e.size());
  if (c.n == 0) return {0, nan, nan, nan, nan, nan};
  const double n = c.n, p = held / n, z2 = kZ * kZ;
  c.share = p;
  // Wilson's score interval: the binomial share's interval that stays inside [0, 1] and keeps its
  // level near 0 and 1, where the normal approximation's does not.
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = kZ / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  c.low = std::max(0.0, centre - half);
  c.high = std::min(1.0, centre + half);
  c.mean_error_over_sigma = mean(z);
  c.sd_over_mean_sigma = sampleStd(e) / mean(s);
  return c;
}

ConfidenceInterval meanCi(const std::vector<double>& x, double level) {
  ConfidenceInterval ci;
  ci.n = static_cast<int>(x.size());
  ci.mean = mean(x);
  ci.std = sampleStd(x);
  if (ci.n < 2) {
    ci.low = ci.high = kNaN;
    return ci;
  }
  const double half = studentTQuantile(0.5 * (1.0 + level), ci.n - 1.0) * ci.std / std::sqrt(static_cast<double>(ci.n));
  ci.low = ci.mean - half;
  ci.high = ci.mean + half;
  return ci;
}

WilcoxonResult wilcoxonSignedRank(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) {
    throw std::invalid_argument("wilcoxonSignedRank: expected samples of equal length, got " + core::toText(x.size()) +
                                " and " + core::toText(y.size()));
  }
  std::vector<double> d;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] - y[i] != 0.0) d.push_back(x[i] - y[i]);
  }
  WilcoxonResult r;
  r.n_used = static_cast<int>(d.size());
  const std::size_t n = d.size();
  if (n == 0) return r;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(d[a]) < std::abs(d[b]); });
  std::vector<double> rank(n);
  bool ties = false;
  double tie_term = 0.0;  // sum of t^3 - t over tie groups
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j + 1 < n && std::abs(d[order[j + 1]]) == std::abs(d[order[i]])) ++j;
    const double avg = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) rank[order[k]] = avg;
    const double t = static_cast<double>(j - i + 1);
    if (t > 1) ties = true;
    tie_term += t * t * t - t;
    i = j + 1;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (d[i] > 0) r.w_plus += rank[i];
  }
  const double nn = static_cast<double>(n);
  const double mu = nn * (nn + 1.0) / 4.0;
  if (n <= 25 && !ties) {
    // Exact null: counts of subsets of {1..n} by rank sum (2^n equally likely sign patterns).
    const int max_sum = static_cast<int>(n * (n + 1) / 2);
    std::vector<double> count(static_cast<std::size_t>(max_sum) + 1, 0.0);
    count[0] = 1.0;
    for (int k = 1; k <= static_cast<int>(n); ++k) {
      for (int s = max_sum; s >= k; --s) count[static_cast<std::size_t>(s)] += count[static_cast<std::size_t>(s - k)];
    }
    const double total = std::ldexp(1.0, static_cast<int>(n));
    const double w = std::min(r.w_plus, nn * (nn + 1.0) / 2.0 - r.w_plus);  // smaller tail
    double tail = 0.0;
    for (int s = 0; s <= static_cast<int>(std::floor(w + 1e-9)); ++s) tail += count[static_cast<std::size_t>(s)];
    r.p_value = std::min(1.0, 2.0 * tail / total);
    r.exact = true;
    return r;
  }
  const double var = nn * (nn + 1.0) * (2.0 * nn + 1.0) / 24.0 - tie_term / 48.0;
  if (var <= 0.0) return r;
  const double z = (std::abs(r.w_plus - mu) - 0.5) / std::sqrt(var);
  r.p_value = std::min(1.0, 2.0 * (1.0 - normalCdf(std::max(z, 0.0))));
  return r;
}

std::vector<double> holmAdjust(const std::vector<double>& p) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isnan(p[i])) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&p](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> out(p.size(), std::numeric_limits<double>::quiet_NaN());
  const double m = static_cast<double>(order.size());
  double running = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(running, std::min(1.0, p[order[k]] * (m - static_cast<double>(k))));
    out[order[k]] = running;
  }
  return out;
}

double minimalDetectableDifference(double sd, int n, double alpha, double power) {
  if (n < 2 || !std::isfinite(sd)) return std::numeric_limits<double>::quiet_NaN();
  const double df = n - 1.0;
  return (studentTQuantile(1.0 - alpha / 2.0, df) + studentTQuantile(power, df)) * sd / std::sqrt(static_cast<double>(n));
}

}  // namespace exoid::experiments::stats
