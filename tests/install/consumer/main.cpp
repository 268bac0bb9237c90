// Uses exoid::ident from the installed package: the regressor and LS recover X from exact torques.
#include "exoid/ident/estimators/least_squares.hpp"
#include "exoid/ident/estimators/linear_cost.hpp"
#include "exoid/ident/leg/params.hpp"
#include "exoid/ident/leg/regressor.hpp"

#include <cmath>
#include <cstdio>

int main() {
  using namespace exoid::ident;
  const LegConstants c{0.45, 9.81};
  ParamVector x;
  x << 5.83, 0.1, 2.1, 1.5, 0.6, 1.3, 0.05, 0.6, 1.2, 0.4;
  const int n = 400;
  Eigen::MatrixXd H(2 * n, kNumParams);
  Eigen::VectorXd y(2 * n);
  for (int i = 0; i < n; ++i) {
    const double t = 0.01 * i;
    const Eigen::Vector2d q(-0.5 + 0.6 * std::sin(1.3 * t), 1.0 + 0.5 * std::sin(2.1 * t + 0.4));
    const Eigen::Vector2d qd(0.78 * std::cos(1.3 * t), 1.05 * std::cos(2.1 * t + 0.4));
    const Eigen::Vector2d qdd(-1.014 * std::sin(1.3 * t), -2.205 * std::sin(2.1 * t + 0.4));
    RegressorRow hip, knee;
    regressorRows(c, q, qd, qdd, hip, knee);
    H.row(2 * i) = hip;
    H.row(2 * i + 1) = knee;
    y[2 * i] = hip.dot(x);
    y[2 * i + 1] = knee.dot(x);
  }
  const LsResult ls = solveLeastSquares(H, y);
  const double err = (ls.x - x).cwiseAbs().maxCoeff();
  // The swarm cost on the kernel the library dispatched to, against this project's own arithmetic.
  const LinearResidualCost cost(H, y);
  Eigen::MatrixXd swarm = Eigen::MatrixXd::Random(kNumParams, 11);
  Eigen::VectorXd costs(11);
  cost.evaluate(swarm, costs);
  const double direct = (y - H * swarm.col(10)).cwiseAbs().sum();
  const double cost_err = std::abs(costs[10] - direct) / direct;
  std::printf("%s recovered to %.3g; swarm cost (%s kernel) agrees to %.3g\n", std::string(paramName(0)).c_str(), err,
              toString(cost.kernel()), cost_err);
  return err < 1e-8 && cost_err < 1e-12 ? 0 : 1;
}
