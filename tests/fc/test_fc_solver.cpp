// ncp::fc::Solve on the published problem and on every problem of the data directory with
// each formulation; each claimed solution is checked with CoulombViolation (no
// projection, no ncp::fc code) and a failure must be reported as such.
#include <catch2/catch.hpp>
#include <filesystem>

#include "fc_support.hpp"
#include "ncp/fc/error.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/solver.hpp"

using namespace ncp::fc;
using Catch::Matchers::WithinAbs;

TEST_CASE("the published solution of FrictionContact3D_1c", "[fc][solver]") {
  const Formulation f = GENERATE(Formulation::kAlartCurnier, Formulation::kNaturalMap,
                                 Formulation::kFischerBurmeister, Formulation::kHybrid);
  const ncp::LinearSolverType ls =
      GENERATE(ncp::LinearSolverType::kDenseLU, ncp::LinearSolverType::kUmfpack,
               ncp::LinearSolverType::kKlu);
  Options options;
  options.formulation = f;
  options.linear_solver = ls;
  options.tolerance = 1e-12;
  Eigen::VectorXd r;
  Summary summary;
  Solve(options, test::OneContactProblem(), &r, &summary);
  INFO(summary.BriefReport());
  REQUIRE(summary.termination == Termination::kConverged);
  const Eigen::Vector3d expected = test::OneContactSolution();
  for (int i = 0; i < 3; ++i) CHECK_THAT(r[i], WithinAbs(expected[i], 1e-10));
  CHECK(summary.iterations <= 10);
}

TEST_CASE("every data problem, every formulation", "[fc][solver][data]") {
  const Formulation f = GENERATE(Formulation::kAlartCurnier, Formulation::kNaturalMap,
                                 Formulation::kFischerBurmeister, Formulation::kHybrid);
  int solved = 0;
  const int files = test::ForEachDataProblem([&](const FrictionProblem& p) {
    Options options;
    options.formulation = f;
    options.max_iterations = 300;
    Eigen::VectorXd r;
    Summary summary;
    Solve(options, p, &r, &summary);
    INFO(p.name << " " << ToString(f) << ": " << summary.BriefReport());
    // the Summary's error is the one recomputed at the returned r
    CHECK(summary.final_error == NaturalMapError(p, r));
    if (summary.IsSolutionUsable()) {
      ++solved;
      CHECK(summary.final_error <= 1e-8);
      CHECK(test::CoulombViolation(p, r) <= 1e-6);
    } else {
      CHECK(summary.final_error > options.tolerance);
    }
  });
  REQUIRE(files >= 15);
  // the hybrid default solves all of them (README's table); each single formulation most
  if (f == Formulation::kHybrid)
    CHECK(solved == files);
  else
    CHECK(solved >= files - 3);
}

TEST_CASE("an unfinished solve says so", "[fc][solver]") {
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  Options options;
  options.max_iterations = 2;
  Eigen::VectorXd r;
  Summary summary;
  Solve(options, p, &r, &summary);
  CHECK(summary.termination == Termination::kMaxIterations);
  CHECK_FALSE(summary.IsSolutionUsable());
  CHECK(summary.iterations == 2);
  CHECK(summary.final_error > options.tolerance);
  CHECK(summary.final_error == NaturalMapError(p, r));
}

TEST_CASE("a time limit ends the solve with its own status", "[fc][solver]") {
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  Options options;
  options.max_time_s = 1e-9;  // passed before the first Newton step
  Eigen::VectorXd r;
  Summary summary;
  Solve(options, p, &r, &summary);
  CHECK(summary.termination == Termination::kTimeLimit);
  CHECK(summary.iterations == 0);
  CHECK_FALSE(summary.IsSolutionUsable());
  CHECK(summary.final_error == NaturalMapError(p, r));
  CHECK(summary.final_error > options.tolerance);
}

TEST_CASE("misuse throws std::invalid_argument", "[fc][solver]") {
  const FrictionProblem p = test::OneContactProblem();
  Summary summary;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2);
  CHECK_THROWS_AS(Solve(Options(), p, &r, &summary), std::invalid_argument);
  r = Eigen::VectorXd::Constant(3, std::nan(""));
  CHECK_THROWS_AS(Solve(Options(), p, &r, &summary), std::invalid_argument);
  Options bad;
  bad.tolerance = -1.0;
  r.resize(0);
  CHECK_THROWS_WITH(Solve(bad, p, &r, &summary), Catch::Contains("tolerance"));
  Options bad_shift;
  bad_shift.shift_error_cap = -1e-6;
  CHECK_THROWS_WITH(Solve(bad_shift, p, &r, &summary),
                    Catch::Contains("shift_error_cap"));
  FrictionProblem wrong = p;
  wrong.mu.resize(2);
  CHECK_THROWS_WITH(Solve(Options(), wrong, &r, &summary),
                    Catch::Contains("mu must have 1"));
}

TEST_CASE("projected Gauss-Seidel warm start", "[fc][solver]") {
  Options options;
  options.gauss_seidel_sweeps = 10;
  options.max_iterations = 0;  // sweeps only
  Eigen::VectorXd r;
  Summary summary;
  // one contact: the local Newton solve of the first sweep is the whole problem
  Solve(options, test::OneContactProblem(), &r, &summary);
  CHECK(summary.termination == Termination::kConverged);
  CHECK(summary.gauss_seidel_sweeps == 1);
  CHECK(test::CoulombViolation(test::OneContactProblem(), r) < 1e-12);
  // 225 contacts: ten sweeps reduce the error from 5.6e-3 (r = 0) to about 1e-4
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  r.resize(0);
  Solve(options, p, &r, &summary);
  CHECK(summary.termination == Termination::kMaxIterations);
  CHECK(summary.gauss_seidel_sweeps == 10);
  CHECK(summary.initial_error > 5e-3);
  CHECK(summary.final_error < 1e-3);
  CHECK(summary.final_error == NaturalMapError(p, r));
}

TEST_CASE("Gauss-Seidel trial after the hybrid's first attempt stalls", "[fc][solver]") {
  // Capsules-i101-404: Alart-Curnier stalls from r = 0; the sweeps that follow stop when
  // the error no longer halves within 200 of them (Gauss-Seidel is slow here), and the
  // next Newton attempt (Fischer-Burmeister) finishes from the Newton iterate.
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  Eigen::VectorXd r;
  Summary summary;
  Solve(Options(), p, &r, &summary);
  INFO(summary.BriefReport());
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.fallback_sweeps >= 200);
  CHECK(summary.fallback_sweeps <= Options().gauss_seidel_fallback_sweeps);
  CHECK(test::CoulombViolation(p, r) <= 1e-6);
  // Off: the same Newton attempts, no sweeps.
  Options off;
  off.gauss_seidel_fallback_sweeps = 0;
  r.resize(0);
  Solve(off, p, &r, &summary);
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.fallback_sweeps == 0);
}

TEST_CASE("a Newton shift proportional to the error on a rounded, indefinite W",
          "[fc][solver]") {
  // 2020 contacts, W printed to 6 digits and slightly indefinite: the hybrid finishes
  // through the shift of Options::shift_error_cap (docs/fc.md has the runs without it).
  const FrictionProblem p = ReadProblem(
      std::string(NCP_FC_DATA_DIR) + "/../fc2d/fc2d_granularflowonwall_02020_00213.dat");
  Eigen::VectorXd r;
  Summary summary;
  Solve(Options(), p, &r, &summary);
  INFO(summary.BriefReport());
  REQUIRE(summary.IsSolutionUsable());
  CHECK(NaturalMapError(p, r) <= 1e-8);
  CHECK(test::CoulombViolation(p, r) <= 1e-6);
}
