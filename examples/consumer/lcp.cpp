// x >= 0 perp F(x) = M x + q >= 0 with M = [2 1; 1 2], q = (-1, 1): x = (0.5, 0).
#include <cstdio>

#include "ncp/ncp.hpp"

int main() {
  ncp::DenseMatrix M(2, 2);
  M << 2, 1, 1, 2;
  const ncp::Vector q = (ncp::Vector(2) << -1, 1).finished();
  ncp::DenseSquareFunction F(
      2, [&](const ncp::Vector& x, ncp::Vector* Fx) { return *Fx = M * x + q, true; },
      [&](const ncp::Vector&, ncp::DenseMatrix* J) { return *J = M, true; });
  ncp::Vector x = ncp::Vector::Zero(2);
  ncp::Summary summary;
  ncp::SolveNcp(ncp::Options(), F, &x, &summary);  // FB, ||Phi||_inf <= 1e-10
  std::printf("%s\nx = (%g, %g)\n", summary.BriefReport().c_str(), x(0), x(1));
  return summary.IsSolutionUsable() ? 0 : 1;
}
