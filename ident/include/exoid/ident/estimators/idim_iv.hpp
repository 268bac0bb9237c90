#pragma once
// IDIM-IV (Janot, Vandanjon, Gautier, IEEE TCST 2014): instrumental variables whose instruments
// are the regressor of a closed-loop simulation of the model identified at the previous
// iteration. The simulated states carry the motion but none of the measurement noise, so the
// estimate loses the bias that noisy regressor columns (differentiated encoder noise) give LS;
// the measured torque stays the output. Starts from LS; iterates until the step is a small
// fraction of each parameter's standard error.
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/model/closed_loop.hpp"
#include "exoid/ident/signals/processing.hpp"

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
  RecordRows measured;    ///< processRecord of the measured record, parallel processing
  SignalOptions signals;  ///< what `measured` was processed with: kParallel, its band fixed (withBand)
  Reference reference;    ///< the controller's reference, full length at the record's rate
  Controller controller;
};

/// The instrument rows of a record for parameters theta: the closed-loop simulation of theta,
/// processed by parallelProcess with the measured record's options (so rows align with
/// `measured`). When theta cannot be simulated (an iterate with M(q) not positive definite, e.g.
/// Jt < 0 on a poorly exciting record), the instruments come from the reference itself, the limit
/// of perfect tracking: still free of the measurement noise, so still consistent, but fixed (the
/// iteration stops) and said in the message. Throws std::invalid_argument when the reference and
/// the measured rows do not align.
Instruments instrumentRows(const Robot& robot, const Eigen::VectorXd& theta, const ClosedLoopRecord& record, RecordRows& out);

/// IDIM-IV over one or more records fitted together (their rows stacked), every parameter:
/// x0 = LS, then x_{k+1} = IV(H, y, Z(x_k)) until each step is below options.step_tolerance
/// standard errors. Throws std::invalid_argument for no records or a record not processed in
/// parallel with its band fixed.
Estimate identifyIdimIv(const Robot& robot, const std::vector<ClosedLoopRecord>& records, const IvOptions& options = {});

/// IDIM-IV with the segmental strategy (segmental.hpp): each stage's combinations from its record,
/// its instruments from that record's closed loop (the parameters later stages find start at 0,
/// irrelevant where their joints are locked). Throws as identifyIdimIv and SegmentalPlan do.
struct ClosedLoopStage {
  Eigen::Index first_joint = 0;
  ClosedLoopRecord record;
};
SegmentalResult identifySegmentalIdimIv(const Robot& robot, const std::vector<ClosedLoopStage>& stages, const IvOptions& options = {},
                                        const BaseParameterOptions& structure = {});

}  // namespace exoid::ident
