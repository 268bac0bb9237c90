#pragma once
// Whether a record's base-motion terms (its IMU columns through the regressor) are kept: chosen
// from the record by held-out prediction. The terms add no parameter; they add the IMU's signals,
// its noise included, to every row. On a still base they can only feed that noise to the fit; on a
// moving one, leaving them out leaves the base's motion in the residual.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/band.hpp"
#include "exoid/ident/signals/preprocess.hpp"

#include <optional>
#include <string>
#include <vector>

namespace exoid::ident {

struct BaseTermsChoice {
  bool use = true;
  int folds = 0;                         ///< 0: the record was too short to judge (the terms kept)
  Eigen::Index samples = 0;              ///< processed samples judged
  Eigen::Index equations = 0;            ///< held-out equations (samples x moving joints); 0 unjudged
  double held_out_rms_with_Nm = 0.0;     ///< torque RMS of every held-out block, predicted with the terms
  double held_out_rms_without_Nm = 0.0;  ///< the same on a still base
  std::string describe() const;
};

/// The rule: the record's rows processed by o with and without the terms (o's band; the record's
/// central rule.pilot_max_samples at most, as the band's pilot), cut into `folds` contiguous
/// blocks of samples; each block's torque of joints rule.first_moving_joint.. predicted by least
/// squares on the other blocks. The terms are kept unless their held-out RMS is the larger; a
/// record with fewer than 2 x parameters rows outside each block keeps them unjudged. Throws
/// std::invalid_argument when d lacks the IMU columns or o is not the parallel processing.
BaseTermsChoice chooseBaseTerms(const Dataset& d, const Robot& robot, const SignalOptions& o, const BandRule& rule = {}, int folds = 5);

/// One choice for records fitted together (their rows stacked into one model): the held-out
/// squared errors of the records judged, pooled over their equations; records too short to judge
/// do not count. nullopt when none was judged.
std::optional<BaseTermsChoice> pooledBaseTerms(const std::vector<std::optional<BaseTermsChoice>>& choices);

/// Records stacked into one fit share one choice (stackRecords refuses a mix): when the records'
/// own choices (one per record, as resolveSignalOptions made them) disagree, every judged record's
/// options take the pooled one, which is returned; nullopt when they agree (nothing changes).
std::optional<BaseTermsChoice> shareBaseTerms(std::vector<SignalOptions>& signals, const std::vector<std::optional<BaseTermsChoice>>& choices);

}  // namespace exoid::ident
