#include "exoid/ident/segmental.hpp"

#include <stdexcept>
#include <string>

namespace exoid::ident {

SegmentalProblem kneeStage(const JointSignals& knee_record, const LegConstants& c) {
  return {jointRegressor(knee_record, Joint::kKnee, c).middleCols(kShankFirst, kGroupSize),
          knee_record.tau_Nm.col(1)};
}

SegmentalProblem hipStage(const JointSignals& both_record, const Eigen::Ref<const Eigen::VectorXd>& x_knee,
                          const LegConstants& c) {
  if (x_knee.size() != kGroupSize) {
    throw std::invalid_argument("segmental hip stage: expected 5 knee parameters, got " +
                                std::to_string(x_knee.size()));
  }
  const Eigen::MatrixXd Hh = jointRegressor(both_record, Joint::kHip, c);
  return {Hh.middleCols(kThighFirst, kGroupSize),
          both_record.tau_Nm.col(0) - Hh.middleCols(kShankFirst, kGroupSize) * x_knee};
}

SegmentalResult identifySegmental(Method method, const JointSignals& knee_record,
                                  const JointSignals& both_record, const LegConstants& c,
                                  const MethodOptions& options) {
  SegmentalResult r;
  const SegmentalProblem knee = kneeStage(knee_record, c);
  r.knee = estimate(method, knee.H, knee.y, options);
  const SegmentalProblem hip = hipStage(both_record, r.knee.x, c);
  r.hip = estimate(method, hip.H, hip.y, options);
  r.x << r.hip.x, r.knee.x;
  return r;
}

}  // namespace exoid::ident
