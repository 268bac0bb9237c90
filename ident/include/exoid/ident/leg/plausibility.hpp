#pragma once
// Physical plausibility of an estimate of X: what the definitions of the parameters imply
// whatever the leg (paper Eq. 1, corrected):
//   Js = Is + ms ((Ls - LGs)^2 + hGs^2) > 0           (an inertia about the knee axis)
//   Jt - Js = It + mt ((Lt - LGt)^2 + hGt^2) + ms Lt^2 > 0   (the thigh adds inertia about the hip)
//   fc1, fc2 >= 0, fv1, fv2 >= 0                       (friction dissipates)
// An estimate that violates one cannot be the leg's; it must not be used.
#include "exoid/ident/leg/params.hpp"

#include <string>
#include <vector>

namespace exoid::ident {

/// The violated conditions, each named with the values, e.g. "Js = -0.12 kg m^2 must be > 0";
/// empty when the estimate is plausible. Parameters listed in `not_estimated` (indices into X,
/// e.g. a block a record cannot identify) are not checked.
std::vector<std::string> implausibilities(const ParamVector& x, const std::vector<int>& not_estimated = {});

}  // namespace exoid::ident
