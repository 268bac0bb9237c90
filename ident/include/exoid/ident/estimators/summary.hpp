#pragma once
// The result summary every estimator shares (Ceres-style): status, message, counts, costs, time.
#include <string>

namespace exoid::ident {

enum class Status {
  kConverged,      ///< met its stopping rule (tolerance, exact solve)
  kMaxIterations,  ///< stopped at its iteration limit; the estimate is the best found
  kRankDeficient,  ///< the data cannot separate some parameters (named in the message)
  kIllConditioned,  ///< full rank, but conditioning beyond LsOptions::max_condition: not usable
  kFailed,         ///< numerical failure; the estimate must not be used
};
const char* toString(Status s);
/// True when the estimate can be used (converged or stopped at the iteration limit).
inline bool usable(Status s) { return s == Status::kConverged || s == Status::kMaxIterations; }

struct Summary {
  Status status = Status::kFailed;
  std::string message;
  long iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double wall_time_s = 0.0;
};

}  // namespace exoid::ident
