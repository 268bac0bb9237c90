#pragma once
// IDIM-IV (Janot, Vandanjon, Gautier, IEEE TCST 2014): instrumental variables whose instruments
// are the regressor of a closed-loop simulation of the model identified at the previous
// iteration. The simulated states carry the motion but none of the measurement noise, so the
// estimate loses the bias that noisy regressor columns (differentiated encoder noise) give LS;
// the measured torque stays the output. Starts from LS; iterates until the step is a small
// fraction of each parameter's standard error.
#include "exoid/ident/leg/closed_loop.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/estimators/segmental.hpp"

#include <functional>
#include <optional>
#include <vector>

namespace exoid::ident {

/// x = (Z^T H)^{-1} Z^T y by column-pivoted QR of the column-scaled Z^T H. Status kRankDeficient
/// when Z^T H is singular at LsOptions::rank_tolerance (instruments that do not excite a column).
/// Throws std::invalid_argument on size mismatch or non-finite input.
Estimate instrumentalVariables(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const Eigen::MatrixXd& Z,
                               const LsOptions& options = {});

struct IvOptions {
  /// Stop when every parameter moved by less than step_tolerance of its standard error (IV
  /// covariance from the residual). Range (0, 1). Default 0.1: smaller steps change nothing the
  /// data can resolve, and the iteration need not contract below that (the instruments' sgn(qd)
  /// columns switch with the simulated motion: one of 50 noisy seeds of the rigid leg settled into
  /// a 2-cycle of 0.065 standard errors).
  double step_tolerance = 0.1;
  /// Iteration limit, >= 1. Default 10 (the method's authors report 2-5).
  int max_iterations = 10;
  LsOptions ls;  ///< rank tolerance for the starting LS and every IV solve
  void validate() const;  ///< throws std::invalid_argument naming the field
};

/// The instruments' regressor (same rows and columns as H) for parameters x; ok = false with a
/// message when the model x cannot produce them (e.g. it cannot be simulated).
struct Instruments {
  bool ok = false;
  std::string message;  ///< why not ok; or, when ok, a note on how they were made
  Eigen::MatrixXd Z;
  /// The instruments do not depend on x (a fallback): one IV solve with them is final.
  bool fixed = false;
};
using InstrumentFn = std::function<Instruments(const Eigen::VectorXd& x)>;

/// The iteration on y = H x: x0 = LS, x_{k+1} = IV(H, y, Z(x_k)). Estimate::summary.iterations
/// counts IV solves; cost_history holds max_i |step_i| / se_i per iteration. Stops after a solve
/// with fixed instruments (their note in the message). Status kFailed (with the instruments'
/// message) if no instruments can be made, kMaxIterations if the steps did not settle.
Estimate iterateInstrumentalVariables(const Eigen::MatrixXd& H, const Eigen::VectorXd& y, const InstrumentFn& instruments,
                                      const IvOptions& options = {});

/// One record as IDIM-IV needs it: its measured rows and what reproduces its motion.
struct ClosedLoopRecord {
  ProcessedRecord measured;  ///< parallelProcess of the measured record (processRecord, kParallel)
  Reference reference;       ///< the controller's reference, full length at the record's rate
  ControllerModel controller;
  /// The options `measured` was processed with, when they are the record's own (a band chosen from
  /// its data): instrumentRecord then uses them instead of the options it is given.
  std::optional<SignalOptions> signals;
};

/// The instrument rows of a record for parameters x: the closed-loop simulation of x, processed
/// by parallelProcess with the measured record's options (so rows align with `measured`). When
/// the model x cannot be simulated (an iterate with M(q) not positive definite, e.g. Jt < 0 on a
/// poorly exciting record), the instruments come from the reference itself, the limit of perfect
/// tracking: still free of the measurement noise, so still consistent, but fixed (the iteration
/// stops) and said in the message.
Instruments instrumentRecord(const ParamVector& x, const LegConstants& c, const ClosedLoopRecord& r,
                             const SignalOptions& signals, ProcessedRecord& out, double knee_armature_kgm2 = 0.0);

/// IDIM-IV with the segmental strategy: knee parameters from the knee record (its instruments from
/// the simulated knee record), then hip parameters from the two-joint record with the knee part
/// subtracted. Requires signals.processing == kParallel (instruments and measurements must be
/// processed alike). `x_start` supplies the parameters a stage does not estimate when it
/// simulates (the hip's, in the knee stage; irrelevant when the hip is locked).
SegmentalResult identifySegmentalIv(const ClosedLoopRecord& knee_record, const ClosedLoopRecord& both_record,
                                    const LegConstants& c, const SignalOptions& signals, const IvOptions& options,
                                    const ParamVector& x_start = ParamVector::Zero());
/// IDIM-IV on both equations of one record, all 10 parameters (11 with knee_armature: Ia2 last).
Estimate identifyAllIv(const ClosedLoopRecord& record, const LegConstants& c, const SignalOptions& signals,
                       const IvOptions& options, bool knee_armature = false);

}  // namespace exoid::ident
