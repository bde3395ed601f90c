// Misuse at the API boundary throws std::invalid_argument with a message naming the
// problem.
#include <catch2/catch.hpp>
#include <limits>

#include "ncp/solver.hpp"
#include "ncp_collection/collection.hpp"

using Catch::Matchers::Contains;
using ncp::Vector;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST_CASE("start point of the wrong size", "[solver][validation]") {
  ncp::collection::TestProblem p = ncp::collection::KojimaShindo();
  Vector x = Vector::Zero(5);  // n = 4
  ncp::Summary summary;
  CHECK_THROWS_AS(ncp::SolveNcp(ncp::Options(), *p.F, &x, &summary),
                  std::invalid_argument);
  CHECK_THROWS_WITH(
      ncp::SolveNcp(ncp::Options(), *p.F, &x, &summary),
      Contains("size", Catch::CaseSensitive::No) && Contains("5") && Contains("4"));
  ncp::collection::MixedTestProblem mixed =
      ncp::collection::SimplexProjection(Vector::Constant(3, 0.5));
  Vector z = Vector::Zero(3);  // n = 4
  CHECK_THROWS_WITH(ncp::Solve(ncp::Options(), *mixed.problem, &z, &summary),
                    Contains("size", Catch::CaseSensitive::No));
}

TEST_CASE("NaN or Inf in the start point", "[solver][validation]") {
  ncp::collection::TestProblem p = ncp::collection::KojimaShindo();
  ncp::Summary summary;
  for (double bad : {kNaN, kInf, -kInf}) {
    Vector x = Vector::Ones(4);
    x(2) = bad;
    INFO("x[2] = " << bad);
    CHECK_THROWS_AS(ncp::SolveNcp(ncp::Options(), *p.F, &x, &summary),
                    std::invalid_argument);
    CHECK_THROWS_WITH(ncp::SolveNcp(ncp::Options(), *p.F, &x, &summary),
                      Contains("finite", Catch::CaseSensitive::No) ||
                          Contains("nan", Catch::CaseSensitive::No));
  }
}

TEST_CASE("bounds: lower > upper, wrong sizes", "[solver][validation]") {
  ncp::collection::TestProblem p =
      ncp::collection::Obstacle1D(5, ncp::collection::ObstacleKind::kTwoSidedBand);
  ncp::Summary summary;
  Vector x = Vector::Zero(5);
  Vector lower = p.lower, upper = p.upper;
  lower(3) = 1.0;  // > upper(3) = 0.1
  CHECK_THROWS_AS(ncp::Solve(ncp::Options(), *p.F, lower, upper, &x, &summary),
                  std::invalid_argument);
  CHECK_THROWS_WITH(ncp::Solve(ncp::Options(), *p.F, lower, upper, &x, &summary),
                    Contains("lower", Catch::CaseSensitive::No) &&
                        Contains("upper", Catch::CaseSensitive::No));
  CHECK_THROWS_WITH(
      ncp::Solve(ncp::Options(), *p.F, Vector::Zero(4), p.upper, &x, &summary),
      Contains("size", Catch::CaseSensitive::No));
}

TEST_CASE("invalid options are rejected before any work", "[solver][validation]") {
  ncp::collection::TestProblem p = ncp::collection::Billups();
  ncp::Summary summary;
  Vector x = Vector::Constant(1, 3.0);
  struct Case {
    const char* field;
    ncp::Options options;
  };
  std::vector<Case> cases;
  {
    ncp::Options o;
    o.tolerance = -1e-8;
    cases.push_back({"tolerance", o});
  }
  {
    ncp::Options o;
    o.armijo_beta = 0.5;
    cases.push_back({"armijo_beta", o});
  }
  {
    ncp::Options o;
    o.armijo_beta = 0.7;
    cases.push_back({"armijo_beta", o});
  }
  {
    ncp::Options o;
    o.max_iterations = -1;
    cases.push_back({"max_iterations", o});
  }
  {
    ncp::Options o;
    o.penalized_fb_lambda = 0.0;
    cases.push_back({"penalized_fb_lambda", o});
  }
  {
    ncp::Options o;
    o.max_seconds = 0.0;
    cases.push_back({"max_seconds", o});
  }
  {
    ncp::Options o;
    o.factorization_flop_rate = -1.0;
    cases.push_back({"factorization_flop_rate", o});
  }
  {
    ncp::Options o;
    o.infinite_bound = 0.0;
    cases.push_back({"infinite_bound", o});
  }
  {
    ncp::Options o;
    o.roundoff_ulps = -1.0;
    cases.push_back({"roundoff_ulps", o});
  }
  {
    ncp::Options o;
    o.roundoff_ulps = std::numeric_limits<double>::quiet_NaN();
    cases.push_back({"roundoff_ulps", o});
  }
  for (const Case& c : cases) {
    INFO(c.field);
    std::string error;
    CHECK_FALSE(c.options.IsValid(&error));
    CHECK_THAT(error, Contains(c.field));
    CHECK_THROWS_AS(ncp::SolveNcp(c.options, *p.F, &x, &summary), std::invalid_argument);
    CHECK_THROWS_WITH(ncp::SolveNcp(c.options, *p.F, &x, &summary), Contains(c.field));
    CHECK_THROWS_WITH(ncp::Solver(c.options), Contains(c.field));
    // set_options rejects it too and keeps the Solver's valid options.
    ncp::Solver kept;
    CHECK_THROWS_WITH(kept.set_options(c.options), Contains(c.field));
    CHECK(kept.options().IsValid(&error));
  }
  std::string error;
  CHECK(ncp::Options().IsValid(&error));
  // Nothing was solved: the summary keeps its "not solved yet" defaults.
  CHECK(summary.termination == ncp::TerminationType::kNotSolved);
  CHECK(summary.iterations == -1);
}

// Before: a negative tolerance was echoed as "-0.000000", stagnation_window = INT_MAX
// allocated 16 GiB, an enum out of range threw std::logic_error from deep inside.
TEST_CASE("options out of range name the value and the accepted range",
          "[solver][validation]") {
  const std::pair<ncp::Options, std::string> cases[] = {
      {[] {
         ncp::Options o;
         o.tolerance = -1e-12;
         return o;
       }(),
       "Options::tolerance must be finite and >= 0, got -1e-12"},
      {[] {
         ncp::Options o;
         o.stagnation_window = std::numeric_limits<int>::max();
         return o;
       }(),
       "Options::stagnation_window must lie in [0, 1000000] iterations, got 2147483647"},
      {[] {
         ncp::Options o;
         o.ncp_function = static_cast<ncp::NcpFunction>(7);
         return o;
       }(),
       "Options::ncp_function must be an NcpFunction (0..2), got 7"},
      {[] {
         ncp::Options o;
         o.linear_solver = static_cast<ncp::LinearSolverType>(-1);
         return o;
       }(),
       "Options::linear_solver must be a LinearSolverType (0..5), got -1"},
  };
  for (const auto& [options, message] : cases) {
    std::string error;
    CHECK_FALSE(options.IsValid(&error));
    CHECK(error == message);
    CHECK_THROWS_WITH(ncp::Solver(options), Contains(message));
  }
}

// F(x) = -2 at the start point x = 0 and NaN everywhere else: every trial point of the
// first line search has a NaN residual. Before, this ended as a plain line-search
// failure.
TEST_CASE("a residual that is NaN at every line-search trial point is reported as such",
          "[solver][validation]") {
  ncp::DenseSquareFunction F(
      1,
      [](const Vector& x, Vector* f) {
        f->resize(1);
        (*f)(0) = x(0) == 0.0 ? -2.0 : kNaN;
        return true;
      },
      [](const Vector&, ncp::DenseMatrix* J) {
        *J = ncp::DenseMatrix::Identity(1, 1);
        return true;
      });
  Vector x = Vector::Zero(1);
  ncp::Summary summary;
  ncp::SolveNcp(ncp::Options(), F, &x, &summary);
  CHECK(summary.termination == ncp::TerminationType::kNonFiniteValues);
  CHECK_THAT(summary.message, Contains("NaN or Inf entries at all") &&
                                  Contains("trial points of the line search"));
  CHECK(x(0) == 0.0);  // the start point, the only one with a finite residual
}
