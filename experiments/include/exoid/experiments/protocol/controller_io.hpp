#pragma once
// The controller and reference a log was recorded under, as IDIM-IV needs them: from a dataset's "# controller_*" metadata (exoid simulate writes them), or
// from a JSON file describing a real rig's controller.
#include "exoid/ident/leg/closed_loop.hpp"
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/estimators/idim_iv.hpp"
#include "exoid/ident/model/chain_closed_loop.hpp"

#include <string>

namespace exoid::experiments {

/// From metadata lines controller_kp_Nm_per_rad, controller_ki_Nm_per_rad_s,
/// controller_kd_Nms_per_rad ("hip,knee"), controller_derivative_cutoff_Hz,
/// controller_integral_limit_Nm, feedforward (true|false), hip_locked (true|false). Throws
/// std::invalid_argument naming `source` and the missing or malformed key.
ident::ControllerModel controllerFromMetadata(const ident::Dataset& d, const std::string& source);

/// From a JSON file: {"kp": [hip, knee], "ki": [..], "kd": [..], "derivative_cutoff_hz": 100,
/// "integral_limit_Nm": 500, "feedforward": "model"|"none", "hip_locked": false}; kp and kd are
/// required, the rest default to 0 / none / no limit / false. Throws std::invalid_argument naming
/// the file and the field.
ident::ControllerModel readControllerJson(const std::string& path);

/// The reference from the dataset's q_hip_ref and q_knee_ref columns (rad); throws
/// std::invalid_argument naming `source` when they are missing.
ident::Reference referenceOf(const ident::Dataset& d, const std::string& source);
/// What IDIM-IV needs of a record besides its rows: the reference and the controller it tracked
/// (from controller_json if not empty, else the record's metadata). knee_only_record: the
/// segmental strategy's knee record, its hip held fixed.
ident::ClosedLoopRecord closedLoopRecord(const ident::Dataset& d, const std::string& source,
                                         const ident::ProcessedRecord& rows, const std::string& controller_json,
                                         bool knee_only_record);

/// A chain record's controller from its metadata lines (exoid simulate --model writes them):
/// controller_kp_Nm_per_rad and controller_kd_Nms_per_rad ("k1,...,kn", one per joint),
/// feedforward (true|false), actuator_bandwidth_Hz (optional, 0). Throws std::invalid_argument
/// naming `source` and the missing or malformed key.
ident::ChainController chainControllerFromMetadata(const ident::Dataset& d, const std::string& source);
/// From a JSON file: {"kp": [one per joint], "kd": [..], "feedforward": "model"|"none",
/// "actuator_bandwidth_hz": 0}; kp and kd required (the law: u = ff + kp (q_ref - q) + kd (qd_ref -
/// qd), the velocity measured). Throws std::invalid_argument naming the file and the field.
ident::ChainController readChainControllerJson(const std::string& path, int dof);
/// The reference from the dataset's q_<joint>_ref columns (rad), one per joint.
ident::ChainReference chainReferenceOf(const ident::Dataset& d, const std::string& source);

}  // namespace exoid::experiments
