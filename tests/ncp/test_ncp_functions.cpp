// NCP function values on hand-computed points, directly (ncp/ncp_functions.hpp) and
// through the public solver (||Phi(x0)||_inf of a one-variable problem, read in the
// callback).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "ncp/ncp_functions.hpp"
#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"

using Catch::Matchers::WithinAbs;
using ncp::NcpFunction;

TEST_CASE("Fischer-Burmeister values", "[ncp_functions]") {
  // phi_FB(a, b) = sqrt(a^2 + b^2) - a - b
  CHECK_THAT(ncp::FischerBurmeister(3, 4), WithinAbs(5.0 - 7.0, 1e-15));
  CHECK(ncp::FischerBurmeister(0, 0) == 0.0);                        // the kink
  CHECK(ncp::FischerBurmeister(0, 5) == 0.0);                        // a = 0, b > 0
  CHECK(ncp::FischerBurmeister(2, 0) == 0.0);                        // a > 0, b = 0
  CHECK_THAT(ncp::FischerBurmeister(-1, 0), WithinAbs(2.0, 1e-15));  // |a| - a
  CHECK_THAT(ncp::FischerBurmeister(-3, -4), WithinAbs(5.0 + 7.0, 1e-15));
  CHECK_THAT(ncp::FischerBurmeister(1, 1), WithinAbs(std::sqrt(2.0) - 2.0, 1e-15));
}

// Recorded, not enforced: sqrt(a^2 + b^2) - (a + b) cancels for a >> b > 0. The exact
// value is phi(1e8, 1) = -1 + 5e-9 - O(1e-25); evaluating it as -2ab / (sqrt(a^2 + b^2)
// + a + b) (valid for a + b > 0) has no cancellation. The absolute error of the direct
// formula is eps max(|a|, |b|), which matters near solutions with large components.
TEST_CASE("Fischer-Burmeister without cancellation for a >> b > 0",
          "[ncp_functions][!mayfail]") {
  CHECK_THAT(ncp::FischerBurmeister(1e8, 1.0), WithinAbs(-1.0 + 0.5e-8, 1e-12));
  CHECK(ncp::FischerBurmeister(1.0, 1e-17) < 0.0);  // exact: -1e-17 + 5e-35
}

TEST_CASE("min and penalized FB values", "[ncp_functions]") {
  CHECK(ncp::MinFunction(3, 4) == 3.0);
  CHECK(ncp::MinFunction(-1, 2) == -1.0);
  CHECK(ncp::MinFunction(0, 0) == 0.0);
  CHECK(ncp::MinFunction(0, 7) == 0.0);
  // phi_lambda = lambda phi_FB - (1 - lambda) max(a, 0) max(b, 0)
  CHECK_THAT(ncp::PenalizedFischerBurmeister(3, 4, 0.95),
             WithinAbs(0.95 * -2.0 - 0.05 * 12.0, 1e-14));
  CHECK_THAT(ncp::PenalizedFischerBurmeister(-1, 2, 0.5),
             WithinAbs(0.5 * (std::sqrt(5.0) - 1.0), 1e-14));
  CHECK(ncp::PenalizedFischerBurmeister(0, 0, 0.95) == 0.0);
  CHECK(ncp::PenalizedFischerBurmeister(0, 3, 0.95) == 0.0);
  CHECK_THAT(ncp::PenalizedFischerBurmeister(3, 4, 1.0),
             WithinAbs(ncp::FischerBurmeister(3, 4), 1e-15));
}

namespace {

// ||Phi(x0)||_inf of the one-variable NCP  x >= 0 perp F(x) = b  at x0 = a, as the solver
// reports it for iteration 0; the callback stops the solve right there.
double SolverPhiAtStart(NcpFunction function, double a, double b) {
  ncp::SparseMatrix zero(1, 1);
  ncp::collection::AffineFunction F(zero, ncp::Vector::Constant(1, b));
  ncp::Options options;
  options.ncp_function = function;
  options.penalized_fb_lambda = 0.95;
  options.project_start_point = false;  // a = x0 may lie outside x >= 0 on purpose
  double phi0 = std::numeric_limits<double>::quiet_NaN();
  options.callback = [&](const ncp::IterationRecord& record) {
    if (record.iteration == 0) phi0 = record.phi_inf;
    return false;
  };
  ncp::Vector x = ncp::Vector::Constant(1, a);
  ncp::Summary summary;
  ncp::SolveNcp(options, F, &x, &summary);
  return phi0;
}

}  // namespace

TEST_CASE("the solver's Phi at the start point uses the same NCP functions",
          "[ncp_functions][solver]") {
  CHECK_THAT(SolverPhiAtStart(NcpFunction::kFischerBurmeister, 3, 4),
             WithinAbs(2.0, 1e-15));
  CHECK_THAT(SolverPhiAtStart(NcpFunction::kFischerBurmeister, -1, 0),
             WithinAbs(2.0, 1e-15));
  CHECK(SolverPhiAtStart(NcpFunction::kFischerBurmeister, 0, 0) == 0.0);
  CHECK_THAT(SolverPhiAtStart(NcpFunction::kMin, 3, 4), WithinAbs(3.0, 1e-15));
  CHECK_THAT(SolverPhiAtStart(NcpFunction::kMin, 5, -2), WithinAbs(2.0, 1e-15));
  CHECK_THAT(SolverPhiAtStart(NcpFunction::kPenalizedFischerBurmeister, 3, 4),
             WithinAbs(2.5, 1e-14));
}
