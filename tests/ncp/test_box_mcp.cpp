// The box-MCP entry: bounds of +-1e20 (the GAMS/PATH "no bound") are infinite, and a
// start point outside [l, u] is projected onto the box. Residuals are recomputed here
// from F, l, u; the runs with +-1e20 are compared with the same runs with +-inf.
#include <Eigen/LU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/collection.hpp"
#include "solve_support.hpp"

using ncp::NcpFunction;
using ncp::TerminationType;
using ncp::Vector;
using namespace ncp::collection;
using namespace ncp::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Natural residual of a converged run (||Phi||_inf <= 1e-10; see test_solve_collection).
constexpr double kResidualTolerance = 1e-8;

Vector ReplaceInfinities(const Vector& bound, double big) {
  Vector out = bound;
  for (Eigen::Index i = 0; i < out.size(); ++i)
    if (std::isinf(out(i))) out(i) = out(i) > 0 ? big : -big;
  return out;
}

ncp::SparseMatrix Tridiagonal(int n) {  // 2 on the diagonal, -1 beside it: SPD
  ncp::SparseMatrix M(n, n);
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i > 0) t.emplace_back(i, i - 1, -1.0);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);
  }
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

}  // namespace

TEST_CASE("bounds of +-1e20 are infinite: same runs as with +-inf", "[box_mcp]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  for (TestProblem& problem : StandardCollection()) {
    if (problem.NumVariables() > 100) continue;  // the small ones suffice here
    const Vector lower_big = ReplaceInfinities(problem.lower, 1e20);
    const Vector upper_big = ReplaceInfinities(problem.upper, 1e20);
    for (const StartPoint& start : problem.starts) {
      const Run with_inf = SolveFrom(problem, start.x, options);
      Vector x = start.x;
      ncp::Summary summary;
      ncp::Solve(options, *problem.F, lower_big, upper_big, &x, &summary);
      INFO(problem.name << " from " << start.label << " with " << ToString(function)
                        << ": " << summary.BriefReport() << " vs "
                        << with_inf.summary.BriefReport());
      CHECK(summary.termination == with_inf.summary.termination);
      CHECK(summary.iterations == with_inf.summary.iterations);
      CHECK(summary.num_variables == with_inf.summary.num_variables);  // no slacks added
      if (summary.termination == TerminationType::kConverged)
        CHECK(NaturalResidual(*problem.F, problem.lower, problem.upper, x) <=
              kResidualTolerance);
    }
  }
}

TEST_CASE("free variables given as [-1e20, 1e20] are equations", "[box_mcp]") {
  // F(x) = T x - q with T tridiagonal SPD, all variables free: the linear system T x = q.
  const int n = 5;
  const Vector q = Vector::LinSpaced(n, 1.0, 5.0);
  AffineFunction F(Tridiagonal(n), -q);
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  Vector x = Vector::Zero(n);
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Constant(n, -1e20), Vector::Constant(n, 1e20), &x,
             &summary);
  INFO(summary.FullReport());
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(summary.num_equations == n);
  CHECK(summary.iterations == 1);  // one Newton step solves a linear system
  const Vector x_direct = Eigen::MatrixXd(F.M()).lu().solve(q);
  CHECK((x - x_direct).lpNorm<Eigen::Infinity>() <= 1e-12);
}

TEST_CASE("infinite_bound = +inf keeps 1e20 a finite bound", "[box_mcp]") {
  const int n = 3;
  AffineFunction F(Tridiagonal(n), -Vector::Ones(n));
  ncp::Options options;
  options.infinite_bound = kInf;
  Vector x = Vector::Zero(n);
  ncp::Summary summary;
  ncp::Solve(options, F, Vector::Zero(n), Vector::Constant(n, 1e20), &x, &summary);
  REQUIRE(summary.termination == TerminationType::kConverged);
  CHECK(summary.num_variables == 3 * n);  // two-sided: two slacks per variable
  ncp::Options bad;
  bad.infinite_bound = 0.0;
  std::string error;
  CHECK_FALSE(bad.IsValid(&error));
  CHECK_THROWS_AS(ncp::Solver(bad), std::invalid_argument);
}

TEST_CASE("a start point outside [l, u] is projected onto the box", "[box_mcp]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  SECTION("a standard NCP from x0 < 0") {
    TestProblem problem = PathManualLcp();
    const Run run = SolveFrom(problem, Vector::Constant(4, -3.0), options);
    INFO(run.summary.FullReport());
    REQUIRE(run.summary.termination == TerminationType::kConverged);
    CHECK(run.summary.projected_start_components == 4);
    CHECK(run.summary.message.find("projected") != std::string::npos);
    CHECK(run.natural_residual <= kResidualTolerance);
    CHECK(DistanceToNearest(run.x, problem.solutions) <= 1e-8);
  }
  SECTION("a two-sided obstacle from u0 = 5 and u0 = -5 outside [-0.1, 0.1]") {
    TestProblem problem = Obstacle1D(50, ObstacleKind::kTwoSidedBand);
    for (double u0 : {5.0, -5.0}) {
      const Run run = SolveFrom(problem, Vector::Constant(50, u0), options);
      INFO("u0 = " << u0 << ": " << run.summary.FullReport());
      if (function == NcpFunction::kMin &&
          run.summary.termination != TerminationType::kConverged) {
        // min is not globally convergent; it must at least say so.
        CHECK(run.summary.termination != TerminationType::kNotSolved);
        continue;
      }
      REQUIRE(run.summary.termination == TerminationType::kConverged);
      CHECK(run.summary.projected_start_components == 50);
      CHECK(run.natural_residual <= kResidualTolerance);
    }
  }
  SECTION("starts below x >= 0 that fail when used as given") {
    // Measured with project_start_point = false and Algorithm 1 (FB, min, penalized FB):
    // josephy from x0 = -10 (1, 1, 1, 1) ends at a stationary point of psi (FB, PFB;
    // ||Phi|| ~ 0.27) or in a line-search failure (min, from -1); mathiesen-mod from -10
    // cannot even be evaluated (its F has a domain). Projected, both converge (with the
    // default options; the nonmonotone search also solves josephy unprojected).
    for (auto make : {&Josephy, &ModifiedMathiesen}) {
      TestProblem problem = make();
      const Vector x0 = Vector::Constant(
          4, problem.name == "josephy" && function == NcpFunction::kMin ? -1.0 : -10.0);
      ncp::Options as_given = ncp::Options::Algorithm1();
      as_given.ncp_function = function;
      as_given.project_start_point = false;
      const Run unprojected = SolveFrom(problem, x0, as_given);
      const Run projected = SolveFrom(problem, x0, options);
      INFO(problem.name << ": as given " << unprojected.summary.BriefReport()
                        << "; projected " << projected.summary.BriefReport());
      CHECK(unprojected.summary.termination != TerminationType::kConverged);
      REQUIRE(projected.summary.termination == TerminationType::kConverged);
      CHECK(projected.summary.projected_start_components == 4);
      CHECK(projected.natural_residual <= kResidualTolerance);
    }
  }
  SECTION("a start inside the box is not touched") {
    TestProblem problem = PathManualLcp();
    const Run run = SolveFrom(problem, Vector::Ones(4), options);
    INFO(run.summary.message);
    CHECK(run.summary.projected_start_components == 0);
    CHECK(run.summary.message.find("start point") == std::string::npos);
  }
}

// The one-shot ncp::Solve borrows a Solver kept per thread for n <= 100: every result
// must be the one a fresh Solver gives, whatever was solved before on the same thread.
TEST_CASE("one-shot solves of small problems equal fresh-Solver solves, in any order",
          "[box_mcp][one_shot]") {
  std::vector<TestProblem> problems = StandardCollection();
  for (ncp::LinearSolverType backend :
       {ncp::LinearSolverType::kAuto, ncp::LinearSolverType::kSparseLU,
        ncp::LinearSolverType::kKlu}) {
    for (int pass = 0; pass < 2; ++pass) {  // the second pass meets a used workspace
      for (TestProblem& p : problems) {
        if (p.NumVariables() > 100) continue;
        for (NcpFunction function :
             {NcpFunction::kFischerBurmeister, NcpFunction::kMin}) {
          ncp::Options options = MakeOptions(function, backend);
          const Vector& x0 = p.starts.back().x;
          Vector x_once = x0, x_fresh = x0;
          ncp::Summary once, fresh;
          ncp::Solve(options, *p.F, p.lower, p.upper, &x_once, &once);
          ncp::Solver(options).Solve(*p.F, p.lower, p.upper, &x_fresh, &fresh);
          INFO(p.name << " " << ncp::ToString(function) << " " << ncp::ToString(backend)
                      << " pass " << pass << ": " << once.BriefReport() << " / "
                      << fresh.BriefReport());
          CHECK(once.termination == fresh.termination);
          CHECK(once.iterations == fresh.iterations);
          CHECK(once.residual_evaluations == fresh.residual_evaluations);
          CHECK((x_once - x_fresh).lpNorm<Eigen::Infinity>() == 0.0);
        }
      }
    }
  }
}

TEST_CASE("a one-shot solve called from inside F of another one-shot solve",
          "[box_mcp][one_shot]") {
  // Outer: x >= 0 perp F(x) = x - c with c = y(x) + 1 found by an inner solve of
  // y >= 0 perp y - 2 (so y = 2, c = 3, x = 3).
  int inner_calls = 0;
  ncp::DenseSquareFunction outer(
      1,
      [&](const Vector& x, Vector* F) {
        ncp::DenseSquareFunction inner(
            1,
            [](const Vector& y, Vector* G) {
              (*G)(0) = y(0) - 2.0;
              return true;
            },
            [](const Vector&, ncp::DenseMatrix* J) {
              (*J)(0, 0) = 1.0;
              return true;
            });
        Vector y = Vector::Zero(1);
        ncp::Summary s;
        ncp::SolveNcp(ncp::Options(), inner, &y, &s);
        ++inner_calls;
        if (!s.IsSolutionUsable()) return false;
        (*F)(0) = x(0) - (y(0) + 1.0);
        return true;
      },
      [](const Vector&, ncp::DenseMatrix* J) {
        (*J)(0, 0) = 1.0;
        return true;
      });
  Vector x = Vector::Zero(1);
  ncp::Summary summary;
  ncp::SolveNcp(ncp::Options(), outer, &x, &summary);
  INFO(summary.FullReport());
  REQUIRE(summary.IsSolutionUsable());
  CHECK(std::abs(x(0) - 3.0) <= 1e-9);
  CHECK(inner_calls == summary.residual_evaluations);
}

// Eigen::SparseLU's analyzePattern does not set info(): read after a singular
// factorization it made every later analysis "fail", so a kept Solver never took a Newton
// step again once the pattern changed.
TEST_CASE("a kept SparseLU Solver works after a singular factorization and a new pattern",
          "[box_mcp][one_shot]") {
  ncp::Options options;
  options.linear_solver = ncp::LinearSolverType::kSparseLU;
  ncp::Solver solver(options);
  // Two free variables, F(x) = (x0 + x1 - 1, x0 + x1 - 3): J = [1 1; 1 1] is singular
  // everywhere, every factorization fails (and there is no solution).
  ncp::DenseSquareFunction singular(
      2,
      [](const Vector& x, Vector* F) {
        (*F)(0) = x(0) + x(1) - 1.0;
        (*F)(1) = x(0) + x(1) - 3.0;
        return true;
      },
      [](const Vector&, ncp::DenseMatrix* J) {
        J->setOnes();
        return true;
      });
  const double inf = std::numeric_limits<double>::infinity();
  Vector x = Vector::Zero(2);
  ncp::Summary summary;
  solver.Solve(singular, Vector::Constant(2, -inf), Vector::Constant(2, inf), &x,
               &summary);
  INFO(summary.FullReport());
  CHECK_FALSE(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_failures >= 1);
  TestProblem kojshin = KojimaShindo();
  x = kojshin.starts.front().x;
  solver.Solve(*kojshin.F, kojshin.lower, kojshin.upper, &x, &summary);
  INFO(summary.FullReport());
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_failures == 0);
}

namespace {

// Independent check of a Farkas certificate of a box LCP (types.hpp, kInfeasible): y in
// the dual cone of the bounds' cone, g = M'y with a finite sup over the box, and q'y +
// sup_{x in [l, u]} g'x < 0. Recomputed densely here, with no tolerance.
double FarkasValue(const Eigen::MatrixXd& M, const Vector& q, const Vector& lower,
                   const Vector& upper, const Vector& y) {
  const Vector g = M.transpose() * y;
  double value = q.dot(y);
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    const bool lo = std::isfinite(lower(i)), up = std::isfinite(upper(i));
    if (lo && !up) REQUIRE(y(i) >= 0.0);
    if (!lo && up) REQUIRE(y(i) <= 0.0);
    if (lo && up) REQUIRE(y(i) == 0.0);
    if (g(i) > 0.0) REQUIRE(std::isfinite(upper(i)));
    if (g(i) < 0.0) REQUIRE(std::isfinite(lower(i)));
    if (g(i) != 0.0) value += g(i) * (g(i) > 0.0 ? upper(i) : lower(i));
  }
  return value;
}

struct BoxLcp {
  const char* name;
  Eigen::MatrixXd M;
  Vector q, lower, upper;
};

}  // namespace

TEST_CASE(
    "an LCP without a solution ends infeasible with a checked certificate, x in [l, u]",
    "[box_mcp][infeasible]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  std::vector<BoxLcp> problems;
  // x >= 0 perp -x - 1 >= 0: F < 0 on the whole orthant (an infeasible example).
  problems.push_back({"M = -I, q = -1", -Eigen::MatrixXd::Identity(2, 2),
                      Vector::Constant(2, -1.0), Vector::Zero(2),
                      Vector::Constant(2, kInf)});
  // x <= 0 perp F = 1 - x/2 <= 0 is impossible for x <= 0 (F >= 1); x_1 free with F_1 =
  // x_1.
  Eigen::MatrixXd M2(2, 2);
  M2 << -0.5, 0.0, 0.0, 1.0;
  problems.push_back({"upper bound, F > 0 on the box", M2,
                      (Vector(2) << 1.0, 0.0).finished(), Vector::Constant(2, -kInf),
                      (Vector(2) << 0.0, kInf).finished()});
  // Two rows that need x_0 + x_1 >= 1 and -x_0 - x_1 >= 0 on the orthant.
  Eigen::MatrixXd M3(2, 2);
  M3 << 1.0, 1.0, -1.0, -1.0;
  problems.push_back({"contradictory rows", M3, (Vector(2) << -1.0, 0.0).finished(),
                      Vector::Zero(2), Vector::Constant(2, kInf)});
  for (const BoxLcp& p : problems) {
    INFO(p.name << ", " << ncp::ToString(function));
    AffineFunction F(p.M.sparseView(), p.q);
    ncp::Options options;
    options.ncp_function = function;
    Vector x = Vector::Zero(2);
    ncp::Summary summary;
    ncp::Solver(options).Solve(F, p.lower, p.upper, &x, &summary);
    INFO(summary.message);
    REQUIRE(summary.termination == TerminationType::kInfeasible);
    REQUIRE(summary.infeasibility_certificate.size() == 2);
    CHECK(FarkasValue(p.M, p.q, p.lower, p.upper, summary.infeasibility_certificate) <
          0.0);
    CHECK(summary.message.find("no solution exists") != std::string::npos);
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      CHECK(x(i) >= p.lower(i));
      CHECK(x(i) <= p.upper(i));
    }
  }
}

TEST_CASE("a stuck solve of a solvable or non-affine problem is never called infeasible",
          "[box_mcp][infeasible]") {
  // The same data as the infeasible LCP, but F not declared affine: no claim is made.
  class NotDeclaredAffine : public ncp::SquareFunction {
   public:
    int NumVariables() const override { return 2; }
    bool Evaluate(const Vector& x, Vector* F) override {
      *F = -x - Vector::Ones(2);
      return true;
    }
    bool Jacobian(const Vector&, ncp::SparseMatrix* J) override {
      *J = -Eigen::MatrixXd::Identity(2, 2).sparseView();
      return true;
    }
  } F;
  Vector x = Vector::Zero(2);
  ncp::Summary summary;
  ncp::Solver().Solve(F, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  CHECK(summary.termination != TerminationType::kInfeasible);
  CHECK(summary.termination != TerminationType::kConverged);
  CHECK(summary.infeasibility_certificate.size() == 0);
  CHECK(x.minCoeff() >= 0.0);  // projected onto the box all the same

  // A solvable LCP (M = I, q = -1: x = 1) converges and carries no certificate.
  AffineFunction G(Eigen::MatrixXd::Identity(2, 2).sparseView(), -Vector::Ones(2));
  x.setZero();
  ncp::Solver().Solve(G, Vector::Zero(2), Vector::Constant(2, kInf), &x, &summary);
  CHECK(summary.termination == TerminationType::kConverged);
  CHECK((x - Vector::Ones(2)).lpNorm<Eigen::Infinity>() <= kResidualTolerance);
  CHECK(summary.infeasibility_certificate.size() == 0);
}

TEST_CASE("the returned x of a box MCP lies in [l, u] whatever the status", "[box_mcp]") {
  // Every collection problem from every start with a small iteration budget: most stop
  // early, inside or outside the box; the returned x must be inside.
  ncp::Options options;
  options.max_iterations = 3;
  for (TestProblem& problem : StandardCollection()) {
    if (problem.NumVariables() > 100) continue;
    for (const StartPoint& start : problem.starts) {
      Vector x = start.x;
      ncp::Summary summary;
      ncp::Solver(options).Solve(*problem.F, problem.lower, problem.upper, &x, &summary);
      INFO(problem.name << " from " << start.label << ": " << summary.message);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        REQUIRE(x(i) >= problem.lower(i));
        REQUIRE(x(i) <= problem.upper(i));
      }
      CHECK(summary.projected_final_components >= 0);
    }
  }
}

// ---------------------------------------------------------------------------------------
// On the dense backend the box MCP writes the Jacobian of Phi itself, straight from F'
// (internal::DenseMixedJacobian). Its results must be those of the general path, where a
// MixedProblem hands JE, JA, JB to the solver: here the same mixed form is written out
// by hand (box_mcp.cpp's file comment) and solved as a MixedProblem, and the two runs
// must agree to the bit at every iterate.
namespace {

// l <= x <= u perp F(x) as equations (free: F_i = 0; fixed: x_i - l_i = 0; two-sided:
// F_i - w_k + v_k = 0) and pairs (x_i - l_i, F_i), (u_i - x_i, -F_i), (x_i - l_i, w_k),
// (u_i - x_i, v_k); unknowns [x; w; v]; the rows in box_mcp.cpp's order.
class BoxMcpByHand final : public ncp::MixedProblem {
 public:
  BoxMcpByHand(ncp::SquareFunction& F, const Vector& lower, const Vector& upper)
      : F_(F), l_(lower), u_(upper), n_(F.NumVariables()) {
    for (int i = 0; i < n_; ++i) {
      const bool lo = std::isfinite(l_(i)), up = std::isfinite(u_(i));
      if (!lo && !up) equations_.push_back({kFree, i, -1});
      if (lo && up && l_(i) == u_(i)) equations_.push_back({kFixed, i, -1});
      if (lo && up && l_(i) < u_(i)) two_sided_.push_back(i);
    }
    const int s = static_cast<int>(two_sided_.size());
    for (int k = 0; k < s; ++k) equations_.push_back({kSplit, two_sided_[k], k});
    for (int i = 0; i < n_; ++i) {
      const bool lo = std::isfinite(l_(i)), up = std::isfinite(u_(i));
      if (lo && !up) pairs_.push_back({kLower, i, -1});
      if (!lo && up) pairs_.push_back({kUpper, i, -1});
    }
    for (int k = 0; k < s; ++k) {
      pairs_.push_back({kLowerSlack, two_sided_[k], k});
      pairs_.push_back({kUpperSlack, two_sided_[k], k});
    }
  }
  int NumVariables() const override { return n_ + 2 * slacks(); }
  int NumEquations() const override { return static_cast<int>(equations_.size()); }
  int PairVariable(int j) const override {
    const Row& r = pairs_[static_cast<size_t>(j)];
    return r.kind == kLowerSlack   ? n_ + r.slack
           : r.kind == kUpperSlack ? n_ + slacks() + r.slack
                                   : r.index;
  }
  /// The start [x0; max(F, 0); max(-F, 0)] of the two-sided rows (x0 in [l, u], as the
  /// box MCP projects it).
  Vector Start(const Vector& x0) {
    Vector y = Vector::Zero(NumVariables()), Fx(n_);
    y.head(n_) = x0;
    F_.Evaluate(x0, &Fx);
    for (int k = 0; k < slacks(); ++k) {
      y(n_ + k) = std::max(Fx(two_sided_[k]), 0.0);
      y(n_ + slacks() + k) = std::max(-Fx(two_sided_[k]), 0.0);
    }
    return y;
  }
  bool Evaluate(const Vector& y, Vector* E, Vector* A, Vector* B) override {
    Vector Fx(n_);
    if (!F_.Evaluate(y.head(n_), &Fx)) return false;
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const auto row = static_cast<Eigen::Index>(e);
      (*E)(row) = r.kind == kFree ? Fx(r.index)
                  : r.kind == kFixed
                      ? y(r.index) - l_(r.index)
                      : Fx(r.index) - y(n_ + r.slack) + y(n_ + slacks() + r.slack);
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const auto row = static_cast<Eigen::Index>(j);
      const bool lower_side = r.kind == kLower || r.kind == kLowerSlack;
      (*A)(row) = lower_side ? y(r.index) - l_(r.index) : u_(r.index) - y(r.index);
      (*B)(row) = r.kind == kLower        ? Fx(r.index)
                  : r.kind == kUpper      ? -Fx(r.index)
                  : r.kind == kLowerSlack ? y(n_ + r.slack)
                                          : y(n_ + slacks() + r.slack);
    }
    return true;
  }
  bool Jacobian(const Vector& y, ncp::SparseMatrix* JE, ncp::SparseMatrix* JA,
                ncp::SparseMatrix* JB) override {
    ncp::SparseMatrix JF;
    if (!F_.Jacobian(y.head(n_), &JF)) return false;
    const ncp::DenseMatrix dense_F(JF);  // every entry of F' is stored (a dense F')
    std::vector<Eigen::Triplet<double, int>> te, ta, tb;
    auto f_row = [&](std::vector<Eigen::Triplet<double, int>>& t, int row, int i,
                     double sign) {
      for (int c = 0; c < n_; ++c) t.emplace_back(row, c, sign * dense_F(i, c));
    };
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const int row = static_cast<int>(e);
      if (r.kind == kFixed) {
        te.emplace_back(row, r.index, 1.0);
        continue;
      }
      f_row(te, row, r.index, 1.0);
      if (r.kind == kSplit) {
        te.emplace_back(row, n_ + r.slack, -1.0);
        te.emplace_back(row, n_ + slacks() + r.slack, 1.0);
      }
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const int row = static_cast<int>(j);
      const bool lower_side = r.kind == kLower || r.kind == kLowerSlack;
      ta.emplace_back(row, r.index, lower_side ? 1.0 : -1.0);
      if (r.kind == kLower || r.kind == kUpper)
        f_row(tb, row, r.index, lower_side ? 1.0 : -1.0);
      else
        tb.emplace_back(
            row, r.kind == kLowerSlack ? n_ + r.slack : n_ + slacks() + r.slack, 1.0);
    }
    JE->setFromTriplets(te.begin(), te.end());
    JA->setFromTriplets(ta.begin(), ta.end());
    JB->setFromTriplets(tb.begin(), tb.end());
    return true;
  }

 private:
  enum Kind { kFree, kFixed, kSplit, kLower, kUpper, kLowerSlack, kUpperSlack };
  struct Row {
    Kind kind;
    int index, slack;
  };
  int slacks() const { return static_cast<int>(two_sided_.size()); }
  ncp::SquareFunction& F_;
  Vector l_, u_;
  int n_;
  std::vector<int> two_sided_;
  std::vector<Row> equations_, pairs_;
};

}  // namespace

TEST_CASE("the box MCP's dense Jacobian of Phi: the general mixed form's, to the bit",
          "[box_mcp][dense]") {
  const NcpFunction function =
      GENERATE(NcpFunction::kFischerBurmeister, NcpFunction::kMin,
               NcpFunction::kPenalizedFischerBurmeister);
  TestProblem p = EveryBoundCubic();
  BoxMcpByHand by_hand(*p.F, p.lower, p.upper);
  REQUIRE(by_hand.NumVariables() == 12);  // one two-sided variable: two slacks
  ncp::Options options;
  options.ncp_function = function;
  options.keep_trace = true;
  ncp::Solver box_solver(options), mixed_solver(options);
  for (const StartPoint& start : p.starts) {
    INFO(start.label << " " << ncp::ToString(function));
    Vector x = start.x, y = by_hand.Start(ProjectOntoBox(p.lower, p.upper, start.x));
    ncp::Summary box, mixed;
    box_solver.Solve(*p.F, p.lower, p.upper, &x, &box);
    mixed_solver.Solve(by_hand, &y, &mixed);
    INFO(box.BriefReport() << " / " << mixed.BriefReport());
    REQUIRE(box.IsSolutionUsable());
    CHECK(NaturalResidual(*p.F, p.lower, p.upper, x) <= kResidualTolerance);
    CHECK(box.linear_solver_used == ncp::LinearSolverType::kDenseLU);
    CHECK(mixed.linear_solver_used == ncp::LinearSolverType::kDenseLU);
    REQUIRE(box.trace.size() == mixed.trace.size());
    for (size_t k = 0; k < box.trace.size(); ++k) {
      INFO("iterate " << k);
      CHECK(box.trace[k].phi_inf == mixed.trace[k].phi_inf);
      CHECK(box.trace[k].grad_psi_inf == mixed.trace[k].grad_psi_inf);
      CHECK(box.trace[k].step_length == mixed.trace[k].step_length);
      CHECK(box.trace[k].direction_norm == mixed.trace[k].direction_norm);
      CHECK(box.trace[k].degenerate_pairs == mixed.trace[k].degenerate_pairs);
    }
    // (The box MCP returns its last iterate projected onto [l, u].)
    CHECK((x - ProjectOntoBox(p.lower, p.upper, y.head(x.size())))
              .lpNorm<Eigen::Infinity>() == 0.0);
    // The start "degenerate" puts pair 4 (x4 >= 0) in the degenerate set: the z-vector
    // rule (za = JA z, zb = JB z) is taken on both paths.
    if (start.label == "degenerate" && function != NcpFunction::kMin)
      CHECK(box.trace.front().degenerate_pairs >= 1);
  }
}
