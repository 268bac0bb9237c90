#pragma once
// The controller and reference a log was recorded under, as IDIM-IV needs them, for any robot:
// from a dataset's "# controller_*" metadata (exoid simulate writes them), or from a JSON file
// describing a real rig's controller.
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/closed_loop.hpp"

#include <string>
#include <vector>

namespace exoid::experiments {

/// From metadata lines controller_kp_Nm_per_rad and controller_kd_Nms_per_rad ("k1,...,kn", one
/// per joint), feedforward (true|false), and optionally controller_ki_Nm_per_rad_s,
/// controller_derivative_cutoff_Hz, controller_integral_limit_Nm, controller_law
/// (pd_measured_velocity: the derivative from the measured velocity; else the error's filtered
/// difference), actuator_bandwidth_Hz, hip_locked (true|false) and locked_joints ("j1,j2").
/// Throws std::invalid_argument naming `source` and the missing or malformed key.
ident::Controller controllerFromMetadata(const ident::Dataset& d, const std::string& source);

/// From a JSON file: {"kp": [one per joint], "kd": [..], "ki": [..], "derivative":
/// "error_difference"|"measured_velocity", "derivative_cutoff_hz": 100, "integral_limit_Nm": 500,
/// "feedforward": "model"|"none", "actuator_bandwidth_hz": 0, "locked": ["hip"], "hip_locked":
/// false}; kp and kd are required, the rest default to 0 / error_difference / none / no limit /
/// none locked. Throws std::invalid_argument naming the file and the field.
ident::Controller readControllerJson(const std::string& path, const std::vector<std::string>& joints);

/// The reference from the dataset's q_<joint>_ref columns (rad), one per joint; throws
/// std::invalid_argument naming `source` when one is missing.
ident::Reference referenceOf(const ident::Dataset& d, const std::string& source);

/// What IDIM-IV needs of a record besides its rows: the reference and the controller it tracked
/// (from controller_json if not empty, else the record's metadata), the processing its rows were
/// made with. locked_from: the joints above it are held by a lock (a segmental stage's record), 0 = none.
ident::ClosedLoopRecord closedLoopRecord(const ident::Dataset& d, const std::string& source, const ident::RecordRows& rows,
                                         const ident::SignalOptions& signals, const std::string& controller_json,
                                         Eigen::Index locked_below = 0);

}  // namespace exoid::experiments
