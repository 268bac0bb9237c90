#pragma once
// A second-order low-pass H(s) = wn^2 / (s^2 + 2 zeta wn s + wn^2), discretised by the bilinear
// (Tustin) transform without prewarping (exact low-frequency gain and delay), run once per sample. Used for what lies between a command
// and the torque a joint gets (actuator bandwidth) and between that torque and its reading
// (the torque sensor's anti-aliasing). Tustin keeps the direct feedthrough, so an infinitely fast
// element (bandwidth -> inf) gives out = in in the same sample; at low frequency it has the
// continuous filter's delay 2 zeta / wn.
namespace exoid::sim {

class SecondOrderLowpass {
 public:
  /// bandwidth_Hz = wn / 2 pi (the -3 dB frequency when zeta = 1/sqrt(2)); 0 = pass-through.
  /// Throws std::invalid_argument unless 0 <= bandwidth < 1 / (2 dt_s) (Nyquist), zeta > 0.
  SecondOrderLowpass(double bandwidth_Hz, double zeta, double dt_s);
  /// Steady state at a constant input (output = value).
  void reset(double value);
  /// One sample: returns the output at this sample. Allocation-free.
  double step(double in);

 private:
  bool pass_ = true;
  double b0_ = 1, b1_ = 0, b2_ = 0, a1_ = 0, a2_ = 0;
  double s1_ = 0, s2_ = 0;  // direct form II transposed state
};

}  // namespace exoid::sim
