#include "exoid/ident/estimators/segmental.hpp"

#include "exoid/core/format.hpp"

#include <stdexcept>
#include <string>

namespace exoid::ident {

SegmentalProblem bothEquations(const ProcessedRecord& r, bool knee_armature) {
  const Eigen::Index n = r.size();
  const Eigen::Index cols = kNumParams + (knee_armature ? 1 : 0);
  SegmentalProblem p{Eigen::MatrixXd::Zero(2 * n, cols), Eigen::VectorXd(2 * n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    p.H.row(2 * i).head(kNumParams) = r.hip.row(i);
    p.H.row(2 * i + 1).head(kNumParams) = r.knee.row(i);
    if (knee_armature) p.H(2 * i + 1, kKneeArmature) = r.knee_armature[i];
    p.y[2 * i] = r.tau_Nm(i, 0);
    p.y[2 * i + 1] = r.tau_Nm(i, 1);
  }
  return p;
}

SegmentalProblem kneeStage(const ProcessedRecord& r) {
  return {r.knee.middleCols(kShankFirst, kGroupSize), r.tau_Nm.col(1)};
}

SegmentalProblem hipStage(const ProcessedRecord& r, const Eigen::Ref<const Eigen::VectorXd>& x_knee) {
  if (x_knee.size() != kGroupSize) {
    throw std::invalid_argument("segmental hip stage: expected 5 knee parameters, got " +
                                core::toText(x_knee.size()));
  }
  return {r.hip.middleCols(kThighFirst, kGroupSize), r.tau_Nm.col(0) - r.hip.middleCols(kShankFirst, kGroupSize) * x_knee};
}

SegmentalProblem kneeStage(const JointSignals& knee_record, const LegConstants& c) {
  return kneeStage(regressorRecord(knee_record, c));
}

SegmentalProblem hipStage(const JointSignals& both_record, const Eigen::Ref<const Eigen::VectorXd>& x_knee,
                          const LegConstants& c) {
  return hipStage(regressorRecord(both_record, c), x_knee);
}

SegmentalResult identifySegmental(Method method, const ProcessedRecord& knee_record, const ProcessedRecord& both_record,
                                  const MethodOptions& options) {
  SegmentalResult r;
  const SegmentalProblem knee = kneeStage(knee_record);
  r.knee = estimate(method, knee.H, knee.y, options);
  const SegmentalProblem hip = hipStage(both_record, r.knee.x);
  r.hip = estimate(method, hip.H, hip.y, options);
  r.x << r.hip.x, r.knee.x;
  return r;
}

SegmentalResult identifySegmental(Method method, const JointSignals& knee_record,
                                  const JointSignals& both_record, const LegConstants& c,
                                  const MethodOptions& options) {
  return identifySegmental(method, regressorRecord(knee_record, c), regressorRecord(both_record, c), options);
}

}  // namespace exoid::ident
