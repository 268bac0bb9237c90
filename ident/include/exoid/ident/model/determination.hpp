#pragma once
// Which parameters a record's own motion determines. A joint the record never moved (a locked
// hip, a joint held by its controller) leaves the parameters only its motion shows undetermined,
// however well column scaling conditions the regressor: their columns are then the noise of a
// still joint (a velocity's, an acceleration's, the sign of either) or constants that only fix a
// combination (a link's first moments at one angle). The test, for any robot:
//   1. each joint's angle range in the recorded (raw) angles against a floor: the range its
//      angle noise alone would span over the record (the noise estimated from the angle's second
//      differences), or a thousandth of the widest joint range in the record, whichever is larger;
//      the base (when the record has the IMU's columns) moved when one of its channels spans more
//      than its own noise would;
//   2. the record's rows recomputed with every held joint frozen (its angle at its mean, its rate
//      and acceleration zero; a still base at its mean specific force, not turning), over the
//      equations fitted: a parameter outside the row space of those rows (a null direction of the
//      column-scaled rows touches it) is not determined. An IMU's noise on a still base, like an
//      encoder's on a held joint, determines nothing.
#include "exoid/ident/io/dataset.hpp"
#include "exoid/ident/model/robot.hpp"
#include "exoid/ident/signals/processing.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace exoid::ident {

/// One recorded signal's motion: a joint's angle (rad) or an IMU channel (its column's unit).
struct SignalMotion {
  std::string name;
  double range = 0.0;  ///< max - min over the record
  double noise = 0.0;  ///< the signal's noise standard deviation, estimated from the record
  double floor = 0.0;  ///< the range below which it counts as still
  bool moved() const { return range > floor; }
};

struct RecordMotion {
  std::vector<SignalMotion> joints;  ///< per joint, in the record's order
  std::vector<SignalMotion> base;    ///< base_acc_x, base_acc_z, base_gyro_y when recorded; else empty
  bool baseMoved() const;            ///< false without IMU columns
};

/// Each joint's and the base's motion in one record's recorded signals. Throws
/// std::invalid_argument for fewer than 3 samples.
RecordMotion recordMotion(const Dataset& d);

struct Determination {
  std::vector<RecordMotion> records;
  std::vector<int> undetermined;                  ///< parameters not determined, ascending
  /// "Mxt, Myt, Jt (hip held in every record: range 6e-06 rad, floor 0.001 rad)", or "" when all are.
  std::string describe(const Robot& robot) const;
};

/// The parameters among `unknowns` that the records do not determine by their own motion (the
/// test above). `rows`: the records' processed rows stacked in the order of `records` (their
/// states give the frozen rows); `equations`: the joints whose equations are fitted (empty: all);
/// known parameters are simply not among `unknowns`. Throws std::invalid_argument when the records
/// and rows disagree.
Determination determination(const Robot& robot, const std::vector<Dataset>& records, const RecordRows& rows,
                            const std::vector<int>& unknowns, const std::vector<Eigen::Index>& equations = {});

/// One stage of a segmental strategy: its records, their processed rows stacked (both outlive the
/// call), the joints whose equations it fits (empty: all), and what it fits: the combinations of
/// the robot's parameters in the columns of `directions` (parameters x k), the others known.
struct DeterminationStage {
  const std::vector<Dataset>* records = nullptr;
  const RecordRows* rows = nullptr;
  std::vector<Eigen::Index> equations;
  Eigen::MatrixXd directions;
};
/// The test stage by stage, as the segmental fit runs (each stage from its own records alone): a
/// combination a stage's own motion leaves open leaves every parameter it carries (a component
/// above 1e-3) undetermined. `records` lists every stage's, in order. Throws std::invalid_argument
/// when a stage's records and rows disagree or its directions are not one row per parameter.
Determination determination(const Robot& robot, const std::vector<DeterminationStage>& stages);
/// The unit columns of `unknowns` (parameters x unknowns.size()): a stage fitting those parameters.
Eigen::MatrixXd parameterDirections(const Robot& robot, const std::vector<int>& unknowns);

}  // namespace exoid::ident
