#pragma once
// iv-band for any serial chain (estimators/band_iv.hpp explains the estimator): the record's rows
// in the chain's base parameters and their instruments, the same rows built from the angles
// low-passed at the motion's bandwidth. solveBandIv then fits them, as for the 2-link leg.
#include "exoid/ident/estimators/band_iv.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/base_parameters.hpp"
#include "exoid/ident/model/chain.hpp"
#include "exoid/ident/signals/preprocess.hpp"

namespace exoid::ident {

/// Rows H (base regressor of processChainRecord(d, model, o), every joint's equation), torques y,
/// and instruments Z (the same processing of d with its angles, and recorded derivatives, low-passed
/// at instrument_cutoff_hz, zero-phase order 4; the band o leaves to the data is chosen once, on
/// d, and used for both). The Coulomb columns instrument themselves (band_iv.cpp says why). Throws
/// std::invalid_argument for a non-parallel o, a cutoff outside (0, Nyquist), or as
/// processChainRecord does.
BandIvRows chainBandIvRows(const Dataset& d, const ChainModel& model, const BaseParameters& base, const SignalOptions& o,
                           double instrument_cutoff_hz);

}  // namespace exoid::ident
