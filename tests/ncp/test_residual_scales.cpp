// MixedProblem::Scales: a stopping test per row in the row's own units. A mass on a
// spring pushed against a wall, written in SI (N, m) and in N-mm: the same iterates, the
// same solution after conversion, and every row within its accuracy, recomputed here.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "ncp/solver.hpp"

using ncp::Vector;

namespace {

// Unknowns (u, lambda): k u - f - lambda = 0 [force], 0 <= lambda [force] perp u - w
// [length] >= 0. lambda > 0 when the spring alone would end behind the wall (f / k < w):
// u = w, lambda = k w - f.
class SpringOnWall : public ncp::MixedProblem {
 public:
  SpringOnWall(double k, double f, double w, bool scaled)
      : k_(k), f_(f), w_(w), scaled_(scaled) {}
  int NumVariables() const override { return 2; }
  int NumEquations() const override { return 1; }
  int PairVariable(int) const override { return 1; }
  bool Evaluate(const Vector& x, Vector* E, Vector* A, Vector* B) override {
    (*E)(0) = k_ * x(0) - f_ - x(1);
    (*A)(0) = x(1);
    (*B)(0) = x(0) - w_;
    return true;
  }
  bool Jacobian(const Vector&, ncp::SparseMatrix* JE, ncp::SparseMatrix* JA,
                ncp::SparseMatrix* JB) override {
    JE->resize(1, 2);
    JA->resize(1, 2);
    JB->resize(1, 2);
    JE->coeffRef(0, 0) = k_;
    JE->coeffRef(0, 1) = -1.0;
    JA->coeffRef(0, 1) = 1.0;
    JB->coeffRef(0, 0) = 1.0;
    return true;
  }
  // Force scale |f|, length scale |w| + |f| / k; floors: the round-off of each row.
  bool Scales(const Vector& x0, ncp::ResidualScales* s) override {
    if (!scaled_) return false;
    const double force = std::abs(f_), length = std::abs(w_) + force / k_;
    const double eps = 2.220446049250313e-16;
    s->equation = Vector::Constant(1, force);
    s->a = Vector::Constant(1, force);
    s->b = Vector::Constant(1, length);
    s->equation_floor = Vector::Constant(1, 8 * eps * (k_ * std::abs(x0(0)) + force));
    s->b_floor = Vector::Constant(1, 8 * eps * std::abs(w_));
    return true;
  }
  double k_, f_, w_;
  bool scaled_;
};

}  // namespace

TEST_CASE("scaled rows: the same iterates in SI and in N-mm", "[solver][scales]") {
  // SI: k = 1e9 N/m, f = -1e3 N, wall at w = -1e-7 m (the spring alone would reach -1e-6
  // m).
  const ncp::NcpFunction function =
      GENERATE(ncp::NcpFunction::kFischerBurmeister, ncp::NcpFunction::kMin,
               ncp::NcpFunction::kPenalizedFischerBurmeister);
  ncp::Options options;
  options.ncp_function = function;
  options.tolerance = 1e-10;
  options.keep_trace = true;
  SpringOnWall si(1e9, -1e3, -1e-7, true), mm(1e6, -1e3, -1e-4, true);
  Vector x_si(2), x_mm(2);
  x_si << 0.0, 0.0;
  x_mm << 0.0, 0.0;
  ncp::Summary s_si, s_mm;
  ncp::Solve(options, si, &x_si, &s_si);
  ncp::Solve(options, mm, &x_mm, &s_mm);
  INFO(s_si.BriefReport() << " / " << s_mm.BriefReport());
  REQUIRE(s_si.termination == ncp::TerminationType::kConverged);
  REQUIRE(s_mm.termination == ncp::TerminationType::kConverged);
  CHECK(s_si.weighted_residual);
  CHECK(s_si.iterations == s_mm.iterations);
  for (size_t k = 0; k < s_si.trace.size(); ++k)
    CHECK(s_si.trace[k].phi_inf ==
          Approx(s_mm.trace[k].phi_inf)
              .epsilon(1e-6)
              .margin(1e-14));  // (relative: 1e-4 of the tolerance is round-off)
  // u = w, lambda = k w - f = -100 + 1000 = 900 N.
  CHECK(x_si(0) == Approx(-1e-7).epsilon(1e-9));
  CHECK(x_mm(0) * 1e-3 == Approx(x_si(0)).epsilon(1e-9));
  CHECK(x_si(1) == Approx(900.0).epsilon(1e-9));
  CHECK(x_mm(1) == Approx(x_si(1)).epsilon(1e-9));
  // Every row within floor + tolerance * scale, recomputed here (floors are ~1e-13 of
  // it).
  CHECK(std::abs(1e9 * x_si(0) + 1e3 - x_si(1)) <= 1.01e-10 * 1e3);
  CHECK(std::min(x_si(1) / 1e3, (x_si(0) + 1e-7) / 1.1e-6) <= 1.01e-10);
}

TEST_CASE("scaled rows: a test in the wrong units is no longer passed early",
          "[solver][scales]") {
  // Unscaled, tolerance 1e-10 is absolute: in metres it accepts a wall gap error of 1e-10
  // m against a wall 1e-10 m away, i.e. no resolution at all. Scaled, the gap is resolved
  // to 1e-10 of its length scale.
  ncp::Options options;
  options.tolerance = 1e-10;
  // k = 1e-3 N/m, f = -1e-12 N, wall at -1e-10 m: u = -1e-10 m, lambda = 9e-13 N.
  SpringOnWall unscaled(1e-3, -1e-12, -1e-10, false), scaled(1e-3, -1e-12, -1e-10, true);
  Vector x1 = Vector::Zero(2), x2 = Vector::Zero(2);
  ncp::Summary s1, s2;
  ncp::Solve(options, unscaled, &x1, &s1);
  ncp::Solve(options, scaled, &x2, &s2);
  CHECK(s1.termination == ncp::TerminationType::kConverged);
  CHECK(s1.iterations == 0);  // the start point x = 0 passes the absolute test
  REQUIRE(s2.termination == ncp::TerminationType::kConverged);
  CHECK(s2.iterations > 0);
  CHECK(x2(0) == Approx(-1e-10).epsilon(1e-9));
  CHECK(x2(1) == Approx(9e-13).epsilon(1e-9));
}

TEST_CASE("scaled rows: invalid scales are refused with the row named",
          "[solver][scales]") {
  class Bad : public SpringOnWall {
   public:
    Bad() : SpringOnWall(1.0, -1.0, 0.0, true) {}
    bool Scales(const Vector&, ncp::ResidualScales* s) override {
      s->equation = Vector::Constant(1, 1.0);
      s->a = Vector::Constant(1, -1.0);
      s->b = Vector::Constant(1, 1.0);
      return true;
    }
  } bad;
  Vector x = Vector::Zero(2);
  ncp::Summary summary;
  try {
    ncp::Solve(ncp::Options(), bad, &x, &summary);
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("a[0]") != std::string::npos);
  }
}
