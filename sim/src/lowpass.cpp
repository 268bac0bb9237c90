#include "exoid/sim/lowpass.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exoid::sim {

SecondOrderLowpass::SecondOrderLowpass(double bandwidth_Hz, double zeta, double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(bandwidth_Hz) || bandwidth_Hz < 0.0 || !(bandwidth_Hz * dt_s < 0.5) ||
      !(zeta > 0.0 && std::isfinite(zeta))) {
    std::ostringstream ss;
    ss.precision(17);
    ss << "second-order low-pass: need 0 <= bandwidth < Nyquist (" << 0.5 / dt_s << " Hz) and damping > 0, got "
       << bandwidth_Hz << " Hz, damping " << zeta;
    throw std::invalid_argument(ss.str());
  }
  if (bandwidth_Hz == 0.0) return;
  pass_ = false;
  // s = K (z - 1) / (z + 1) with K = 2 / dt (no prewarping): the discrete element matches the
  // continuous one at low frequency, where the motion is, to O((w dt)^2) in gain and delay; the
  // response at w maps to the continuous one at (2 / dt) tan(w dt / 2) (the -3 dB point of a
  // 200 Hz element sampled at 1 kHz moves to 178 Hz).
  const double wn = 2.0 * M_PI * bandwidth_Hz;
  const double K = 2.0 / dt_s;
  const double a0 = K * K + 2.0 * zeta * wn * K + wn * wn;
  b0_ = wn * wn / a0;
  b1_ = 2.0 * b0_;
  b2_ = b0_;
  a1_ = 2.0 * (wn * wn - K * K) / a0;
  a2_ = (K * K - 2.0 * zeta * wn * K + wn * wn) / a0;
}

void SecondOrderLowpass::reset(double value) {
  // DC gain 1: in = out = value; DF-II-T states at rest: s1 = out - b0 in, s2 = b2 in - a2 out.
  s1_ = value - b0_ * value;
  s2_ = b2_ * value - a2_ * value;
}

double SecondOrderLowpass::step(double in) {
  if (pass_) return in;
  const double out = b0_ * in + s1_;
  s1_ = b1_ * in - a1_ * out + s2_;
  s2_ = b2_ * in - a2_ * out;
  return out;
}

}  // namespace exoid::sim
