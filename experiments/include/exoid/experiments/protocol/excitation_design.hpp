#pragma once
// `exoid excite` for any leg: a periodic excitation designed (ident::designExcitation) for the
// robot's parameters inside its limits, every joint moving or the joints above a stage's first
// moving joint held; written as the design file every command reads (excitation_io.hpp) with each
// parameter's Cramer-Rao std on a stated footing, its series and figure. The APAL leg's design is
// in the paper's X, under the paper's envelope (or its URDF's limits), and compared with the
// paper's trajectory and with the floor no trajectory inside the limits can beat.
#include "exoid/core/tree_selection.hpp"
#include "exoid/ident/design/excitation.hpp"

#include <string>
#include <vector>

namespace exoid::experiments {

/// Overrides of the limits a design respects (--q-min-deg ... --tau-max), one value per joint in
/// the design's order; an empty one keeps the model's (or the envelope's) limit.
struct LimitOverrides {
  std::vector<double> q_min_deg, q_max_deg, qd_max, qdd_max, tau_max;
  bool empty() const { return q_min_deg.empty() && q_max_deg.empty() && qd_max.empty() && qdd_max.empty() && tau_max.empty(); }
  /// Replaces the limits given (deg for the angles); throws CLI::ValidationError naming the option
  /// when a count is wrong.
  void applyTo(ident::ExcitationLimits& limits) const;
};

struct ExciteRequest {
  std::string model = "apal";  ///< apal, leg3, or an MJCF/URDF file
  std::string out;             ///< the design JSON
  /// The criterion, harmonics, f0, restarts, seed; its locked joints are set from first_moving.
  ident::ExcitationOptions options;
  /// A stage's record: the joints above this one are held (exoid simulate locks them where the
  /// design holds them). Empty: every joint moves.
  std::string first_moving;
  /// Where each held joint is held, deg, one per held joint. Empty: the APAL leg's hip at the
  /// paper's -10 deg; a chain's joint at 0, or at its range's middle when 0 is not inside the
  /// range's middle 80 % (0 on a stop would put the lock against it).
  std::vector<double> held_at_deg;
  LimitOverrides overrides;
  /// The APAL leg's limits: "paper" (the envelope of the paper's trajectories) or "urdf" (the
  /// rig's range, speed and effort from `urdf`). A chain's are its model file's (speed 3 rad/s,
  /// acceleration 30 rad/s^2 where the file gives none).
  std::string limits = "paper";
  std::string urdf;                   ///< empty: models/apal_leg.urdf
  std::vector<std::string> armature;  ///< chains: joints (or "all") given an armature parameter the file lacks
  core::ChainSelection selection;     ///< --base, --tip, --lock: a chain out of a tree
  /// The Cramer-Rao footing: LS on raw torques of duration_s at rate_hz, white noise sigma_Nm per joint.
  double duration_s = 10.0, rate_hz = 1000.0, sigma_Nm = 0.5;
  bool plot = true;  ///< <out stem>.png and <out stem>_series.csv beside the design
};

/// Designs, writes `out` (and the figure), prints the summary. Throws std::invalid_argument or
/// CLI::ValidationError naming the option or file at fault, before any work.
void excite(const ExciteRequest& request);

}  // namespace exoid::experiments
