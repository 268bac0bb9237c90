#include "exoid/ident/estimators/band_iv.hpp"

#include "exoid/core/format.hpp"
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/signals/signals.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <limits>
#include <optional>
#include <stdexcept>

namespace exoid::ident {

Dataset instrumentRecord(const Dataset& d, const SignalOptions& o, double instrument_cutoff_hz) {
  if (o.processing != Processing::kParallel) {
    throw std::invalid_argument("iv-band needs the parallel processing: its instruments are processed like the rows");
  }
  const double fs = 1.0 / d.sampleInterval_s();
  if (!(instrument_cutoff_hz > 0.0 && instrument_cutoff_hz < 0.5 * fs)) {
    throw std::invalid_argument("iv-band: the instruments' cutoff must be in (0, " + core::formatNumber(0.5 * fs, 6) +
                                ") Hz, got " + core::formatNumber(instrument_cutoff_hz, 6));
  }
  Dataset smooth = d;
  const SosFilter lp = butterworthLowpass(4, instrument_cutoff_hz, fs);
  smooth.q_rad = filtfilt(lp, d.q_rad);
  if (d.qd_radps) smooth.qd_radps = filtfilt(lp, *d.qd_radps);
  if (d.qdd_radps2) smooth.qdd_radps2 = filtfilt(lp, *d.qdd_radps2);
  return smooth;
}

BandIvRows bandIvRows(const Dataset& d, const Robot& robot, const SignalOptions& o, double instrument_cutoff_hz) {
  // The same record with every angle (and recorded derivative) low-passed at the motion's band,
  // processed in the band chosen on the record itself (so rows and instruments align).
  const Dataset smooth = instrumentRecord(d, o, instrument_cutoff_hz);
  std::optional<BandChoice> band;
  const RecordRows measured = processRecord(d, robot, o, {}, &band);
  const RecordRows instruments = processRecord(smooth, robot, band ? withBand(o, *band) : o);
  if (instruments.W.rows() != measured.W.rows()) throw std::logic_error("iv-band: instruments and rows do not align");
  BandIvRows out{measured.W, instruments.W, measured.y};
  // The Coulomb columns instrument themselves: sgn(qd) of noisy velocities is not the smooth
  // motion's plus zero-mean noise (the sign flips near reversals shift its mean), and a smooth
  // instrument would turn that shift into bias; taken as they are they cost least squares'
  // behaviour on those parameters only.
  for (const int j : robot.coulomb) out.Z.col(j) = out.H.col(j);
  return out;
}

Estimate solveBandIv(const std::vector<BandIvRows>& records, const LsOptions& options) {
  options.validate();
  if (records.empty()) throw std::invalid_argument("iv-band: no records");
  Stopwatch clock;
  const Eigen::Index p = records.front().H.cols();
  Eigen::MatrixXd ZtH = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd Zty = Eigen::VectorXd::Zero(p);
  Eigen::Index rows = 0;
  for (const BandIvRows& r : records) {
    if (r.H.cols() != p || r.Z.cols() != p || r.Z.rows() != r.H.rows() || r.y.size() != r.H.rows()) {
      throw std::invalid_argument("iv-band: a record's rows, instruments and torques do not match");
    }
    ZtH.noalias() += r.Z.transpose() * r.H;
    Zty.noalias() += r.Z.transpose() * r.y;
    rows += r.H.rows();
  }
  if (rows < p) throw std::invalid_argument("iv-band: fewer rows than parameters");
  // Scale the unknowns like least squares does (columns of H to unit norm).
  Eigen::VectorXd scale(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    double sq = 0.0;
    for (const BandIvRows& r : records) sq += r.H.col(j).squaredNorm();
    scale[j] = sq > 0.0 ? 1.0 / std::sqrt(sq) : 1.0;
  }
  Eigen::VectorXd zscale(p);  // and the instruments' rows of Z^T H
  for (Eigen::Index j = 0; j < p; ++j) {
    double sq = 0.0;
    for (const BandIvRows& r : records) sq += r.Z.col(j).squaredNorm();
    zscale[j] = sq > 0.0 ? 1.0 / std::sqrt(sq) : 1.0;
  }
  const Eigen::MatrixXd A = zscale.asDiagonal() * ZtH * scale.asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(options.rank_tolerance);
  Estimate e;
  e.method = Method::kIvBand;
  e.x = scale.asDiagonal() * qr.solve(Eigen::VectorXd(zscale.asDiagonal() * Zty));
  e.rank = qr.rank();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  e.condition_number = sv[p - 1] > 0.0 ? sv[0] / sv[p - 1] : std::numeric_limits<double>::infinity();
  e.summary.iterations = 1;
  if (*e.rank < p) {
    for (Eigen::Index k = *e.rank; k < p; ++k) e.unidentifiable.push_back(qr.colsPermutation().indices()[k]);
    e.summary.status = Status::kRankDeficient;
    e.summary.message = "rank " + core::toText(*e.rank) + " < " + core::toText(p) + ": Z^T H is singular";
  } else if (*e.condition_number > options.max_condition) {
    e.summary.status = Status::kIllConditioned;
    e.summary.message = illConditionedMessage(*e.condition_number, options.max_condition);
  } else {
    e.summary.status = Status::kConverged;
    e.summary.message = "instrumental variables from the motion's band (no controller model)";
  }
  double l1 = 0.0;
  for (const BandIvRows& r : records) l1 += (r.y - r.H * e.x).cwiseAbs().sum();
  e.l1_cost = l1;
  e.summary.wall_time_s = clock.seconds();
  return e;
}

}  // namespace exoid::ident
