// Algorithm 1's safeguards are exercised and counted: the gradient fallback when the
// Newton system is singular, Armijo backtracking, and a step shortened because
// Evaluate() returned false. Residuals are recomputed here.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/mcplib_nlp.hpp"
#include "ncp_collection/small_problems.hpp"
#include "solve_support.hpp"

using ncp::LinearSolverType;
using ncp::NcpFunction;
using ncp::SparseMatrix;
using ncp::TerminationType;
using ncp::Vector;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Scalar or small F with a dense, fully stored Jacobian.
class SmallFunction : public ncp::SquareFunction {
 public:
  explicit SmallFunction(int n) : n_(n) {}
  int NumVariables() const override { return n_; }
  bool Jacobian(const Vector& x, SparseMatrix* J) override {
    ncp::DenseMatrix D = ncp::DenseMatrix::Zero(n_, n_);
    if (!DenseJacobian(x, &D)) return false;
    J->resize(n_, n_);
    std::vector<Eigen::Triplet<double, int>> t;
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) t.emplace_back(i, j, D(i, j));  // explicit zeros kept
    J->setFromTriplets(t.begin(), t.end());
    return true;
  }
  virtual bool DenseJacobian(const Vector& x, ncp::DenseMatrix* J) = 0;

 private:
  int n_;
};

// F1 = (x1 - 1)^2 + (x2 - 1)^2, F2 = x2 - 2. At x0 = (1, 1) pair 1 has a = x1 = 1 > 0,
// b = F1 = 0, so d phi_FB/da = a/r - 1 = 0 and row 1 of the Newton matrix is
// d phi/db grad F1 = -(0, 0): the matrix is singular and Algorithm 1 must take the
// gradient step. Unique solution (0, 2) (F1 >= 1 > 0 whenever x2 = 2).
class SingularAtStart : public SmallFunction {
 public:
  SingularAtStart() : SmallFunction(2) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    (*F)(0) = (x(0) - 1) * (x(0) - 1) + (x(1) - 1) * (x(1) - 1);
    (*F)(1) = x(1) - 2;
    return true;
  }
  bool DenseJacobian(const Vector& x, ncp::DenseMatrix* J) override {
    *J << 2 * (x(0) - 1), 2 * (x(1) - 1), 0, 1;
    return true;
  }
};

// F(x) = atan(x - 5), x >= 0: solution x* = 5. Far from x*, Newton on atan overshoots
// (|x0 - x*| > 1.39 diverges without damping), so the line search must backtrack.
class Arctangent : public SmallFunction {
 public:
  Arctangent() : SmallFunction(1) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    (*F)(0) = std::atan(x(0) - 5.0);
    return true;
  }
  bool DenseJacobian(const Vector& x, ncp::DenseMatrix* J) override {
    (*J)(0, 0) = 1.0 / (1.0 + (x(0) - 5.0) * (x(0) - 5.0));
    return true;
  }
};

// F(x) = log(x), defined only for x > 0 (Evaluate returns false otherwise); x* = 1. From
// x0 = 5 the first FB Newton step lands near x = -2.3, outside the domain.
class Logarithm : public SmallFunction {
 public:
  Logarithm() : SmallFunction(1) {}
  int failed_evaluations = 0;
  bool Evaluate(const Vector& x, Vector* F) override {
    if (!(x(0) > 0.0)) {
      ++failed_evaluations;
      return false;
    }
    (*F)(0) = std::log(x(0));
    return true;
  }
  bool DenseJacobian(const Vector& x, ncp::DenseMatrix* J) override {
    if (!(x(0) > 0.0)) return false;
    (*J)(0, 0) = 1.0 / x(0);
    return true;
  }
};

const Vector kZero1 = Vector::Zero(1);
const Vector kInf1 = Vector::Constant(1, kInf);

}  // namespace

TEST_CASE("singular Newton matrix at the start: gradient fallback",
          "[solver][globalization]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  SingularAtStart F;
  Vector x(2);
  x << 1.0, 1.0;
  ncp::Options options = ncp::test::MakeOptions(NcpFunction::kFischerBurmeister, backend);
  options.keep_trace = true;
  {  // By default the consistent singular system is solved by the rank-revealing step.
    ncp::Summary summary;
    ncp::Solve(options, F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
    INFO(ncp::ToString(backend) << ": " << summary.FullReport());
    CHECK(summary.linear_solver_failures >= 1);
    REQUIRE(summary.trace.size() >= 2);
    CHECK(summary.trace[1].minimum_norm_step);
    CHECK(summary.gradient_steps == 0);
    CHECK(summary.termination == TerminationType::kConverged);
    CHECK(ncp::collection::NaturalResidual(F, Vector::Zero(2), Vector::Constant(2, kInf),
                                           x) <= 1e-8);
  }
  // The gradient fallback itself.
  options.minimum_norm_step = false;
  x << 1.0, 1.0;
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  INFO(ncp::ToString(backend) << ": " << summary.FullReport());
  CHECK(summary.linear_solver_failures >= 1);
  CHECK(summary.gradient_steps >= 1);
  REQUIRE(summary.trace.size() >= 2);
  CHECK(summary.trace[1].gradient_step);  // the first step is the gradient step
  CHECK(summary.termination == TerminationType::kConverged);
  const double r =
      ncp::collection::NaturalResidual(F, Vector::Zero(2), Vector::Constant(2, kInf), x);
  CHECK(r <= 1e-8);
  CHECK(x(0) == Approx(0.0).margin(1e-8));
  CHECK(x(1) == Approx(2.0).epsilon(1e-8));

  // With the fallback disabled the same start must end with an honest status.
  options.gradient_fallback = false;
  x << 1.0, 1.0;
  ncp::Summary no_fallback;
  ncp::Solve(options, F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &no_fallback);
  INFO(no_fallback.FullReport());
  CHECK(no_fallback.termination == TerminationType::kLinearSolverFailure);
  CHECK(no_fallback.gradient_steps == 0);
}

TEST_CASE("overshooting Newton steps are shortened by Armijo backtracking",
          "[solver][globalization]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin);
  Arctangent F;
  Vector x = Vector::Constant(1, 20.0);
  ncp::Summary summary;
  ncp::Solve(ncp::test::MakeOptions(function, backend), F, kZero1, kInf1, &x, &summary);
  INFO(ncp::ToString(function) << " / " << ncp::ToString(backend) << ": "
                               << summary.FullReport());
  CHECK(summary.backtracks > 0);
  CHECK(summary.residual_evaluations > summary.iterations + 1);  // trial points counted
  CHECK(summary.termination == TerminationType::kConverged);
  CHECK(ncp::collection::NaturalResidual(F, kZero1, kInf1, x) <= 1e-8);
  CHECK(x(0) == Approx(5.0).epsilon(1e-8));
}

TEST_CASE("Evaluate() returning false shortens the step and the solve still converges",
          "[solver][globalization]") {
  const LinearSolverType backend =
      GENERATE(LinearSolverType::kDenseLU, LinearSolverType::kSparseLU,
               LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin);
  Logarithm F;
  Vector x = Vector::Constant(1, 5.0);
  ncp::Summary summary;
  ncp::Solve(ncp::test::MakeOptions(function, backend), F, kZero1, kInf1, &x, &summary);
  INFO(ncp::ToString(function) << " / " << ncp::ToString(backend) << ": "
                               << summary.FullReport());
  CHECK(F.failed_evaluations >= 1);  // a trial point left the domain x > 0
  CHECK(summary.backtracks >= 1);
  CHECK(summary.termination == TerminationType::kConverged);
  CHECK(ncp::collection::NaturalResidual(F, kZero1, kInf1, x) <= 1e-8);
  CHECK(x(0) == Approx(1.0).epsilon(1e-8));
}

TEST_CASE("Options::Algorithm1 keeps the thesis's published constants",
          "[solver][globalization]") {
  const ncp::Options a = ncp::Options::Algorithm1();
  CHECK(a.descent_rho == 1e-8);  // eq. (22)
  CHECK(a.descent_p == 2.1);
  CHECK(a.armijo_beta == 1e-4);      // eq. (23)
  CHECK(a.nonmonotone_memory == 1);  // monotone
  CHECK_FALSE(a.regularized_direction);
  CHECK(a.merit_restarts == 0);  // -grad psi is the only fallback
  CHECK(a.gradient_fallback);
  std::string error;
  CHECK(a.IsValid(&error));
}

TEST_CASE(
    "josephy from MCPLIB start 3 with FB: Algorithm 1 stalls, the nonmonotone default "
    "converges",
    "[solver][globalization]") {
  ncp::collection::TestProblem problem = ncp::collection::Josephy();
  const Vector x0 = Vector::Constant(4, 100.0);  // MCPLIB start 3
  ncp::Options algorithm1 = ncp::Options::Algorithm1();
  const ncp::test::Run stalled = ncp::test::SolveFrom(problem, x0, algorithm1);
  INFO("Algorithm 1: " << stalled.summary.BriefReport());
  // Measured: stationary-point after 235 iterations, ||Phi||_inf = 0.277.
  CHECK(stalled.summary.termination == TerminationType::kStationaryPoint);
  CHECK(stalled.natural_residual > 1e-2);

  ncp::Options options;
  options.keep_trace = true;
  const ncp::test::Run run = ncp::test::SolveFrom(problem, x0, options);
  INFO("default: " << run.summary.FullReport());
  REQUIRE(run.summary.termination == TerminationType::kConverged);
  CHECK(run.summary.iterations <= 37);  // Siconos' FB-LSA: 37 iterations
  CHECK(run.natural_residual <= 1e-8);
  CHECK(ncp::test::DistanceToNearest(run.x, problem.solutions) <= 1e-8);
  // The run is nonmonotone, and every accepted psi respects the reference of the last
  // 3 iterates: psi_{k+1} < max(psi_k, psi_{k-1}, psi_{k-2}).
  bool increased = false;
  const auto& trace = run.summary.trace;
  for (size_t k = 1; k < trace.size(); ++k) {
    double reference = 0.0;
    for (size_t j = k >= 3 ? k - 3 : 0; j < k; ++j)
      reference = std::max(reference, trace[j].psi);
    CHECK(trace[k].psi < reference);
    increased = increased || trace[k].psi > trace[k - 1].psi;
  }
  CHECK(increased);
}

TEST_CASE(
    "singular Newton matrix: the Levenberg-Marquardt direction comes before -grad psi",
    "[solver][globalization]") {
  const LinearSolverType backend = GENERATE(
      LinearSolverType::kDenseLU, LinearSolverType::kUmfpack, LinearSolverType::kKlu);
  SingularAtStart F;
  Vector x(2);
  x << 1.0, 1.0;
  ncp::Options options = ncp::test::MakeOptions(NcpFunction::kFischerBurmeister, backend);
  options.regularized_direction = true;
  options.minimum_norm_step = false;  // (by default it solves this consistent system)
  options.keep_trace = true;
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  INFO(ncp::ToString(backend) << ": " << summary.FullReport());
  CHECK(summary.linear_solver_failures >= 1);
  CHECK(summary.regularized_steps >= 1);
  REQUIRE(summary.trace.size() >= 2);
  CHECK(summary.trace[1].regularized_step);
  CHECK_FALSE(summary.trace[1].gradient_step);
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(ncp::collection::NaturalResidual(F, Vector::Zero(2), Vector::Constant(2, kInf),
                                         x) <= 1e-8);
  CHECK(x(1) == Approx(2.0).epsilon(1e-8));
}

TEST_CASE(
    "colvdual: FB stalls at a stationary point of psi_FB, the merit restarts solve it",
    "[solver][globalization][restart]") {
  ncp::collection::TestProblem problem = ncp::collection::ColvilleDual();
  for (const auto& start : problem.starts) {
    ncp::Options without;
    without.merit_restarts = 0;
    without.hybrid = false;  // one strategy (the hybrid default's switches solve it too)
    const ncp::test::Run stalled = ncp::test::SolveFrom(problem, start.x, without);
    INFO(start.label << ", no restarts: " << stalled.summary.BriefReport());
    // Measured: stationary-point after ~60 iterations, ||Phi||_inf ~ 0.14.
    CHECK(stalled.summary.termination == TerminationType::kStationaryPoint);
    CHECK(stalled.natural_residual > 1e-2);

    ncp::Options options;  // defaults: FB, merit_restarts = 6
    options.keep_trace = true;
    const ncp::test::Run run = ncp::test::SolveFrom(problem, start.x, options);
    INFO(start.label << ", default: " << run.summary.FullReport());
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    CHECK(run.summary.merit_restarts >= 1);
    CHECK(run.summary.merit_restarts <= options.merit_restarts);
    CHECK(run.summary.message.find("restarts") != std::string::npos);
    CHECK(run.summary.trace.size() == static_cast<size_t>(run.summary.iterations) + 1);
    CHECK(run.natural_residual <= 1e-8);
    CHECK(ncp::test::DistanceToNearest(run.x, problem.solutions) <= 1e-6);
  }
}

TEST_CASE("merit restarts: the min function and Algorithm 1 never restart",
          "[solver][globalization][restart]") {
  ncp::collection::TestProblem problem = ncp::collection::ColvilleDual();
  ncp::Options min_options;
  min_options.ncp_function = NcpFunction::kMin;
  min_options.hybrid =
      false;  // (the hybrid default switches to penalized FB, which restarts)
  const ncp::test::Run with_min =
      ncp::test::SolveFrom(problem, problem.starts[0].x, min_options);
  CHECK(with_min.summary.merit_restarts == 0);
  const ncp::test::Run thesis =
      ncp::test::SolveFrom(problem, problem.starts[0].x, ncp::Options::Algorithm1());
  CHECK(thesis.summary.merit_restarts == 0);
  CHECK_FALSE(thesis.summary.IsSolutionUsable());
  ncp::Options bad;
  bad.merit_restarts = -1;
  std::string error;
  CHECK_FALSE(bad.IsValid(&error));
  CHECK(error.find("merit_restarts") != std::string::npos);
}

// A step is "too small" only when it moves no component: x1 ~ 1e8 and x2 ~ 1e-9 in their
// own units, the last correction of x2 (1e-9) is below eps ||x||_inf (2.2e-8) but changes
// x2 completely. The line search used to stop on t ||d||_inf <= eps ||x||_inf and ended
// in a line-search failure at ||Phi|| = 2e-9 (the 2D obstacle at 10^6 unknowns failed
// so).
TEST_CASE("the line search judges a step component by component, not by ||x||_inf",
          "[solver][globalization]") {
  SparseMatrix M(2, 2);
  M.setIdentity();
  ncp::collection::AffineFunction F(M, Vector((Vector(2) << -1e8, -1e-9).finished()));
  const Vector lower = Vector::Zero(2), upper = Vector::Constant(2, kInf);
  Vector x =
      (Vector(2) << 1e8, 0.0).finished();  // x1 solved, x2 = 0 < 1e-9: Phi_2 = 2e-9
  ncp::Options options;
  options.tolerance = 1e-14;
  ncp::Summary summary;
  ncp::Solve(options, F, lower, upper, &x, &summary);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(std::abs(x(0) - 1e8) == 0.0);
  CHECK(std::abs(x(1) - 1e-9) <= 1e-14);
}
