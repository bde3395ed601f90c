// ncp::fc::Solve on an OperatorProblem (W given by its action only): every problem of the
// data directory posed matrix-free from its W, each claimed solution checked with
// CoulombViolation on the matrix (no ncp::fc code), and compared with the matrix solver;
// and each problem split into two parts solved by two threads with OperatorProblem's
// reduction (the distributed form): both parts take the same decisions and together
// solve the whole problem.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

#include "fc_support.hpp"
#include "ncp/fc/error.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/operator_problem.hpp"

using namespace ncp::fc;
using Catch::Matchers::WithinAbs;

namespace {

/// The problem with W applied through a closure; diag(W) exact or scaled by `skew`
/// per component (an approximate diagonal, as a finite-element caller would give).
OperatorProblem AsOperator(const FrictionProblem& p, double skew = 1.0) {
  OperatorProblem op;
  op.dimension = p.dimension;
  op.num_contacts = p.num_contacts;
  op.apply_W = [W = p.W](const Eigen::VectorXd& r, Eigen::VectorXd* Wr) { *Wr = W * r; };
  op.diagonal = Eigen::VectorXd(p.W.diagonal()).cwiseMax(0.0);
  for (Eigen::Index i = 0; i < op.diagonal.size(); ++i)
    op.diagonal(i) *= i % 2 ? skew : 1.0 / skew;
  op.q = p.q;
  op.mu = p.mu;
  op.name = p.name;
  return op;
}

/// Two parts of a problem, contacts [0, split) and [split, n_c), each solved by its own
/// thread: the reduction of a part waits for the other at a barrier and adds (or takes
/// the larger of) slot 0 and slot 1 in that order, so both get the same bits; W r is
/// applied to r joined from both parts, each part computing its rows.
class TwoParts {
 public:
  TwoParts(const FrictionProblem& p, int split) : p_(p), joined_(p.size()) {
    const int d = p.dimension;
    offset_ = {0, d * split};
    count_ = {d * split, d * (p.num_contacts - split)};
    contacts_ = {split, p.num_contacts - split};
    for (int k = 0; k < 2; ++k)
      rows_[k] = Eigen::SparseMatrix<double, Eigen::RowMajor>(
          p.W.middleRows(offset_[k], count_[k]));
  }

  OperatorProblem Part(int k) {
    OperatorProblem op;
    op.dimension = p_.dimension;
    op.num_contacts = contacts_[k];
    op.q = p_.q.segment(offset_[k], count_[k]);
    op.mu = p_.mu.segment(k == 0 ? 0 : contacts_[0], contacts_[k]);
    op.diagonal =
        Eigen::VectorXd(p_.W.diagonal()).segment(offset_[k], count_[k]).cwiseMax(0.0);
    op.name = p_.name + " part " + std::to_string(k);
    op.apply_W = [this, k](const Eigen::VectorXd& r, Eigen::VectorXd* Wr) {
      joined_.segment(offset_[k], count_[k]) = r;
      Barrier();
      *Wr = rows_[k] * joined_;
      Barrier();
    };
    op.reduction.sum = [this, k](double* v, int n) {
      Combine(k, v, n, [](double a, double b) { return a + b; });
    };
    op.reduction.max = [this, k](double* v, int n) {
      Combine(k, v, n, [](double a, double b) { return std::max(a, b); });
    };
    return op;
  }

  /// The parts' r joined into one vector of the whole problem.
  Eigen::VectorXd Join(const std::array<Eigen::VectorXd, 2>& r) const {
    Eigen::VectorXd out(p_.size());
    for (int k = 0; k < 2; ++k) out.segment(offset_[k], count_[k]) = r[k];
    return out;
  }

 private:
  template <typename Op>
  void Combine(int k, double* v, int n, Op op) {
    slot_[k].assign(v, v + n);
    Barrier();
    for (int i = 0; i < n; ++i) v[i] = op(slot_[0][i], slot_[1][i]);
    Barrier();
  }

  void Barrier() {
    std::unique_lock<std::mutex> lock(mutex_);
    const long generation = generation_;
    if (++arrived_ == 2) {
      arrived_ = 0;
      ++generation_;
      wake_.notify_all();
    } else {
      wake_.wait(lock, [&] { return generation_ != generation; });
    }
  }

  const FrictionProblem& p_;
  std::array<int, 2> offset_{}, count_{}, contacts_{};
  std::array<Eigen::SparseMatrix<double, Eigen::RowMajor>, 2> rows_;
  Eigen::VectorXd joined_;
  std::array<std::vector<double>, 2> slot_;
  std::mutex mutex_;
  std::condition_variable wake_;
  int arrived_ = 0;
  long generation_ = 0;
};

}  // namespace

TEST_CASE("matrix-free: the published solution of FrictionContact3D_1c",
          "[fc][operator]") {
  Options options;
  options.tolerance = 1e-12;
  Eigen::VectorXd r;
  Summary summary;
  Solve(options, AsOperator(test::OneContactProblem()), &r, &summary);
  INFO(summary.message);
  REQUIRE(summary.termination == Termination::kConverged);
  const Eigen::Vector3d expected = test::OneContactSolution();
  for (int i = 0; i < 3; ++i) CHECK_THAT(r[i], WithinAbs(expected[i], 1e-10));
  CHECK(summary.operator_applications > 0);
  CHECK(summary.krylov_iterations > 0);
}

TEST_CASE("matrix-free: every data problem, exact and skewed diagonal",
          "[fc][operator][data]") {
  const double skew = GENERATE(1.0, 3.0);
  int solved = 0;
  const int files = test::ForEachDataProblem([&](const FrictionProblem& p) {
    Options options;
    options.max_iterations = 300;
    Eigen::VectorXd r;
    Summary summary;
    Solve(options, AsOperator(p, skew), &r, &summary);
    INFO(p.name << " skew " << skew << ": " << summary.message);
    // the Summary's error is the natural-map error at the returned r, recomputed here
    CHECK_THAT(summary.final_error,
               WithinAbs(NaturalMapError(p, r), 1e-12 * (1.0 + summary.final_error)));
    if (summary.IsSolutionUsable()) {
      ++solved;
      CHECK(summary.final_error <= options.tolerance);
      CHECK(test::CoulombViolation(p, r) <= 1e-6);
    } else {
      CHECK(summary.final_error > options.tolerance);
    }
  });
  REQUIRE(files >= 15);
  // exact diagonal: all, like the matrix hybrid; a diagonal off by 3 (rho and the
  // preconditioner) loses the two BoxesStack problems (measured), where Siconos' own
  // Alart-Curnier Newton fails too (data/fc3d/README.md)
  if (skew == 1.0)
    CHECK(solved == files);
  else
    CHECK(solved >= files - 2);
}

TEST_CASE("matrix-free: bad problems are refused with the reason", "[fc][operator]") {
  OperatorProblem op = AsOperator(test::OneContactProblem());
  Options options;
  Eigen::VectorXd r;
  Summary summary;
  op.mu(0) = -1.0;
  CHECK_THROWS_WITH(Solve(options, op, &r, &summary), Catch::Contains("mu must be >= 0"));
  op = AsOperator(test::OneContactProblem());
  op.apply_W = nullptr;
  CHECK_THROWS_WITH(Solve(options, op, &r, &summary),
                    Catch::Contains("apply_W is not set"));
  op = AsOperator(test::OneContactProblem());
  op.diagonal.resize(2);
  CHECK_THROWS_WITH(Solve(options, op, &r, &summary),
                    Catch::Contains("diagonal must have 3 entries"));
  op = AsOperator(test::OneContactProblem());
  Options bad;
  bad.krylov_max_iterations = 0;
  CHECK_THROWS_WITH(Solve(bad, op, &r, &summary),
                    Catch::Contains("krylov_max_iterations must be >= 1"));
  bad = Options();
  bad.acceptable_tolerance = -1.0;
  CHECK_THROWS_WITH(Solve(bad, op, &r, &summary),
                    Catch::Contains("acceptable_tolerance must be >= 0"));
}

TEST_CASE(
    "acceptable_tolerance: a solve asked for more than round-off allows ends at its "
    "floor",
    "[fc][operator][solver]") {
  // Asked 1e-30 (below the round-off of W r + q), accepted at 1e-10: both solvers stop at
  // the round-off floor within a few Newton steps, at an error <= the acceptable
  // tolerance, instead of running every attempt of the hybrid out - with their own
  // status (above the tolerance: not kConverged), usable.
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  Options options;
  options.tolerance = 1e-30;
  options.acceptable_tolerance = 1e-10;
  Eigen::VectorXd r;
  Summary summary;
  Solve(options, p, &r, &summary);
  INFO(summary.message);
  CHECK(summary.termination == Termination::kAtRoundoffFloor);
  CHECK(std::string(ToString(summary.termination)) == "at_roundoff_floor");
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.final_error <= 1e-10);
  CHECK(summary.final_error == NaturalMapError(p, r));
  CHECK_THAT(summary.message, Catch::Contains("round-off floor"));
  r.resize(0);
  Solve(options, AsOperator(p), &r, &summary);
  INFO(summary.message);
  CHECK(summary.termination == Termination::kAtRoundoffFloor);
  CHECK(summary.IsSolutionUsable());
  CHECK(NaturalMapError(p, r) <= 1e-10);
  // without it the same request is reported as not reached
  options.acceptable_tolerance = 0.0;
  options.max_iterations = 60;
  r.resize(0);
  Solve(options, p, &r, &summary);
  CHECK(summary.termination != Termination::kConverged);
  CHECK_FALSE(summary.IsSolutionUsable());
}

TEST_CASE("matrix-free over two parts: the same decisions on both, the whole solved",
          "[fc][operator][data]") {
  // GMRES's dot products in sequence (modified Gram-Schmidt, one reduction each) or at
  // once (classical twice, one reduction per pass).
  const bool classical = GENERATE(false, true);
  int solved = 0, same_as_serial = 0;
  const int files = test::ForEachDataProblem([&](const FrictionProblem& p) {
    Options options;
    options.max_iterations = 300;
    options.krylov_classical_gram_schmidt = classical;
    // (One contact: part 0 empty - a part without contacts takes part all the same.)
    TwoParts parts(p, p.num_contacts / 2);
    std::array<OperatorProblem, 2> op = {parts.Part(0), parts.Part(1)};
    std::array<Eigen::VectorXd, 2> r;
    std::array<Summary, 2> summary;
    std::thread other([&] { Solve(options, op[1], &r[1], &summary[1]); });
    Solve(options, op[0], &r[0], &summary[0]);
    other.join();
    INFO(p.name << (classical ? ", classical" : ", modified")
                << " Gram-Schmidt: " << summary[0].message);
    CHECK(summary[0].termination == summary[1].termination);
    CHECK(summary[0].iterations == summary[1].iterations);
    CHECK(summary[0].krylov_iterations == summary[1].krylov_iterations);
    CHECK(summary[0].attempts == summary[1].attempts);
    CHECK(summary[0].final_error == summary[1].final_error);
    CHECK(summary[0].num_contacts == p.num_contacts);
    const Eigen::VectorXd joined = parts.Join(r);
    CHECK_THAT(summary[0].final_error, WithinAbs(NaturalMapError(p, joined),
                                                 1e-12 * (1.0 + summary[0].final_error)));
    if (summary[0].IsSolutionUsable()) {
      ++solved;
      CHECK(summary[0].final_error <= options.tolerance);
      CHECK(test::CoulombViolation(p, joined) <= 1e-6);
    }
    Eigen::VectorXd serial_r;
    Summary serial;
    Solve(options, AsOperator(p), &serial_r, &serial);
    if (serial.iterations == summary[0].iterations &&
        serial.krylov_iterations == summary[0].krylov_iterations)
      ++same_as_serial;
  });
  REQUIRE(files >= 15);
  CHECK(solved == files);
  std::printf(
      "two parts, %s Gram-Schmidt: %d of %d data problems solved, %d with the serial "
      "counts\n",
      classical ? "classical" : "modified", solved, files, same_as_serial);
}

TEST_CASE("matrix-free over two parts: a bad part is refused on both", "[fc][operator]") {
  const FrictionProblem p =
      ReadProblem(std::string(NCP_FC_DATA_DIR) + "/Capsules-i101-404.dat");
  TwoParts parts(p, p.num_contacts / 2);
  std::array<OperatorProblem, 2> op = {parts.Part(0), parts.Part(1)};
  op[1].q(0) = std::numeric_limits<double>::quiet_NaN();
  std::array<Eigen::VectorXd, 2> r;
  std::array<Summary, 2> summary;
  std::array<std::string, 2> what;
  const auto run = [&](int k) {
    try {
      Solve(Options(), op[k], &r[k], &summary[k]);
    } catch (const std::invalid_argument& e) {
      what[k] = e.what();
    }
  };
  std::thread other(run, 1);
  run(0);
  other.join();
  CHECK_THAT(what[0], Catch::Contains("invalid on another part"));
  CHECK_THAT(what[1], Catch::Contains("q has non-finite entries"));
}
