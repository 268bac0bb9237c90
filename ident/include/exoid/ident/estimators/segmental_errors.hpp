#pragma once
// What identify reports of a segmental least-squares estimate: reportedErrors' rules (Newey-West
// from the residuals, the jackknife over blocks of the records and over whole records, the larger
// of the two), applied stage by stage, with what each stage inherits from the stages before it.
//
// A stage's torque side subtracts the combinations the earlier stages found, so their errors carry
// into it: LS is linear in that torque, x_s = x_s(own rows) + A_s x_earlier, with A_s the stage's
// least-squares solution of the change in its torque side per unit of an earlier value. The
// stages' records are independent, so each stage's own covariance (Newey-West, or a jackknife's)
// is carried down the later stages by (I - A)^-1 and the stages' parts add. The part of an earlier
// error a stage cannot absorb stays in its residuals too: conservative when an earlier record is
// much noisier than the later one's.
#include "exoid/ident/estimators/segmental.hpp"
#include "exoid/ident/estimators/standard_errors.hpp"

namespace exoid::ident {

/// The reported errors of `ls` (identifySegmental's with Method::kLs on these stages), in the
/// robot's parameters. A parameter no stage identifies has error 0. Throws as SegmentalPlan does.
ReportedErrors segmentalReportedErrors(const Robot& robot, const std::vector<SegmentalStage>& stages, const SegmentalResult& ls,
                                       const BaseParameterOptions& structure = {});

}  // namespace exoid::ident
