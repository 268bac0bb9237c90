#include "exoid/ident/estimators/summary.hpp"

namespace exoid::ident {

const char* toString(Status s) {
  switch (s) {
    case Status::kConverged: return "converged";
    case Status::kMaxIterations: return "max_iterations";
    case Status::kRankDeficient: return "rank_deficient";
    case Status::kIllConditioned: return "ill_conditioned";
    case Status::kFailed: return "failed";
  }
  return "unknown";
}

}  // namespace exoid::ident
