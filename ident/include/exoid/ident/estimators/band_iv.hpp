#pragma once
// Instrumental variables from the motion's band ("iv-band"): a bias-robust estimator that needs
// no controller model (IDIM-IV needs the rig's controller, which most real logs do not come with).
//
// Least squares over the rows H of a record is biased when H carries noise (differentiated encoder
// noise: errors-in-variables). The instruments Z are the same rows built from the angles low-passed
// at the motion's bandwidth f_m (zero-phase, order 4) before differentiating, then processed exactly
// like H (same band, trims, decimation). Z follows the motion, so Z^T H is well conditioned; Z's
// noise is the encoder noise below f_m only, whose share of H's noise is (f_m / fc)^5 for twice-
// differentiated white noise in a band fc: the estimate
//   x = (Z^T H)^-1 Z^T y
// is free of the attenuation least squares suffers, to that share. Exact on exact data
// (y = H x gives Z^T y = Z^T H x whatever Z). Several records are stacked row-wise, each with its own
// instruments.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <vector>

namespace exoid::ident {

/// One record's rows (every joint's equation in time order, RecordRows' layout) and its instruments.
struct BandIvRows {
  Eigen::MatrixXd H, Z;
  Eigen::VectorXd y;
};

/// The record the instruments are built from: d with its angles (and recorded derivatives)
/// low-passed at instrument_cutoff_hz (zero-phase, order 4). Throws std::invalid_argument for a
/// non-parallel o (the instruments must be processed like the rows) or a cutoff outside (0, Nyquist).
Dataset instrumentRecord(const Dataset& d, const SignalOptions& o, double instrument_cutoff_hz);

/// The robot's rows of record d processed by o (every joint's equation; the band o leaves to the
/// data chosen once, on d, and used for both) and its instruments, the same processing of d with
/// its angles (and recorded derivatives) low-passed at instrument_cutoff_hz. The Coulomb columns
/// instrument themselves (band_iv.cpp says why). Throws std::invalid_argument for a non-parallel
/// o, a cutoff outside (0, Nyquist) or as processRecord does.
BandIvRows bandIvRows(const Dataset& d, const Robot& robot, const SignalOptions& o, double instrument_cutoff_hz);

/// x = (Z^T H)^-1 Z^T y over the records' rows stacked, column-scaled, by column-pivoted QR of
/// Z^T H. Estimate.method = kIvBand; rank and condition_number of Z^T H (scaled); status as LS's
/// (rank deficient, ill-conditioned beyond options.max_condition). Throws std::invalid_argument
/// for none or mismatched rows.
Estimate solveBandIv(const std::vector<BandIvRows>& records, const LsOptions& options = {});

}  // namespace exoid::ident
