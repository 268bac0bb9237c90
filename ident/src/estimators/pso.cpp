#include "exoid/ident/estimators/pso.hpp"

#include "exoid/core/format.hpp"
#include "exoid/core/random.hpp"
#include "exoid/ident/estimators/stopwatch.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace exoid::ident {

const char* toString(BoundaryPolicy p) { return p == BoundaryPolicy::kClamp ? "clamp" : "reflect"; }

void PsoOptions::validate() const {
  auto fail = [](const char* name, const std::string& range, double v) {
    throw std::invalid_argument(std::string("'") + name + "' must be " + range + ", got " +
                                core::toText(v));
  };
  if (swarm_size < 2) fail("swarm_size", ">= 2", swarm_size);
  if (max_iterations < 1) fail("max_iterations", ">= 1", static_cast<double>(max_iterations));
  if (!(cost_tolerance >= 0.0)) fail("cost_tolerance", ">= 0", cost_tolerance);
  if (!(w_max > 0.0 && w_max < 2.0)) fail("w_max", "in (0, 2)", w_max);
  if (!(w_min > 0.0 && w_min <= w_max)) fail("w_min", "in (0, w_max]", w_min);
  if (!(c1 >= 0.0 && std::isfinite(c1))) fail("c1", ">= 0", c1);
  if (!(c2 >= 0.0 && std::isfinite(c2))) fail("c2", ">= 0", c2);
  if (!(velocity_fraction > 0.0 && velocity_fraction <= 1.0)) fail("velocity_fraction", "in (0, 1]", velocity_fraction);
}

namespace {

// The swarm: positions and velocities (one column per particle), each particle's best, the best of all.
struct Swarm {
  Eigen::MatrixXd x, v;
  Eigen::VectorXd f;  ///< the cost at x
  Eigen::MatrixXd pbest;
  Eigen::VectorXd pbest_f;
  Eigen::VectorXd gbest;
  double gbest_f = 0.0;
};

// Positions uniform in the box, velocities uniform in +-vmax, drawn particle by particle; then
// evaluated, each particle its own best.
Swarm initialSwarm(const BatchCost& cost, const Box& box, const Eigen::VectorXd& vmax, Eigen::Index S, core::Rng& rng) {
  const Eigen::Index p = box.dim();
  Swarm s;
  s.x.resize(p, S);
  s.v.resize(p, S);
  for (Eigen::Index j = 0; j < S; ++j) {
    for (Eigen::Index k = 0; k < p; ++k) {
      s.x(k, j) = rng.uniform(box.lower[k], box.upper[k]);
      s.v(k, j) = rng.uniform(-vmax[k], vmax[k]);
    }
  }
  s.f.resize(S);
  cost(s.x, s.f);
  s.pbest = s.x;
  s.pbest_f = s.f;
  Eigen::Index g;
  s.gbest_f = s.pbest_f.minCoeff(&g);
  s.gbest = s.pbest.col(g);
  return s;
}

// One step of every particle at inertia w: velocity pulled toward its own and the swarm's best
// (clamped to +-vmax), position moved by it and kept in the box by the boundary policy.
void moveSwarm(Swarm& s, const Box& box, const Eigen::VectorXd& vmax, double w, const PsoOptions& o, core::Rng& rng) {
  Eigen::MatrixXd& x = s.x;
  Eigen::MatrixXd& v = s.v;
  const Eigen::MatrixXd& pbest = s.pbest;
  const Eigen::VectorXd& gbest = s.gbest;
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    for (Eigen::Index k = 0; k < x.rows(); ++k) {
      const double r1 = rng.uniform(), r2 = rng.uniform();
      double vk = w * v(k, j) + o.c1 * r1 * (pbest(k, j) - x(k, j)) + o.c2 * r2 * (gbest[k] - x(k, j));
      vk = std::clamp(vk, -vmax[k], vmax[k]);
      double xk = x(k, j) + vk;
      if (xk < box.lower[k] || xk > box.upper[k]) {
        const double bound = xk < box.lower[k] ? box.lower[k] : box.upper[k];
        if (o.boundary == BoundaryPolicy::kClamp) {
          xk = bound;
        } else {
          xk = std::clamp(2.0 * bound - xk, box.lower[k], box.upper[k]);
          vk = -vk;
        }
      }
      x(k, j) = xk;
      v(k, j) = vk;
    }
  }
}

// Each particle's best and the swarm's, from the costs at the new positions.
void updateBests(Swarm& s) {
  for (Eigen::Index j = 0; j < s.f.size(); ++j) {
    if (s.f[j] < s.pbest_f[j]) {
      s.pbest_f[j] = s.f[j];
      s.pbest.col(j) = s.x.col(j);
      if (s.f[j] < s.gbest_f) {
        s.gbest_f = s.f[j];
        s.gbest = s.x.col(j);
      }
    }
  }
}

// The status of a search that did not fail: below the tolerance, or out of iterations.
void finishSummary(PsoResult& r, const PsoOptions& o) {
  if (r.cost < o.cost_tolerance) {
    r.summary.status = Status::kConverged;
    r.summary.message = "best cost below cost_tolerance after " + core::toText(r.summary.iterations) + " iterations";
  } else {
    r.summary.status = Status::kMaxIterations;
    r.summary.message = "stopped at max_iterations = " + core::toText(o.max_iterations);
  }
}

}  // namespace

PsoResult minimizePso(const BatchCost& cost, const Box& box, const PsoOptions& o) {
  o.validate();
  box.validate();
  Stopwatch clock;
  const Eigen::Index S = o.swarm_size;
  const Eigen::VectorXd vmax = o.velocity_fraction * (box.upper - box.lower);
  core::Rng rng(o.seed);
  Swarm s = initialSwarm(cost, box, vmax, S, rng);

  PsoResult r;
  r.evaluations = S;
  r.summary.initial_cost = s.gbest_f;
  if (o.keep_history) {
    r.best_cost_history.reserve(static_cast<std::size_t>(o.max_iterations) + 1);
    r.best_cost_history.push_back(s.gbest_f);
  }
  bool failed = false;
  auto nonFinite = [&](const char* when) {
    failed = true;
    r.summary.status = Status::kFailed;
    r.summary.message = std::string("cost returned NaN or Inf ") + when;
  };
  if (!s.f.allFinite()) nonFinite("at initialisation");

  long it = 0;
  const double span = o.max_iterations > 1 ? static_cast<double>(o.max_iterations - 1) : 1.0;
  while (!failed && s.gbest_f >= o.cost_tolerance && it < o.max_iterations) {
    const double w = o.w_max - (o.w_max - o.w_min) * static_cast<double>(it) / span;
    moveSwarm(s, box, vmax, w, o, rng);
    cost(s.x, s.f);
    r.evaluations += S;
    ++it;
    if (!s.f.allFinite()) {
      nonFinite("during the search");
      break;
    }
    updateBests(s);
    if (o.keep_history) r.best_cost_history.push_back(s.gbest_f);
  }

  r.x = s.gbest;
  r.cost = s.gbest_f;
  r.summary.iterations = it;
  r.summary.final_cost = s.gbest_f;
  if (!failed) finishSummary(r, o);
  r.summary.wall_time_s = clock.seconds();
  return r;
}

}  // namespace exoid::ident
