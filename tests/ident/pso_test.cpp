#include "exoid/ident/estimators/pso.hpp"

#include "exoid/ident/estimators/linear_cost.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

namespace exoid::ident {
namespace {

BatchCost columnwise(double (*f)(const Eigen::VectorXd&)) {
  return [f](const Eigen::Ref<const Eigen::MatrixXd>& X, Eigen::Ref<Eigen::VectorXd> c) {
    for (Eigen::Index j = 0; j < X.cols(); ++j) c[j] = f(X.col(j));
  };
}
double sphere(const Eigen::VectorXd& x) { return (x.array() - 1.5).square().sum(); }
double rosenbrock(const Eigen::VectorXd& x) {
  double s = 0.0;
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
    s += 100.0 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1.0 - x[i], 2);
  }
  return s;
}

TEST(Pso, FindsSphereMinimumInABox) {
  PsoOptions o;
  o.max_iterations = 2000;
  o.cost_tolerance = 1e-12;
  const PsoResult r = minimizePso(columnwise(sphere), Box::uniform(5, -10.0, 10.0), o);
  EXPECT_EQ(r.summary.status, Status::kConverged);
  // cost < 1e-12 means |x - 1.5| < 1e-6 in every coordinate.
  EXPECT_LT((r.x.array() - 1.5).abs().maxCoeff(), 1e-6);
  EXPECT_EQ(r.best_cost_history.size(), static_cast<std::size_t>(r.summary.iterations) + 1);
  for (std::size_t k = 1; k < r.best_cost_history.size(); ++k) {
    EXPECT_LE(r.best_cost_history[k], r.best_cost_history[k - 1]);  // best-so-far never rises
  }
}

TEST(Pso, FindsRosenbrockMinimumInABox) {
  PsoOptions o;
  o.max_iterations = 5000;
  o.cost_tolerance = 1e-10;
  o.boundary = BoundaryPolicy::kReflect;
  const PsoResult r = minimizePso(columnwise(rosenbrock), Box::uniform(2, -2.0, 2.0), o);
  // Rosenbrock's valley: cost 1e-10 allows |x - 1| up to ~1e-4.
  EXPECT_LT(r.cost, 1e-8);
  EXPECT_LT((r.x.array() - 1.0).abs().maxCoeff(), 1e-3);
}

TEST(Pso, MinimumOnTheBoundIsReachedWithClamping) {
  PsoOptions o;
  o.max_iterations = 300;
  o.cost_tolerance = 0.0;
  // Sphere centred at 1.5 but the box stops at 1: the minimum is the corner (1, ..., 1).
  const PsoResult r = minimizePso(columnwise(sphere), Box::uniform(3, -5.0, 1.0), o);
  EXPECT_LT((r.x.array() - 1.0).abs().maxCoeff(), 1e-9);
}

TEST(Pso, SameSeedSameResultDifferentSeedDiffers) {
  PsoOptions o;
  o.max_iterations = 200;
  o.cost_tolerance = 0.0;
  const Box box = Box::uniform(4, -3.0, 3.0);
  const PsoResult a = minimizePso(columnwise(rosenbrock), box, o);
  const PsoResult b = minimizePso(columnwise(rosenbrock), box, o);
  EXPECT_TRUE(a.x == b.x);
  EXPECT_EQ(a.best_cost_history, b.best_cost_history);
  o.seed = 2;
  const PsoResult c = minimizePso(columnwise(rosenbrock), box, o);
  EXPECT_FALSE(a.x == c.x);
}

TEST(Pso, StaysInsideTheBox) {
  for (BoundaryPolicy policy : {BoundaryPolicy::kClamp, BoundaryPolicy::kReflect}) {
    PsoOptions o;
    o.max_iterations = 100;
    o.boundary = policy;
    o.velocity_fraction = 1.0;
    o.cost_tolerance = 0.0;
    const Box box = Box::uniform(3, 0.0, 1.0);
    const PsoResult r = minimizePso(
        [&](const Eigen::Ref<const Eigen::MatrixXd>& X, Eigen::Ref<Eigen::VectorXd> c) {
          for (Eigen::Index j = 0; j < X.cols(); ++j) {
            ASSERT_TRUE(box.contains(X.col(j))) << toString(policy);
            c[j] = 3.0 - X.col(j).sum();  // minimum 0 at the corner (1, 1, 1)
          }
        },
        box, o);
    EXPECT_LT(r.cost, 1e-6);  // the optimum is the box corner
  }
}

TEST(Pso, NonFiniteCostIsAFailureNotAResult) {
  PsoOptions o;
  o.max_iterations = 10;
  const PsoResult r = minimizePso(
      [](const Eigen::Ref<const Eigen::MatrixXd>&, Eigen::Ref<Eigen::VectorXd> c) { c.setConstant(std::nan("")); },
      Box::uniform(2, 0.0, 1.0), o);
  EXPECT_EQ(r.summary.status, Status::kFailed);
}

TEST(Pso, RejectsBadOptionsNamingTheField) {
  PsoOptions o;
  o.w_min = 1.0;
  o.w_max = 0.5;
  try {
    minimizePso(columnwise(sphere), Box::uniform(2, 0.0, 1.0), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'w_min'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(minimizePso(columnwise(sphere), Box::uniform(2, 1.0, 0.0), PsoOptions{}), std::invalid_argument);
}

TEST(LinearResidualCost, BatchEqualsOneAtATimeForEveryDimension) {
  std::mt19937_64 gen(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int p = 1; p <= 12; ++p) {
    for (CostNorm norm : {CostNorm::kL1, CostNorm::kL2}) {
      const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(1003, p, [&] { return n01(gen); });
      const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(1003, [&] { return n01(gen); });
      const LinearResidualCost cost(A, b, norm);
      const Eigen::MatrixXd X = Eigen::MatrixXd::NullaryExpr(p, 13, [&] { return n01(gen); });
      Eigen::VectorXd batch(13);
      cost.evaluate(X, batch);
      for (Eigen::Index j = 0; j < 13; ++j) {
        const Eigen::VectorXd r = b - A * X.col(j);
        const double expected = norm == CostNorm::kL1 ? r.cwiseAbs().sum() : r.squaredNorm();
        // Different summation order: roundoff ~ N * eps * |terms| ~ 1e3 * 1e-16 * 1e3.
        EXPECT_NEAR(batch[j], expected, 1e-10 * expected) << "p " << p << " j " << j;
      }
    }
  }
}

// Every instruction set's kernel gives the generic kernel's bits (same lanes, same summation order,
// no contraction), so a PSO run is the same on every machine: compared for p = 1..10, both norms,
// a partial last block and particles that are a block of a larger matrix (outer stride != p).
TEST(LinearResidualCost, EveryKernelTheCpuRunsGivesTheSameBits) {
  std::mt19937_64 gen(12);
  std::normal_distribution<double> n01(0.0, 1.0);
  const std::vector<CostKernel> kernels = supportedCostKernels();
  ASSERT_FALSE(kernels.empty());
  EXPECT_EQ(kernels.front(), CostKernel::kGeneric);
  for (int p = 1; p <= 10; ++p) {
    for (CostNorm norm : {CostNorm::kL1, CostNorm::kL2}) {
      const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(997, p, [&] { return n01(gen); });
      const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(997, [&] { return n01(gen); });
      const Eigen::MatrixXd big = Eigen::MatrixXd::NullaryExpr(p + 3, 21, [&] { return n01(gen); });
      LinearResidualCost cost(A, b, norm);
      cost.useKernel(CostKernel::kGeneric);
      Eigen::VectorXd reference(21);
      cost.evaluate(big.topRows(p), reference);
      for (CostKernel k : kernels) {
        cost.useKernel(k);
        EXPECT_EQ(cost.kernel(), k);
        Eigen::VectorXd costs(21);
        cost.evaluate(big.topRows(p), costs);
        for (Eigen::Index j = 0; j < 21; ++j) {
          EXPECT_EQ(costs[j], reference[j]) << toString(k) << " p " << p << " j " << j;
          const double expected = norm == CostNorm::kL1 ? (b - A * big.col(j).head(p)).cwiseAbs().sum()
                                                        : (b - A * big.col(j).head(p)).squaredNorm();
          EXPECT_NEAR(costs[j], expected, 1e-10 * expected);
        }
      }
    }
  }
}

TEST(LinearResidualCost, KernelNamesParseAndTheDefaultFollowsTheEnvironment) {
  for (CostKernel k : {CostKernel::kAuto, CostKernel::kGeneric, CostKernel::kAvx2, CostKernel::kAvx512}) {
    EXPECT_EQ(parseCostKernel(toString(k)), k);
  }
  try {
    parseCostKernel("sse9");
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected auto, generic, avx2 or avx512"), std::string::npos) << e.what();
  }
  // ctest runs this test a second time with EXOID_COST_KERNEL=generic (tests/CMakeLists.txt).
  const char* env = std::getenv("EXOID_COST_KERNEL");
  if (env != nullptr && std::string(env) != "auto") {
    EXPECT_EQ(defaultCostKernel(), parseCostKernel(env));
  } else {
    EXPECT_EQ(defaultCostKernel(), supportedCostKernels().back());  // the widest the CPU runs
  }
  const LinearResidualCost cost(Eigen::MatrixXd::Ones(3, 2), Eigen::VectorXd::Ones(3));
  EXPECT_EQ(cost.kernel(), defaultCostKernel());
}

}  // namespace
}  // namespace exoid::ident
