// ncp-example: solve a user-defined nonlinear complementarity problem
//     x >= 0,  F(x) >= 0,  x' F(x) = 0,   F(x) = M x + q + x.^3 / 10,
// a strongly monotone NCP (M positive definite, the cubic term monotone), so it has
// exactly one solution. F and its Jacobian are given as two lambdas.
#include <cstdio>

#include "ncp/ncp.hpp"

int main() {
  ncp::DenseMatrix M(3, 3);
  M << 4, -1, 0,  //
      -1, 4, -1,  //
      0, -1, 4;
  ncp::Vector q(3);
  q << -3, 1, -2;

  ncp::DenseSquareFunction F(
      3,
      [&](const ncp::Vector& x, ncp::Vector* Fx) {
        *Fx = M * x + q + x.array().cube().matrix() / 10;
        return true;
      },
      [&](const ncp::Vector& x, ncp::DenseMatrix* J) {
        *J = M;
        J->diagonal() += 0.3 * x.array().square().matrix();  // d(x^3/10)/dx = 3x^2/10
        return true;
      });

  ncp::Options options;  // Fischer-Burmeister, tolerance 1e-10, automatic linear solver
  ncp::Vector x = ncp::Vector::Zero(3);  // start point
  ncp::Summary summary;
  ncp::SolveNcp(options, F, &x, &summary);

  std::printf("%s\n", summary.BriefReport().c_str());
  if (!summary.IsSolutionUsable()) {
    std::printf("no solution: %s\n", summary.message.c_str());
    return 1;
  }
  ncp::Vector Fx(3);
  F.Evaluate(x, &Fx);
  std::printf("%3s %14s %14s\n", "i", "x_i", "F_i(x)");
  for (int i = 0; i < 3; ++i) std::printf("%3d %14.10f %14.10f\n", i, x(i), Fx(i));
  std::printf("x'F(x) = %.3e, natural residual = %.3e\n", x.dot(Fx),
              ncp::BoxMcpResidual(F, ncp::Vector::Zero(3),
                                  ncp::Vector::Constant(3, INFINITY), x));
  return 0;
}
