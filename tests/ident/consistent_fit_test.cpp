#include "exoid/ident/model/consistent_fit.hpp"

#include "exoid/ident/leg/consistency.hpp"
#include "exoid/ident/model/newton_euler.hpp"
#include "exoid/ident/model/log_cholesky.hpp"

#include "exoid/ident/leg/params.hpp"
#include "random_chain.hpp"

#include <Eigen/LU>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <random>

namespace exoid::ident {
namespace {

constexpr double kFitLt_m = 0.45;


// Set B (docs/paper.md) as standard parameters: the thigh 13 kg, COM (-0.2, 0, -0.31), Iyy 0.28
// about the COM; the shank 4 kg, COM (0.08, 0, -0.32), Iyy 0.16.
Eigen::VectorXd setB() {
  Eigen::VectorXd phi(24);
  phi.segment<10>(0) = linkParameters(13.0, {-0.2, 0.0, -0.31}, Eigen::Vector3d(0.28, 0.28, 0.03).asDiagonal());
  phi.segment<2>(10) << 1.5, 0.6;
  phi.segment<10>(12) = linkParameters(4.0, {0.08, 0.0, -0.32}, Eigen::Vector3d(0.16, 0.16, 0.01).asDiagonal());
  phi.segment<2>(22) << 0.35, 0.25;
  return phi;
}

struct Record {
  Eigen::MatrixXd W;
  Eigen::VectorXd y;
};

Record exactRecord(const ChainModel& model, const Eigen::VectorXd& phi, int samples, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Record r{Eigen::MatrixXd(2 * samples, model.standardParameterCount()), Eigen::VectorXd(2 * samples)};
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector2d q(2 * u(gen), 1 + u(gen)), qd(3 * u(gen), 3 * u(gen)), qdd(20 * u(gen), 20 * u(gen));
    r.W.middleRows(2 * s, 2) = chainRegressor(model, q, qd, qdd);
  }
  r.y = r.W * phi;
  return r;
}

TEST(LogCholesky, RoundTripAndJacobian) {
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    LinkVector theta;
    for (int k = 0; k < kLinkParams; ++k) theta[k] = u(gen);
    const LinkVector phi = linkFromLogCholesky(theta);
    EXPECT_GT(pseudoInertiaMinEigenvalue(phi), 0.0);
    EXPECT_LE((logCholeskyFromLink(phi) - theta).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE((linkFromPseudoInertia(pseudoInertia(phi)) - phi).cwiseAbs().maxCoeff(), 1e-14);
    // Central differences: truncation ~h^2 phi''' ~ 1e-10 at h = 1e-5.
    const Eigen::Matrix<double, kLinkParams, kLinkParams> D = linkFromLogCholeskyJacobian(theta);
    for (int k = 0; k < kLinkParams; ++k) {
      LinkVector a = theta, b = theta;
      a[k] += 1e-5;
      b[k] -= 1e-5;
      const LinkVector fd = (linkFromLogCholesky(a) - linkFromLogCholesky(b)) / 2e-5;
      EXPECT_LE((fd - D.col(k)).cwiseAbs().maxCoeff(), 1e-7 * std::max(1.0, fd.cwiseAbs().maxCoeff())) << "column " << k;
    }
  }
  // A point mass off the origin has J of rank 1: not positive definite, refused by name.
  EXPECT_THROW(logCholeskyFromLink(linkParameters(1.0, {0.1, 0.0, 0.0}, Eigen::Matrix3d::Zero())), std::invalid_argument);
}

TEST(ConsistentFit, EqualsLeastSquaresWhenLeastSquaresIsConsistent) {
  const ChainModel model = testing::apalChain(kFitLt_m);
  const BaseParameters base = baseParameters(model);
  const Eigen::VectorXd truth = setB();
  const Record rec = exactRecord(model, truth, 400, 1);
  // Started far from the truth: a generic 1 kg body per link, frictions at 1.
  const ConsistentFit fit = consistentFit(model, base, rec.W, rec.y, Eigen::VectorXd::Zero(24));
  EXPECT_EQ(fit.status, ConsistentFitStatus::kLeastSquaresConsistent) << fit.message;
  const Eigen::VectorXd beta_true = base.combination * truth;
  EXPECT_LE((fit.beta_ls - beta_true).cwiseAbs().maxCoeff(), 1e-9 * beta_true.cwiseAbs().maxCoeff());
  EXPECT_LE((fit.beta - fit.beta_ls).cwiseAbs().maxCoeff(), 1e-9 * beta_true.cwiseAbs().maxCoeff()) << fit.message;
  for (double e : fit.link_min_eigenvalue) EXPECT_GT(e, 0.0);
}

// Whichever search meets LS, LS is consistent when the excess cost is within the tolerance: with
// Levenberg-Marquardt stopped after one iteration (as it stops early when its steps' decrease falls
// below the tolerance first on an ill-conditioned A: measured on a real humanoid's leg, exact data
// then reported 6.9e3 standard errors from any consistent body), the barrier's interior search
// finishes at LS, and the status says so.
TEST(ConsistentFit, LeastSquaresMetByTheBarrierIsConsistent) {
  const ChainModel model = testing::apalChain(kFitLt_m);
  const BaseParameters base = baseParameters(model);
  const Eigen::VectorXd truth = setB();
  const Record rec = exactRecord(model, truth, 400, 1);
  ConsistentFitOptions options;
  options.max_iterations = 1;
  const ConsistentFit fit = consistentFit(model, base, rec.W, rec.y, Eigen::VectorXd::Zero(24), options);
  EXPECT_GT(fit.barrier_newton_steps, 0) << fit.message;  // the barrier finished the search
  const Eigen::VectorXd beta_true = base.combination * truth;
  EXPECT_LE((fit.beta - fit.beta_ls).cwiseAbs().maxCoeff(), 1e-9 * beta_true.cwiseAbs().maxCoeff()) << fit.message;
  EXPECT_EQ(fit.status, ConsistentFitStatus::kLeastSquaresConsistent) << fit.message;
  // An LS that no body explains stays constrained however early either search stops: the barrier's
  // unfinished centring resolves nothing (the planar leg's two inconsistent cases, noisy data).
  std::mt19937_64 gen(9);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const double fv2_offset : {-0.4, -1.0}) {
    Eigen::VectorXd phi = setB();
    phi[23] += fv2_offset;
    Record bad = exactRecord(model, phi, 400, 2);
    for (Eigen::Index k = 0; k < bad.y.size(); ++k) bad.y[k] += 0.05 * noise(gen);
    for (const int newton_steps : {1, 3, 400}) {
      ConsistentFitOptions early;
      early.max_iterations = 1;
      early.max_newton_steps = newton_steps;
      const ConsistentFit c = consistentFit(model, base, bad.W, bad.y, setB(), early);
      EXPECT_NE(c.status, ConsistentFitStatus::kLeastSquaresConsistent) << fv2_offset << ", " << newton_steps << ": " << c.message;
    }
  }
}

// The APAL leg's base parameters in the paper's X: beta = (thigh.mx, thigh.mz - Lt ms,
// thigh.Iyy + Lt^2 ms, fc1, fv1, shank.mx, shank.mz, shank.Iyy, fc2, fv2).
ParamVector toX(const Eigen::VectorXd& beta) {
  ParamVector x;
  x << -beta[1], -beta[0], beta[2] + beta[7], beta[3], beta[4], -beta[6], -beta[5], beta[7], beta[8], beta[9];
  return x;
}

TEST(ConsistentFit, AgreesWithThePlanarLegsConstrainedLeastSquares) {
  const ChainModel model = testing::apalChain(kFitLt_m);
  const BaseParameters base = baseParameters(model);
  std::mt19937_64 gen(9);
  std::normal_distribution<double> noise(0.0, 1.0);
  struct Case {
    const char* what;
    double knee_viscous_offset, shank_inertia_scale;
  };
  // A negative knee viscous friction in the data; a shank whose inertia about the knee is too
  // small for its first moment (no real body: the cone (Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2) binds).
  for (const Case c : {Case{"fv2 < 0", -0.4, 1.0}, Case{"shank too light", 0.0, 0.05}}) {
    Eigen::VectorXd phi = setB();
    phi[23] += c.knee_viscous_offset;
    phi[19] *= c.shank_inertia_scale;  // shank Iyy about the knee
    Record rec = exactRecord(model, phi, 400, 2);
    for (Eigen::Index k = 0; k < rec.y.size(); ++k) rec.y[k] += 0.05 * noise(gen);
    const ConsistentFit fit = consistentFit(model, base, rec.W, rec.y, setB());
    EXPECT_EQ(fit.status, ConsistentFitStatus::kConstrained) << c.what << ": " << fit.message;
    for (double e : fit.link_min_eigenvalue) EXPECT_GT(e, 0.0) << c.what;
    // The same problem for the planar leg's solver: H = Wb T^-1 in X coordinates.
    const Eigen::MatrixXd Wb = base.baseRegressor(rec.W);
    Eigen::MatrixXd T(10, 10);  // x = T beta
    for (int k = 0; k < 10; ++k) T.col(k) = toX(Eigen::VectorXd::Unit(10, k));
    const Eigen::MatrixXd H = Wb * T.inverse();
    const Eigen::VectorXd x_ls = H.colPivHouseholderQr().solve(rec.y);
    const Eigen::MatrixXd cov = Eigen::MatrixXd::Identity(10, 10);
    const ConsistentEstimate planar = solveConsistentLeastSquares(H, rec.y, kFitLt_m, x_ls, cov);
    ASSERT_TRUE(planar.constrained) << c.what;
    const ParamVector x = toX(fit.beta);
    // The planar solver's cone is the closure of the consistent set (it lets the thigh's mass,
    // which no torque shows, grow without bound); the generic fit bounds every mass by
    // max_link_mass_kg (1e4 kg), which moves the optimum by about (thigh first moment)^2 / 1e4
    // ~ 4e-3 kg m^2 at most, and stops its barrier within 1e-6 of the residual sum of squares.
    // So its excess cost is never below the planar one and above it by little,
    const Eigen::VectorXd d_planar = H * (planar.x - x_ls), d_fit = H * (x - x_ls);
    EXPECT_GE(d_fit.squaredNorm(), d_planar.squaredNorm() * (1.0 - 1e-9)) << c.what;
    EXPECT_LE(d_fit.squaredNorm(), d_planar.squaredNorm() * (1.0 + 1e-3)) << c.what;
    // and the parameters agree to 1e-4 of each one's scale.
    for (int k = 0; k < 10; ++k) {
      EXPECT_NEAR(x[k], planar.x[k], 1e-4 * std::max(1.0, std::abs(planar.x[k]))) << c.what << ", " << paramName(k);
    }
  }
}

// Whatever the data (here torques unrelated to the motion, on random spatial chains), every link
// comes back strictly consistent and within the bounds, every coefficient non-negative.
TEST(ConsistentFit, NeverReturnsAnInconsistentLink) {
  std::mt19937_64 gen(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const ConsistentFitOptions options;
  for (int trial = 0; trial < 8; ++trial) {
    const ChainModel model = testing::randomChain(gen, 4);
    const BaseParameters base = baseParameters(model);
    const int samples = 150;
    Eigen::MatrixXd W(4 * samples, model.standardParameterCount());
    for (int s = 0; s < samples; ++s) {
      Eigen::VectorXd q(4), qd(4), qdd(4);
      for (int k = 0; k < 4; ++k) q[k] = 3 * u(gen), qd[k] = 3 * u(gen), qdd[k] = 20 * u(gen);
      W.middleRows(4 * s, 4) = chainRegressor(model, q, qd, qdd);
    }
    Eigen::VectorXd y(W.rows());
    for (Eigen::Index k = 0; k < y.size(); ++k) y[k] = 10.0 * u(gen);
    const ConsistentFit fit = consistentFit(model, base, W, y, Eigen::VectorXd::Zero(model.standardParameterCount()), options);
    ASSERT_TRUE(fit.phi.allFinite()) << trial;
    for (const JointParameterLayout& l : model.layout()) {
      const LinkVector link = fit.phi.segment<kLinkParams>(l.link);
      EXPECT_GT(pseudoInertiaMinEigenvalue(link), 0.0) << trial;
      EXPECT_LT(link[0], options.max_link_mass_kg) << trial;
      EXPECT_GT(options.link_radius_m * options.link_radius_m * link[0] - 0.5 * (link[4] + link[7] + link[9]), 0.0) << trial;
      if (l.friction >= 0) {
        EXPECT_GT(fit.phi[l.friction], 0.0) << trial;
        EXPECT_GT(fit.phi[l.friction + 1], 0.0) << trial;
      }
      if (l.armature >= 0) {
        EXPECT_GT(fit.phi[l.armature], 0.0) << trial;
      }
    }
    EXPECT_LE((base.combination * fit.phi - fit.beta).cwiseAbs().maxCoeff(), 1e-12 * fit.beta.cwiseAbs().maxCoeff()) << trial;
  }
}

TEST(ConsistentFit, RejectsBadInput) {
  const ChainModel model = testing::apalChain(kFitLt_m);
  const BaseParameters base = baseParameters(model);
  const Record rec = exactRecord(model, setB(), 5, 1);
  EXPECT_THROW(consistentFit(model, base, rec.W.leftCols(20), rec.y, setB()), std::invalid_argument);
  // Too few distinct states to identify 10 base parameters.
  const Record one = exactRecord(model, setB(), 1, 1);
  EXPECT_THROW(consistentFit(model, base, one.W, one.y, setB()), std::invalid_argument);
}

}  // namespace
}  // namespace exoid::ident
