#pragma once
// The paper's segmental strategy (Fig. 5, Eq. 9): knee parameters X(6:10) from a knee-only record
// (hip fixed), then hip parameters X(1:5) from a record where both joints swing, after
// subtracting the knee part of the hip equation: T1' = T1 - H_hip(6:10) X(6:10).
#include "exoid/ident/estimators/methods.hpp"
#include "exoid/ident/signals/preprocess.hpp"
#include "exoid/ident/leg/regressor.hpp"

namespace exoid::ident {

/// The two linear problems of the strategy, for any estimator.
struct SegmentalProblem {
  Eigen::MatrixXd H;  ///< N x 5
  Eigen::VectorXd y;  ///< N
};
/// Both equations of a record, all 10 columns, in time order: row 2i is sample i's hip equation,
/// 2i+1 its knee equation (so RLS sees the record in order).
/// With knee_armature, an 11th column (kKneeArmature): 0 in hip rows, knee_armature in knee rows.
SegmentalProblem bothEquations(const ProcessedRecord& record, bool knee_armature = false);
/// Stage 1: knee equation of the knee record, columns 6-10. (No knee armature here: with the hip
/// fixed, its column qdd2 is Js's, so only Js + Ia2 is identifiable; bothEquations separates them
/// on a record where the hip moves, since Js also enters the hip equation.)
SegmentalProblem kneeStage(const ProcessedRecord& knee_record);
/// Stage 2: hip equation of the two-joint record, columns 1-5, with the knee part subtracted
/// (x_knee: Mxs..fv2; the armature does not act on the hip equation).
SegmentalProblem hipStage(const ProcessedRecord& both_record, const Eigen::Ref<const Eigen::VectorXd>& x_knee);
/// The same on signals as they are (regressorRecord).
SegmentalProblem kneeStage(const JointSignals& knee_record, const LegConstants& c);
SegmentalProblem hipStage(const JointSignals& both_record, const Eigen::Ref<const Eigen::VectorXd>& x_knee,
                          const LegConstants& c);

struct SegmentalResult {
  Estimate knee;  ///< over Mxs, Mys, Js, fc2, fv2
  Estimate hip;   ///< over Mxt, Myt, Jt, fc1, fv1
  ParamVector x;  ///< the assembled 10-vector
};

SegmentalResult identifySegmental(Method method, const ProcessedRecord& knee_record,
                                  const ProcessedRecord& both_record, const MethodOptions& options);
SegmentalResult identifySegmental(Method method, const JointSignals& knee_record,
                                  const JointSignals& both_record, const LegConstants& c,
                                  const MethodOptions& options);

}  // namespace exoid::ident
