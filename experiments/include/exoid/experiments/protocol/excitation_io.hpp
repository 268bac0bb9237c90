#pragma once
// Excitation designs: the file `exoid excite` writes for any leg and `exoid simulate --excitation`,
// sweeps and reproduce read (its "trajectory" in sim/trajectory_json.hpp's form), the Cramer-Rao
// footing of any leg's design, and the APAL leg's comparison (the paper's envelope).
#include "exoid/ident/design/excitation.hpp"
#include "exoid/sim/trajectory.hpp"
#include "exoid/sim/trajectory_json.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace exoid::experiments {

/// The "trajectory" of an excitation design file. With `joints` given, the design's joints must be
/// these, in order. Throws std::invalid_argument naming the file and the key (or both joint lists).
sim::NamedTrajectory readExcitationFile(const std::string& path, const std::vector<std::string>& joints = {});
/// The APAL leg's (hip, knee).
inline const std::vector<std::string> kLegJoints = {"hip", "knee"};

/// What every design file holds beside its trajectory: the limits it was designed under, from
/// `source`, and its score with what it reached; both per quantity, one value per joint in the
/// trajectory's order ("q_min_rad": [...], ..., "tau_max_Nm": [...]).
nlohmann::json limitsJson(const ident::ExcitationLimits& limits, const std::string& source);
nlohmann::json scoreJson(const ident::ExcitationDesign& d);

/// The envelope of the paper's trajectories 1-4 on the nominal model: their joint ranges, largest
/// |qd|, |qdd| and |tau|: designs under these limits ask no more of the rig than the paper did.
ident::ExcitationLimits paperEnvelope(const ident::LegConstants& c, const ident::ParamVector& nominal);

/// Noise-limited std of each parameter fitted by LS to `duration_s` of the trajectory at
/// `rate_hz` with white torque noise sigma_Nm on each joint (raw torques, no filter): the design's
/// Cramer-Rao bound. The moving joints' equations, over the parameters they determine
/// (ident::excitationParameters: the APAL leg's 10, or the knee's 5 with the hip locked).
Eigen::VectorXd excitationCrb(const core::FourierSeries& t, const ident::Robot& robot, double duration_s, double rate_hz,
                              double sigma_Nm);

}  // namespace exoid::experiments
