// Options::max_seconds: checked at every iterate, in the line search and before every
// numeric factorization, whose time is predicted from the symbolic analysis (flops /
// rate). Times are measured here with their own clock, not taken from the Summary.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <utility>

#include "ncp/solver.hpp"
#include "ncp_collection/random_lcp.hpp"
#include "solve_support.hpp"

using Catch::Matchers::Contains;
using ncp::LinearSolverType;
using ncp::TerminationType;
using ncp::Vector;

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// F(x) = atan(x - 5), x >= 0, whose every evaluation sleeps evaluation_s: a slow user
// function. From x0 = 0 FB needs a few damped steps (test_solver_globalization).
class SlowArctangent : public ncp::SquareFunction {
 public:
  explicit SlowArctangent(double evaluation_s) : evaluation_s_(evaluation_s) {}
  int NumVariables() const override { return 1; }
  bool Evaluate(const Vector& x, Vector* F) override {
    std::this_thread::sleep_for(std::chrono::duration<double>(evaluation_s_));
    (*F)(0) = std::atan(x(0) - 5.0);
    return true;
  }
  bool Jacobian(const Vector& x, ncp::SparseMatrix* J) override {
    J->resize(1, 1);
    J->insert(0, 0) = 1.0 / (1.0 + (x(0) - 5.0) * (x(0) - 5.0));
    return true;
  }

 private:
  double evaluation_s_;
};

}  // namespace

TEST_CASE("a factorization predicted to exceed the time left is not started",
          "[time_limit]") {
  // Random sparse P-LCP: UMFPACK's LU fills in (4 random off-diagonals per row).
  ncp::collection::TestProblem problem = ncp::collection::RandomPLcp(2000);
  const LinearSolverType backend = GENERATE(
      LinearSolverType::kUmfpack, LinearSolverType::kKlu, LinearSolverType::kDenseLU);
  ncp::Options options;
  options.linear_solver = backend;
  options.max_seconds = 60.0;
  // 1 flop/s: any factorization of this matrix is predicted to take far beyond 60 s.
  options.factorization_flop_rate = 1.0;
  Vector x = problem.starts[0].x;
  const Vector x0 = x;
  ncp::Summary summary;
  const auto t0 = Clock::now();
  ncp::Solve(options, *problem.F, problem.lower, problem.upper, &x, &summary);
  const double elapsed = SecondsSince(t0);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kTimeLimit);
  CHECK_THAT(summary.message, Contains("was not started"));
  CHECK(summary.iterations == 0);
  CHECK(x == x0);  // the start point is returned
  CHECK(elapsed < 5.0);
  const double n = problem.NumVariables();
  if (backend == LinearSolverType::kDenseLU)
    CHECK_THAT(summary.predicted_factorization_flops,
               Catch::Matchers::WithinRel(2.0 / 3.0 * n * n * n, 1e-12));
  else  // UMFPACK's and KLU's estimates: at least one operation per row
    CHECK(summary.predicted_factorization_flops >= n);
}

TEST_CASE("the random P-LCP at n = 1e4 stops before an LU predicted to exceed the limit",
          "[time_limit]") {
  // Measured: UMFPACK estimates 1.46e11 flops for this LU (3.1 s at its typical 4.8e10
  // flop/s; it took 3.06 s), KLU 6.69e10 (30 s at 2.2e9 flop/s; it took 40-75 s). Before
  // max_seconds was checked before the factorization, KLU ran 41.6 s against a 5 s limit.
  const auto [backend, limit] = GENERATE(std::make_pair(LinearSolverType::kUmfpack, 2.0),
                                         std::make_pair(LinearSolverType::kKlu, 5.0));
  ncp::collection::TestProblem problem = ncp::collection::RandomPLcp(10000);
  ncp::Options options;
  options.linear_solver = backend;
  options.max_seconds = limit;
  Vector x = problem.starts[0].x;
  ncp::Summary summary;
  const auto t0 = Clock::now();
  ncp::Solve(options, *problem.F, problem.lower, problem.upper, &x, &summary);
  const double elapsed = SecondsSince(t0);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kTimeLimit);
  CHECK_THAT(summary.message, Contains("was not started"));
  CHECK(elapsed < limit);
}

TEST_CASE("the same solve with the default rate and no time limit converges",
          "[time_limit]") {
  ncp::collection::TestProblem problem = ncp::collection::RandomPLcp(2000);
  ncp::Options options;
  options.linear_solver = LinearSolverType::kUmfpack;
  options.max_seconds = 60.0;
  const ncp::test::Run run = ncp::test::SolveFrom(problem, problem.starts[0].x, options);
  INFO(run.summary.FullReport());
  REQUIRE(run.summary.termination == TerminationType::kConverged);
  CHECK(run.natural_residual <= 1e-8);
  CHECK(std::isfinite(run.summary.predicted_factorization_flops));
}

TEST_CASE("max_seconds stops a slow problem between evaluations", "[time_limit]") {
  constexpr double kEvaluation = 0.02;  // s per F evaluation
  constexpr double kLimit = 0.05;       // s
  SlowArctangent F(kEvaluation);
  ncp::Options options;
  options.max_seconds = kLimit;
  Vector x = Vector::Zero(1);
  ncp::Summary summary;
  const auto t0 = Clock::now();
  ncp::SolveNcp(options, F, &x, &summary);
  const double elapsed = SecondsSince(t0);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kTimeLimit);
  CHECK_THAT(summary.message, Contains("max_seconds"));
  // At most one evaluation started before the limit runs past it (plus scheduling).
  CHECK(elapsed < kLimit + 2 * kEvaluation + 0.05);
  // Without the limit the same problem converges: the stop was the clock, not the method.
  options.max_seconds = std::numeric_limits<double>::infinity();
  x.setZero();
  ncp::SolveNcp(options, F, &x, &summary);
  CHECK(summary.termination == TerminationType::kConverged);
  CHECK_THAT(x(0), Catch::Matchers::WithinAbs(5.0, 1e-8));
}
