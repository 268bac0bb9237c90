// Differentiation and Butterworth zero-phase filtering (ports of scipy.signal's butter, sosfilt,
// sosfilt_zi and sosfiltfilt; see signals.hpp).
#include "exoid/ident/signals/signals.hpp"

#include "exoid/core/format.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::ident {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxOrder = 12;
// Columns filtered together: the per-sample recursion of a block of columns is independent
// across columns, so the compiler can run the block in one SIMD register.
constexpr int kLanes = 4;
using Lanes = Eigen::Array<double, kLanes, 1>;

// --- Butterworth design --------------------------------------------------------------------

struct Pole {
  Complex value;
  bool real;  // a real pole; otherwise `value` stands for the pair (value, conj(value))
};

// Index of the pole closest to the unit circle (scipy's idx_worst; first one on ties).
template <typename Pred>
std::size_t worstPole(const std::vector<Pole>& p, Pred keep) {
  std::size_t best = p.size();
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double distance = std::abs(1.0 - std::abs(p[i].value));
    if (keep(p[i]) && distance < best_distance) {
      best = i;
      best_distance = distance;
    }
  }
  return best;
}

// Index of the (real) zero nearest to `to` (scipy's _nearest_real_complex_idx).
std::size_t nearestZero(const std::vector<double>& z, Complex to) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < z.size(); ++i) {
    if (std::abs(z[i] - to) < std::abs(z[best] - to)) best = i;
  }
  return best;
}

// One section [b0 b1 b2 1 a1 a2] with unit gain from two zeros and two poles (scipy's
// _single_zpksos with both lists of length 2).
void setSection(double* row, double z1, double z2, Complex p1, Complex p2) {
  const Complex a1 = -(p1 + p2);
  const Complex a2 = p1 * p2;
  row[0] = 1.0;
  row[1] = -(z1 + z2);
  row[2] = z1 * z2;
  row[3] = 1.0;
  row[4] = a1.real();
  row[5] = a2.real();
}

// --- filtering ------------------------------------------------------------------------------

void validateSos(const SosFilter& f) {
  if (f.sections() < 1) throw std::invalid_argument("SosFilter must have at least 1 section, got 0");
  for (Eigen::Index s = 0; s < f.sections(); ++s) {
    for (Eigen::Index k = 0; k < 6; ++k) {
      if (!std::isfinite(f.sos(s, k))) {
        throw std::invalid_argument("sos(" + core::toText(s) + ", " + core::toText(k) +
                                    ") must be finite, got " + core::formatNumber(f.sos(s, k), 12));
      }
    }
    if (f.sos(s, 3) != 1.0) {
      throw std::invalid_argument("sos(" + core::toText(s) + ", 3) (a0 of section " + core::toText(s) +
                                  ") must be 1, got " + core::formatNumber(f.sos(s, 3), 12));
    }
  }
}

// scipy.signal.sosfilt_zi: the state of each section (direct form II transposed) in steady
// state for a unit step at the cascade's input. Section s sees a step of the DC gain of the
// sections before it; with g = H_s(1), y = g, z0 = y - b0 and z1 = b2 - a2 y.
std::vector<double> steadyStateZi(const SosFilter& f) {
  std::vector<double> zi(static_cast<std::size_t>(2 * f.sections()));
  double scale = 1.0;
  for (Eigen::Index s = 0; s < f.sections(); ++s) {
    const double b0 = f.sos(s, 0), b1 = f.sos(s, 1), b2 = f.sos(s, 2);
    const double a1 = f.sos(s, 4), a2 = f.sos(s, 5);
    const double a_sum = 1.0 + a1 + a2;
    if (a_sum == 0.0) {
      throw std::invalid_argument("section " + core::toText(s) +
                                  " has a pole at z = 1 (1 + a1 + a2 = 0): no steady state");
    }
    const double g = (b0 + b1 + b2) / a_sum;
    zi[static_cast<std::size_t>(2 * s)] = scale * (g - b0);
    zi[static_cast<std::size_t>(2 * s + 1)] = scale * (b2 - a2 * g);
    scale *= g;
  }
  return zi;
}

// Runs the cascade over `rows` interleaved rows of kLanes values (buf[row * kLanes + lane]) in
// place, forwards or backwards, from and into `state` (per section: z0, then z1).
void runCascade(const SosFilter& f, Lanes* state, double* buf, Eigen::Index rows, bool backwards) {
  const Eigen::Index sections = f.sections();
  const double* coeffs = f.sos.data();  // row-major: section s at coeffs[6 s]
  for (Eigen::Index i = 0; i < rows; ++i) {
    double* row = buf + (backwards ? rows - 1 - i : i) * kLanes;
    Lanes x = Lanes::Map(row);
    for (Eigen::Index s = 0; s < sections; ++s) {
      const double* c = coeffs + 6 * s;
      Lanes& z0 = state[2 * s];
      Lanes& z1 = state[2 * s + 1];
      const Lanes y = c[0] * x + z0;
      z0 = c[1] * x - c[4] * y + z1;
      z1 = c[2] * x - c[5] * y;
      x = y;
    }
    Lanes::Map(row) = x;
  }
}

// scipy.signal.sosfiltfilt's default pad length: 3 * ntaps, ntaps = 2 * sections + 1 less the
// number of sections that are really first order (min of the counts of b2 == 0 and a2 == 0).
Eigen::Index padLength(const SosFilter& f) {
  const Eigen::Index b2_zero = (f.sos.col(2).array() == 0.0).count();
  const Eigen::Index a2_zero = (f.sos.col(5).array() == 0.0).count();
  return 3 * (2 * f.sections() + 1 - std::min(b2_zero, a2_zero));
}

}  // namespace

const char* toString(Differentiation d) {
  switch (d) {
    case Differentiation::kForward: return "forward";
    case Differentiation::kCentral: return "central";
    case Differentiation::kCentral4: return "central4";
  }
  return "unknown";
}

Eigen::MatrixXd differentiate(const Eigen::MatrixXd& x, double dt_s, Differentiation method) {
  if (x.rows() < 2) {
    throw std::invalid_argument("x must have at least 2 rows (samples), got " + core::toText(x.rows()));
  }
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    throw std::invalid_argument("dt_s must be positive and finite, got " + core::formatNumber(dt_s, 12));
  }
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd dx(n, x.cols());
  switch (method) {
    case Differentiation::kForward:
      dx.topRows(n - 1) = (x.bottomRows(n - 1) - x.topRows(n - 1)) / dt_s;
      break;
    case Differentiation::kCentral:
      dx.row(0) = (x.row(1) - x.row(0)) / dt_s;
      if (n > 2) dx.middleRows(1, n - 2) = (x.bottomRows(n - 2) - x.topRows(n - 2)) / (2.0 * dt_s);
      break;
    case Differentiation::kCentral4:
      dx.row(0) = (x.row(1) - x.row(0)) / dt_s;
      if (n > 2) dx.middleRows(1, n - 2) = (x.bottomRows(n - 2) - x.topRows(n - 2)) / (2.0 * dt_s);
      if (n > 4) {
        dx.middleRows(2, n - 4) = (x.topRows(n - 4) - 8.0 * x.middleRows(1, n - 4) + 8.0 * x.middleRows(3, n - 4) -
                                   x.bottomRows(n - 4)) / (12.0 * dt_s);
      }
      break;
    default:
      throw std::invalid_argument("unknown Differentiation method " +
                                  core::toText(static_cast<int>(method)));
  }
  dx.row(n - 1) = (x.row(n - 1) - x.row(n - 2)) / dt_s;
  return dx;
}

namespace {

void validateButterworth(int order, double cutoff_hz, double sample_rate_hz) {
  if (order < 1 || order > kMaxOrder) {
    throw std::invalid_argument("order must be in [1, " + core::toText(kMaxOrder) + "], got " +
                                core::toText(order));
  }
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz)) {
    throw std::invalid_argument("sample_rate_hz must be positive and finite, got " + core::formatNumber(sample_rate_hz, 12));
  }
  const double nyquist_hz = sample_rate_hz / 2.0;
  if (!(cutoff_hz > 0.0 && cutoff_hz < nyquist_hz)) {
    throw std::invalid_argument("cutoff_hz must be in (0, " + core::formatNumber(nyquist_hz, 12) + ") Hz, got " +
                                core::formatNumber(cutoff_hz, 12));
  }
}

struct DigitalZpk {
  std::vector<Pole> poles;
  std::vector<double> zeros;
};

// scipy.signal.iirfilter: normalise to fs = 2, prewarp, scale the analog prototype (buttap)
// to the warped cutoff (lp2lp_zpk) and map each pole with the bilinear transform
// (bilinear_zpk): p_z = (4 + p) / (4 - p). All N zeros go to z = -1.
// Then scipy's zpk2sos(pairing='nearest') after _cplxreal: one pole of each conjugate pair
// (positive imaginary part) by increasing real part, then the real poles by increasing value.
// An odd order gets an extra pole and zero at 0, so every section is second order.
DigitalZpk butterworthZpk(int order, double wn) {
  const double warped = 4.0 * std::tan(kPi * wn / 2.0);
  const auto bilinear = [](Complex p) { return (4.0 + p) / (4.0 - p); };
  DigitalZpk d;
  std::vector<Pole>& p = d.poles;
  std::vector<double>& z = d.zeros;
  z.assign(static_cast<std::size_t>(order), -1.0);
  for (int m = order - 1; m > 0; m -= 2) {
    // buttap's pole -exp(i pi m' / (2N)) for m' = -m, which has a positive imaginary part.
    const double theta = kPi * static_cast<double>(m) / (2.0 * order);
    p.push_back({bilinear(warped * Complex(-std::cos(theta), std::sin(theta))), false});
  }
  std::sort(p.begin(), p.end(), [](const Pole& l, const Pole& r) { return l.value.real() < r.value.real(); });
  if (order % 2 == 1) {
    const double real_pole = bilinear(Complex(-warped, 0.0)).real();
    p.push_back({Complex(std::min(real_pole, 0.0), 0.0), true});
    p.push_back({Complex(std::max(real_pole, 0.0), 0.0), true});
    z.push_back(0.0);
    std::sort(z.begin(), z.end());
  }
  return d;
}

// Pair the pole closest to the unit circle with the nearest zeros, filling the sections from
// the last one, so the sections nearest to instability run last.
SosFilter pairIntoSections(DigitalZpk d, int order) {
  std::vector<Pole>& p = d.poles;
  std::vector<double>& z = d.zeros;
  const Eigen::Index sections = (order + 1) / 2;
  SosFilter f;
  f.sos.resize(sections, 6);
  const auto any = [](const Pole&) { return true; };
  const auto is_real = [](const Pole& q) { return q.real; };
  for (Eigen::Index s = sections - 1; s >= 0; --s) {
    const std::size_t i1 = worstPole(p, any);
    const Pole p1 = p[i1];
    p.erase(p.begin() + static_cast<std::ptrdiff_t>(i1));
    const bool real_left = std::any_of(p.begin(), p.end(), is_real);
    const std::size_t j1 = nearestZero(z, p1.value);
    const double z1 = z[j1];
    z.erase(z.begin() + static_cast<std::ptrdiff_t>(j1));
    if (p1.real && !real_left) {
      // Last real pole with no real partner: a first-order section [z1, 0] / [p1, 0]. With
      // Butterworth's even pole count after padding this cannot happen, but it keeps the port
      // faithful.
      setSection(f.sos.row(s).data(), z1, 0.0, p1.value, 0.0);
      continue;
    }
    Complex p2 = std::conj(p1.value);
    if (p1.real) {
      const std::size_t i2 = worstPole(p, is_real);
      p2 = p[i2].value;
      p.erase(p.begin() + static_cast<std::ptrdiff_t>(i2));
    }
    const std::size_t j2 = nearestZero(z, p1.value);
    const double z2 = z[j2];
    z.erase(z.begin() + static_cast<std::ptrdiff_t>(j2));
    setSection(f.sos.row(s).data(), z1, z2, p1.value, p2);
  }
  return f;
}

// The gain goes into the first section, chosen so the DC gain prod_s B_s(1) / A_s(1) of the
// stored coefficients is 1 (scipy's k differs from it only by rounding).
void normaliseDcGain(SosFilter& f) {
  double gain = 1.0;
  for (Eigen::Index s = 0; s < f.sos.rows(); ++s) {
    gain *= (1.0 + f.sos(s, 4) + f.sos(s, 5)) / (f.sos(s, 0) + f.sos(s, 1) + f.sos(s, 2));
  }
  f.sos.block(0, 0, 1, 3) *= gain;
}

}  // namespace

SosFilter butterworthLowpass(int order, double cutoff_hz, double sample_rate_hz) {
  validateButterworth(order, cutoff_hz, sample_rate_hz);
  SosFilter f = pairIntoSections(butterworthZpk(order, 2.0 * cutoff_hz / sample_rate_hz), order);
  normaliseDcGain(f);
  return f;
}

Eigen::MatrixXd sosfilt(const SosFilter& f, const Eigen::MatrixXd& x) {
  validateSos(f);
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd y(n, x.cols());
  std::vector<double> buf(static_cast<std::size_t>(n * kLanes));
  std::vector<Lanes> state(static_cast<std::size_t>(2 * f.sections()));
  for (Eigen::Index c0 = 0; c0 < x.cols(); c0 += kLanes) {
    const int lanes = static_cast<int>(std::min<Eigen::Index>(kLanes, x.cols() - c0));
    std::fill(buf.begin(), buf.end(), 0.0);
    for (int l = 0; l < lanes; ++l) {
      for (Eigen::Index i = 0; i < n; ++i) buf[static_cast<std::size_t>(i * kLanes + l)] = x(i, c0 + l);
    }
    std::fill(state.begin(), state.end(), Lanes::Zero());
    runCascade(f, state.data(), buf.data(), n, false);
    for (int l = 0; l < lanes; ++l) {
      for (Eigen::Index i = 0; i < n; ++i) y(i, c0 + l) = buf[static_cast<std::size_t>(i * kLanes + l)];
    }
  }
  return y;
}

void filtfiltInPlace(const SosFilter& f, Eigen::Ref<Eigen::MatrixXd> x) {
  validateSos(f);
  const Eigen::Index pad = padLength(f);
  const Eigen::Index n = x.rows();
  if (n <= pad) {
    throw std::invalid_argument("x must have more rows (samples) than padlen = " + core::toText(pad) +
                                " for " + core::toText(f.sections()) + " sections, got " +
                                core::toText(n));
  }
  const std::vector<double> zi = steadyStateZi(f);
  const Eigen::Index sections = f.sections();
  const Eigen::Index m = n + 2 * pad;  // odd extension on both ends
  // In place: each group of columns is read whole into buf (edges included) before it is written.
  Eigen::Ref<Eigen::MatrixXd>& y = x;
  // Columns are filtered independently, so an all-zero column's output is zero and a repeated
  // column's is its first copy's, bit for bit: only the distinct non-zero ones are filtered (a
  // regressor's structural zeros and repeats are a third of the leg's columns).
  std::vector<Eigen::Index> filtered;
  std::vector<Eigen::Index> same_as(static_cast<std::size_t>(x.cols()), -1);  // -1: filtered itself
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    if ((x.col(c).array() == 0.0).all()) {
      same_as[static_cast<std::size_t>(c)] = -2;  // zero
      continue;
    }
    for (Eigen::Index e : filtered) {
      if (x.col(c) == x.col(e)) {
        same_as[static_cast<std::size_t>(c)] = e;
        break;
      }
    }
    if (same_as[static_cast<std::size_t>(c)] == -1) filtered.push_back(c);
  }
  std::vector<double> buf(static_cast<std::size_t>(m * kLanes));
  std::vector<Lanes> state(static_cast<std::size_t>(2 * sections));
  const auto at = [](Eigen::Index row, int lane) { return static_cast<std::size_t>(row * kLanes + lane); };
  // Steady state of the cascade for a step of height buf[row] in every lane.
  const auto initState = [&](Eigen::Index row) {
    const Lanes step = Lanes::Map(buf.data() + row * kLanes);
    for (std::size_t k = 0; k < state.size(); ++k) state[k] = zi[k] * step;
  };

  const auto count = static_cast<Eigen::Index>(filtered.size());
  for (Eigen::Index g = 0; g < count; g += kLanes) {
    const int lanes = static_cast<int>(std::min<Eigen::Index>(kLanes, count - g));
    const auto column = [&](int l) { return filtered[static_cast<std::size_t>(g + l)]; };
    if (lanes < kLanes) std::fill(buf.begin(), buf.end(), 0.0);
    // Row by row, so buf is written (and below read) in one sequential sweep.
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int l = 0; l < lanes; ++l) buf[at(pad + i, l)] = x(i, column(l));
    }
    for (int l = 0; l < lanes; ++l) {
      const auto col = x.col(column(l));
      const double first = col(0), last = col(n - 1);
      for (Eigen::Index i = 0; i < pad; ++i) buf[at(i, l)] = 2.0 * first - col(pad - i);
      for (Eigen::Index j = 0; j < pad; ++j) buf[at(pad + n + j, l)] = 2.0 * last - col(n - 2 - j);
    }
    initState(0);
    runCascade(f, state.data(), buf.data(), m, false);
    initState(m - 1);
    runCascade(f, state.data(), buf.data(), m, true);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int l = 0; l < lanes; ++l) y(i, column(l)) = buf[at(pad + i, l)];
    }
  }
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    const Eigen::Index src = same_as[static_cast<std::size_t>(c)];
    if (src == -2) y.col(c).setZero();
    if (src >= 0) y.col(c) = y.col(src);
  }
}

Eigen::MatrixXd filtfilt(const SosFilter& f, const Eigen::MatrixXd& x) {
  Eigen::MatrixXd y = x;
  filtfiltInPlace(f, y);
  return y;
}

}  // namespace exoid::ident
