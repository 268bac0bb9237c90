#pragma once
// The APAL leg's excitation trajectories (core::FourierSeries of hip and knee, what ident designs
// and the simulator runs) and the JSON file `exoid excite` writes and `exoid simulate
// --excitation` reads.
#include "exoid/ident/design/excitation.hpp"
#include "exoid/sim/trajectory.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace exoid::experiments {

/// {"f0_hz", "hip_locked", "offset_rad": {"hip", "knee"}, "a_rad": {"hip": [...], "knee": [...]}, "b_rad": ...}
nlohmann::json toJson(const core::FourierSeries& t);
/// Reads the "trajectory" object of an excitation file; throws std::invalid_argument naming the
/// file and the key.
core::FourierSeries readExcitationFile(const std::string& path);

/// The envelope of the paper's trajectories 1-4 on the nominal model: their joint ranges, largest
/// |qd|, |qdd| and |tau|: designs under these limits ask no more of the rig than the paper did.
ident::ExcitationLimits paperEnvelope(const ident::LegConstants& c, const ident::ParamVector& nominal);

/// Noise-limited std of each parameter fitted by LS to `duration_s` of the trajectory at
/// `rate_hz` with white torque noise sigma_Nm on each joint (raw torques, no filter): the design's
/// Cramer-Rao bound. Both equations, 10 parameters; a locked hip: the knee equation's 5.
Eigen::VectorXd excitationCrb(const core::FourierSeries& t, const ident::LegConstants& c, double duration_s,
                              double rate_hz, double sigma_Nm);

}  // namespace exoid::experiments
