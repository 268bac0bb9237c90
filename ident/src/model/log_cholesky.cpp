#include "exoid/ident/model/log_cholesky.hpp"

#include "exoid/core/format.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <stdexcept>

namespace exoid::ident {

Eigen::Matrix4d pseudoInertia(const LinkVector& phi) {
  Eigen::Matrix3d I;
  I << phi[4], phi[5], phi[6], phi[5], phi[7], phi[8], phi[6], phi[8], phi[9];
  Eigen::Matrix4d J;
  J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
  J.topRightCorner<3, 1>() = phi.segment<3>(1);
  J.bottomLeftCorner<1, 3>() = phi.segment<3>(1).transpose();
  J(3, 3) = phi[0];
  return J;
}

LinkVector linkFromPseudoInertia(const Eigen::Matrix4d& J) {
  const Eigen::Matrix3d S = J.topLeftCorner<3, 3>();
  const Eigen::Matrix3d I = S.trace() * Eigen::Matrix3d::Identity() - S;  // tr(Sigma) = tr(I) / 2
  LinkVector phi;
  phi << J(3, 3), J(0, 3), J(1, 3), J(2, 3), I(0, 0), I(0, 1), I(0, 2), I(1, 1), I(1, 2), I(2, 2);
  return phi;
}

double pseudoInertiaMinEigenvalue(const LinkVector& phi) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(pseudoInertia(phi), Eigen::EigenvaluesOnly).eigenvalues()[0];
}

namespace {

// theta = (alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3) -> U.
Eigen::Matrix4d upperFactor(const LinkVector& th) {
  Eigen::Matrix4d U;
  U << std::exp(th[1]), th[4], th[6], th[7],  //
      0.0, std::exp(th[2]), th[5], th[8],      //
      0.0, 0.0, std::exp(th[3]), th[9],        //
      0.0, 0.0, 0.0, 1.0;
  return std::exp(th[0]) * U;
}

}  // namespace

LinkVector linkFromLogCholesky(const LinkVector& theta) {
  const Eigen::Matrix4d U = upperFactor(theta);
  return linkFromPseudoInertia(U * U.transpose());
}

Eigen::Matrix<double, kLinkParams, kLinkParams> linkFromLogCholeskyJacobian(const LinkVector& theta) {
  const Eigen::Matrix4d U = upperFactor(theta);
  const double e = std::exp(theta[0]);
  // dU / d theta_k: alpha scales all of U; d_i its diagonal entries; the rest one entry each.
  static const int kRow[kLinkParams] = {-1, 0, 1, 2, 0, 1, 0, 0, 1, 2};
  static const int kCol[kLinkParams] = {-1, 0, 1, 2, 1, 2, 2, 3, 3, 3};
  Eigen::Matrix<double, kLinkParams, kLinkParams> D;
  for (int k = 0; k < kLinkParams; ++k) {
    Eigen::Matrix4d dU = Eigen::Matrix4d::Zero();
    if (k == 0) {
      dU = U;
    } else {
      dU(kRow[k], kCol[k]) = k <= 3 ? U(kRow[k], kCol[k]) : e;
    }
    D.col(k) = linkFromPseudoInertia(dU * U.transpose() + U * dU.transpose());  // phi is linear in J
  }
  return D;
}

LinkVector logCholeskyFromLink(const LinkVector& phi) {
  const Eigen::Matrix4d J = pseudoInertia(phi);
  // J = U U' with U upper triangular: the Cholesky factor of J with rows and columns reversed.
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  for (int i = 0; i < 4; ++i) P(i, 3 - i) = 1.0;
  Eigen::LLT<Eigen::Matrix4d> llt(P * J * P);
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("log-Cholesky: the link's pseudo-inertia is not positive definite (smallest eigenvalue " +
                                core::formatNumber(pseudoInertiaMinEigenvalue(phi), 4) + "): not a consistent link");
  }
  const Eigen::Matrix4d L = llt.matrixL();
  const Eigen::Matrix4d U = P * L * P;
  const double e = U(3, 3);
  LinkVector th;
  th << std::log(e), std::log(U(0, 0) / e), std::log(U(1, 1) / e), std::log(U(2, 2) / e), U(0, 1) / e, U(1, 2) / e,
      U(0, 2) / e, U(0, 3) / e, U(1, 3) / e, U(2, 3) / e;
  return th;
}

}  // namespace exoid::ident
