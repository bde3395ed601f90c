// The classical small complementarity problems. Every formula below is written out
// from the cited source; each Jacobian is the analytic derivative of the line above it.
#include "ncp_collection/small_problems.hpp"

#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "dense_function.hpp"
#include "ncp_collection/affine_function.hpp"
#include "problem_building.hpp"

namespace ncp::collection {
namespace {

using internal::MakeStandardNcp;
using internal::Vec;

// The 8 starting points of the MCPLIB runs of kojshin and josephy (the AMPL versions of
// MCPLIB, kojshin.mod / josephy run file, `param xinit`, columns 1..8).
std::vector<StartPoint> McplibKojimaStarts() {
  return {{"1", Vec({0, 0, 0, 0})},         {"2", Vec({1, 1, 1, 1})},
          {"3", Vec({100, 100, 100, 100})}, {"4", Vec({1, 0, 1, 0})},
          {"5", Vec({1, 0, 0, 0})},         {"6", Vec({0, 1, 1, 0})},
          {"7", Vec({0, 1, 0, 1})},         {"8", Vec({1.25, 0, 0, 0.5})}};
}

// ---- Kojima-Shindo -----------------------------------------------------------------
// M. Kojima and S. Shindo, "Extensions of Newton and quasi-Newton methods to systems of
// PC^1 equations", J. Oper. Res. Soc. Japan 29 (1986) 352-374; MCPLIB kojshin
// (Dirkse and Ferris 1995):
//   F1 = 3 x1^2 + 2 x1 x2 + 2 x2^2 +    x3 + 3 x4 - 6
//   F2 = 2 x1^2 +   x1    +   x2^2 + 10 x3 + 2 x4 - 2
//   F3 = 3 x1^2 +   x1 x2 + 2 x2^2 +  2 x3 + 9 x4 - 9
//   F4 =   x1^2           + 3 x2^2 +  2 x3 + 3 x4 - 3
class KojimaShindoFunction : public internal::DenseJacobianFunction {
 public:
  KojimaShindoFunction() : DenseJacobianFunction(4) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    const double x1 = x(0), x2 = x(1), x3 = x(2), x4 = x(3);
    (*F)(0) = 3 * x1 * x1 + 2 * x1 * x2 + 2 * x2 * x2 + x3 + 3 * x4 - 6;
    (*F)(1) = 2 * x1 * x1 + x1 + x2 * x2 + 10 * x3 + 2 * x4 - 2;
    (*F)(2) = 3 * x1 * x1 + x1 * x2 + 2 * x2 * x2 + 2 * x3 + 9 * x4 - 9;
    (*F)(3) = x1 * x1 + 3 * x2 * x2 + 2 * x3 + 3 * x4 - 3;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    const double x1 = x(0), x2 = x(1);
    *J << 6 * x1 + 2 * x2, 2 * x1 + 4 * x2, 1, 3,  //
        4 * x1 + 1, 2 * x2, 10, 2,                 //
        6 * x1 + x2, x1 + 4 * x2, 2, 9,            //
        2 * x1, 6 * x2, 2, 3;
    return true;
  }
};

// ---- Josephy -----------------------------------------------------------------------
// N. H. Josephy, "Newton's method for generalized equations", Tech. Summary Report 1965,
// Math. Research Center, Univ. of Wisconsin (1979), example of Kojima; MCPLIB josephy:
//   F1 = 3 x1^2 + 2 x1 x2 + 2 x2^2 +   x3 + 3 x4 - 6
//   F2 = 2 x1^2 +   x1    +   x2^2 + 3 x3 + 2 x4 - 2
//   F3 = 3 x1^2 +   x1 x2 + 2 x2^2 + 2 x3 + 3 x4 - 1
//   F4 =   x1^2           + 3 x2^2 + 2 x3 + 3 x4 - 3
class JosephyFunction : public internal::DenseJacobianFunction {
 public:
  JosephyFunction() : DenseJacobianFunction(4) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    const double x1 = x(0), x2 = x(1), x3 = x(2), x4 = x(3);
    (*F)(0) = 3 * x1 * x1 + 2 * x1 * x2 + 2 * x2 * x2 + x3 + 3 * x4 - 6;
    (*F)(1) = 2 * x1 * x1 + x1 + x2 * x2 + 3 * x3 + 2 * x4 - 2;
    (*F)(2) = 3 * x1 * x1 + x1 * x2 + 2 * x2 * x2 + 2 * x3 + 3 * x4 - 1;
    (*F)(3) = x1 * x1 + 3 * x2 * x2 + 2 * x3 + 3 * x4 - 3;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    const double x1 = x(0), x2 = x(1);
    *J << 6 * x1 + 2 * x2, 2 * x1 + 4 * x2, 1, 3,  //
        4 * x1 + 1, 2 * x2, 3, 2,                  //
        6 * x1 + x2, x1 + 4 * x2, 2, 3,            //
        2 * x1, 6 * x2, 2, 3;
    return true;
  }
};

// ---- Modified Mathiesen ------------------------------------------------------------
// Kanzow's modification of Mathiesen's Walrasian equilibrium example (L. Mathiesen,
// Math. Programming 37 (1987) 1-18): C. Kanzow, "Some equation-based methods for the
// nonlinear complementarity problem", Optim. Methods Softw. 3 (1994) 327-340, used as
// "modified Mathiesen problem" in De Luca, Facchinei and Kanzow, Math. Programming 75
// (1996) 407-439, sec. 6:
//   F1 = -x2 + x3 + x4
//   F2 = x1 - (4.5 x3 + 2.7 x4) / (x2 + 1)
//   F3 = 5 - x1 - (0.5 x3 + 0.3 x4) / (x3 + 1)
//   F4 = 3 - x1
// The denominators x2 + 1, x3 + 1 (Mathiesen's original has x2, x3) make F defined on
// all of R^4_+; outside x2 > -1, x3 > -1 Evaluate() returns false.
// Solution set: (lambda, 0, 0, 0), lambda in [0, 3]: F = (0, lambda, 5 - lambda,
// 3 - lambda) there, so x1 = lambda >= 0 pairs with F1 = 0 and x2 = x3 = x4 = 0 pair with
// F2, F3, F4 >= 0 exactly when lambda <= 3.
class ModifiedMathiesenFunction : public internal::DenseJacobianFunction {
 public:
  ModifiedMathiesenFunction() : DenseJacobianFunction(4) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    const double x1 = x(0), x2 = x(1), x3 = x(2), x4 = x(3);
    if (!(x2 > -1.0) || !(x3 > -1.0)) return false;
    (*F)(0) = -x2 + x3 + x4;
    (*F)(1) = x1 - (4.5 * x3 + 2.7 * x4) / (x2 + 1);
    (*F)(2) = 5 - x1 - (0.5 * x3 + 0.3 * x4) / (x3 + 1);
    (*F)(3) = 3 - x1;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    const double x2 = x(1), x3 = x(2), x4 = x(3);
    if (!(x2 > -1.0) || !(x3 > -1.0)) return false;
    const double d2 = x2 + 1, d3 = x3 + 1;
    // d/dx3 [(0.5 x3 + 0.3 x4) / (x3 + 1)] = (0.5 - 0.3 x4) / (x3 + 1)^2
    *J << 0, -1, 1, 1,                                               //
        1, (4.5 * x3 + 2.7 * x4) / (d2 * d2), -4.5 / d2, -2.7 / d2,  //
        -1, 0, -(0.5 - 0.3 * x4) / (d3 * d3), -0.3 / d3,             //
        -1, 0, 0, 0;
    return true;
  }
};

// ---- Nash-Cournot, 5 firms -----------------------------------------------------------
// F. H. Murphy, H. D. Sherali and A. L. Soyster, "A mathematical programming approach
// for determining oligopolistic market equilibrium", Math. Programming 24 (1982) 92-106;
// P. T. Harker, "Accelerating the convergence of the diagonalization and projection
// algorithms for finite-dimensional variational inequalities", Math. Programming 41
// (1988) 29-59. Firm i supplies q_i at cost
//   f_i(q_i) = c_i q_i + beta_i / (beta_i + 1) L_i^(1/beta_i) q_i^((beta_i+1)/beta_i),
// the inverse demand is p(Q) = 5000^(1/gamma) Q^(-1/gamma), Q = sum q_i, and the Nash
// equilibrium is the NCP  q >= 0 perp F_i(q) = f_i'(q_i) - p(Q) - q_i p'(Q) >= 0 with
//   f_i'(q_i) = c_i + (L_i q_i)^(1/beta_i),  p'(Q) = -p(Q) / (gamma Q),
//   p''(Q) = (1 + 1/gamma) p(Q) / (gamma Q^2).
// Data: c = (10, 8, 6, 4, 2), L = (5, 5, 5, 5, 5), beta = (1.2, 1.1, 1, 0.9, 0.8),
// gamma = 1.1. Evaluate() returns false unless q >= 0 and Q > 0; Jacobian() returns
// false at q_i = 0 with beta_i > 1 where f_i'' = +inf.
class NashCournotFunction : public internal::DenseJacobianFunction {
 public:
  NashCournotFunction() : DenseJacobianFunction(5) {}
  bool Evaluate(const Vector& q, Vector* F) override {
    double Q = 0;
    if (!Price(q, &Q)) return false;
    const double p = PriceAt(Q), dp = -p / (kGamma * Q);
    for (int i = 0; i < 5; ++i)
      (*F)(i) = kC[i] + std::pow(kL[i] * q(i), 1.0 / kBeta[i]) - p - q(i) * dp;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& q, DenseMatrix* J) override {
    double Q = 0;
    if (!Price(q, &Q)) return false;
    const double p = PriceAt(Q);
    const double dp = -p / (kGamma * Q);
    const double d2p = (1.0 + 1.0 / kGamma) * p / (kGamma * Q * Q);
    for (int i = 0; i < 5; ++i) {
      // dF_i/dq_j = delta_ij (f_i'' - p') - p' - q_i p''
      for (int j = 0; j < 5; ++j) (*J)(i, j) = -dp - q(i) * d2p;
      // f_i'' = (1/beta_i) L_i^(1/beta_i) q_i^(1/beta_i - 1)
      const double f2 = std::pow(kL[i], 1.0 / kBeta[i]) / kBeta[i] *
                        std::pow(q(i), 1.0 / kBeta[i] - 1.0);
      if (!std::isfinite(f2)) return false;
      (*J)(i, i) += f2 - dp;
    }
    return true;
  }

 private:
  static constexpr double kC[5] = {10, 8, 6, 4, 2};
  static constexpr double kL[5] = {5, 5, 5, 5, 5};
  static constexpr double kBeta[5] = {1.2, 1.1, 1.0, 0.9, 0.8};
  static constexpr double kGamma = 1.1;

  static bool Price(const Vector& q, double* Q) {
    for (int i = 0; i < 5; ++i)
      if (!(q(i) >= 0.0)) return false;
    *Q = q.sum();
    return *Q > 0.0;
  }
  static double PriceAt(double Q) {
    return std::pow(5000.0, 1.0 / kGamma) * std::pow(Q, -1.0 / kGamma);
  }
};

// ---- Billups -----------------------------------------------------------------------
// S. C. Billups, "Algorithms for complementarity problems and generalized equations",
// PhD thesis, Univ. of Wisconsin-Madison (1995): the one-dimensional NCP
//   x >= 0 perp F(x) = (x - 1)^2 - 1.01 >= 0.
// Its only solution is x* = 1 + sqrt(1.01) (the other root of F is negative). At x = 0,
// F(0) = -0.01 < 0, and psi = 1/2 phi(x, F(x))^2 has a local minimizer near x = 0 with
// psi > 0 (phi_FB > 0 on all of (-inf, x*)); a monotone merit-function method started at
// x0 = 0 therefore stops at a stationary point of psi that is not a solution.
class BillupsFunction : public internal::DenseJacobianFunction {
 public:
  BillupsFunction() : DenseJacobianFunction(1) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    (*F)(0) = (x(0) - 1) * (x(0) - 1) - 1.01;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    (*J)(0, 0) = 2 * (x(0) - 1);
    return true;
  }
};

SparseMatrix DenseToSparse(const DenseMatrix& A) {
  return A.sparseView();  // drops the structural zeros
}

}  // namespace

TestProblem KojimaShindo() {
  TestProblem p;
  p.name = "kojshin";
  p.source =
      "Kojima and Shindo, J. Oper. Res. Soc. Japan 29 (1986) 352-374; MCPLIB kojshin "
      "(Dirkse and Ferris 1995), 8 MCPLIB starts";
  p.F = std::make_unique<KojimaShindoFunction>();
  MakeStandardNcp(&p);
  p.starts = McplibKojimaStarts();
  p.solutions = {Vec({std::sqrt(6.0) / 2, 0, 0, 0.5}), Vec({1, 0, 3, 0})};
  p.notes =
      "two solutions: (sqrt(6)/2, 0, 0, 1/2) is degenerate in component 3 "
      "(x3 = F3 = 0; F2 = 2 + sqrt(6)/2 > 0), (1, 0, 3, 0) is nondegenerate";
  return p;
}

TestProblem Josephy() {
  TestProblem p;
  p.name = "josephy";
  p.source =
      "Josephy (1979), example of Kojima; MCPLIB josephy (Dirkse and Ferris 1995), the "
      "8 starts of the MCPLIB AMPL run file";
  p.F = std::make_unique<JosephyFunction>();
  MakeStandardNcp(&p);
  p.starts = McplibKojimaStarts();
  p.solutions = {Vec({std::sqrt(6.0) / 2, 0, 0, 0.5})};
  p.notes = "unique solution (sqrt(6)/2, 0, 0, 1/2), nondegenerate (F2, F3 > 0)";
  return p;
}

TestProblem ModifiedMathiesen() {
  TestProblem p;
  p.name = "mathiesen-mod";
  p.source =
      "Kanzow, Optim. Methods Softw. 3 (1994); De Luca, Facchinei and Kanzow, "
      "Math. Programming 75 (1996), sec. 6 (Kanzow's modification of Mathiesen 1987; "
      "not a transcription of MCPLIB mathinum/mathisum)";
  p.F = std::make_unique<ModifiedMathiesenFunction>();
  MakeStandardNcp(&p);
  // No documented list of starts was found for this problem; these reuse the MCPLIB
  // kojshin vectors 1, 2, 3 and add (1, 1, 0, 0). "zero" is itself a solution
  // (lambda = 0, with two degenerate pairs).
  p.starts = {{"zero", Vec({0, 0, 0, 0})},
              {"ones", Vec({1, 1, 1, 1})},
              {"hundred", Vec({100, 100, 100, 100})},
              {"1100", Vec({1, 1, 0, 0})}};
  p.solutions = {Vec({0, 0, 0, 0}), Vec({1.5, 0, 0, 0}), Vec({3, 0, 0, 0})};
  p.isolated_solutions = false;
  p.notes =
      "non-isolated solutions (lambda, 0, 0, 0), lambda in [0, 3]; judge by residual. "
      "F is undefined at x2 = -1 or x3 = -1 (Evaluate returns false for x2 <= -1 or "
      "x3 <= -1)";
  return p;
}

TestProblem NashCournot5() {
  TestProblem p;
  p.name = "nash5";
  p.source =
      "Murphy, Sherali and Soyster, Math. Programming 24 (1982); Harker, Math. "
      "Programming 41 (1988)";
  p.F = std::make_unique<NashCournotFunction>();
  MakeStandardNcp(&p);
  p.starts = {{"tens", Vector::Constant(5, 10.0)}, {"ones", Vector::Constant(5, 1.0)}};
  // Reference values to the digits quoted in the literature; the tests compare with a
  // tolerance of 1e-4 and check the residual of the computed point independently.
  p.solutions = {Vec({15.4293, 12.4986, 9.6635, 7.1651, 5.1326})};
  p.notes =
      "F defined only for q >= 0 with Q > 0 (Evaluate returns false elsewhere); "
      "the solution is interior (all q_i > 0)";
  return p;
}

TestProblem Billups() {
  TestProblem p;
  p.name = "billups";
  p.source = "Billups, PhD thesis, Univ. of Wisconsin-Madison (1995)";
  p.F = std::make_unique<BillupsFunction>();
  MakeStandardNcp(&p);
  p.starts = {{"0", Vec({0.0})}, {"3", Vec({3.0})}};
  p.solutions = {Vec({1.0 + std::sqrt(1.01)})};
  p.expected_failures = {
      {"0",
       {},
       "psi = 1/2 phi(x, F(x))^2 has a local minimizer near x = 0 that is not a "
       "solution; a monotone descent method must stop there without a solution"}};
  p.notes = "unique solution 1 + sqrt(1.01) ~= 2.00499";
  return p;
}

// ---- Hock-Schittkowski 35 as an LCP --------------------------------------------------
// W. Hock and K. Schittkowski, "Test examples for nonlinear programming codes", Lecture
// Notes in Econ. and Math. Systems 187 (1981), problem 35:
//   min 9 - 8 x1 - 6 x2 - 4 x3 + 2 x1^2 + 2 x2^2 + x3^2 + 2 x1 x2 + 2 x1 x3
//   s.t. 3 - x1 - x2 - 2 x3 >= 0,  x >= 0,
// solution x* = (4/3, 7/9, 4/9), f* = 1/9. With the Hessian H, gradient offset c and
// constraint a' x <= 3, a = (1, 1, 2), the KKT conditions are the LCP in z = (x, lambda)
//   z >= 0 perp  M z + q >= 0,   M = [ H  a ; -a'  0 ],  q = (c ; 3),
//   H = [4 2 2; 2 4 0; 2 0 2],  c = (-8, -6, -4).
// At x*, H x* + c = (-2, -2, -4)/9 = -lambda a gives lambda* = 2/9 > 0 (active
// constraint).
TestProblem Hs35Lcp() {
  DenseMatrix M(4, 4);
  M << 4, 2, 2, 1,  //
      2, 4, 0, 1,   //
      2, 0, 2, 2,   //
      -1, -1, -2, 0;
  TestProblem p;
  p.name = "hs35-lcp";
  p.source =
      "Hock and Schittkowski (1981), problem 35; its KKT conditions written as an LCP";
  p.F = std::make_unique<AffineFunction>(DenseToSparse(M), Vec({-8, -6, -4, 3}));
  MakeStandardNcp(&p);
  p.starts = {{"zero", Vector::Zero(4)}, {"hs", Vec({0.5, 0.5, 0.5, 0.0})}};
  p.solutions = {Vec({4.0 / 3, 7.0 / 9, 4.0 / 9, 2.0 / 9})};
  p.notes =
      "M is positive semidefinite (H is positive definite, the a-blocks are skew), so "
      "the LCP is monotone; the solution is unique and nondegenerate; the HS standard "
      "start is x0 = (0.5, 0.5, 0.5), with lambda0 = 0";
  return p;
}

// ---- PATH library LCP ----------------------------------------------------------------
// The linear example of the PATH library interfaces (M. C. Ferris and T. S. Munson,
// "Interfaces to PATH 3.0: design, implementation and usage", Comput. Optim. Appl. 12
// (1999) 207-227; the same data is the example of the PATHSolver.jl wrapper):
//   M = [0 0 -1 -1; 0 0 1 -2; 1 -1 2 -2; 1 2 -2 4],  q = (2, 2, -2, -6).
// It is the KKT system of  min x1^2 - 2 x1 x2 + 2 x2^2 - 2 x1 - 6 x2  s.t.
// x1 + x2 <= 2, -x1 + 2 x2 <= 2, x >= 0, with z = (mu1, mu2, x1, x2). Solution by hand:
// x = (0.8, 1.2) with the first constraint active, mu = (2.8, 0); M z + q = (0, 0.4, 0,
// 0).
TestProblem PathManualLcp() {
  DenseMatrix M(4, 4);
  M << 0, 0, -1, -1,  //
      0, 0, 1, -2,    //
      1, -1, 2, -2,   //
      1, 2, -2, 4;
  TestProblem p;
  p.name = "path-lcp";
  p.source =
      "Ferris and Munson, Comput. Optim. Appl. 12 (1999), the PATH library LCP example";
  p.F = std::make_unique<AffineFunction>(DenseToSparse(M), Vec({2, 2, -2, -6}));
  MakeStandardNcp(&p);
  p.starts = {{"zero", Vector::Zero(4)}, {"ones", Vector::Ones(4)}};
  p.solutions = {Vec({2.8, 0.0, 0.8, 1.2})};
  p.notes = "M is positive semidefinite (QP KKT matrix); unique nondegenerate solution";
  return p;
}

// ---- Murty's exponential LCP ----------------------------------------------------------
// K. G. Murty, "Computational complexity of complementary pivot methods", Math.
// Programming Study 7 (1978) 61-73: the LCP on which Lemke's method takes 2^n - 1 pivots,
//   M_ii = 1,  M_ij = 2 for i > j,  M_ij = 0 for i < j,  q = -1.
// M is lower triangular with a positive diagonal, a P-matrix: the solution is unique. By
// hand: x = e_1 gives w = M e_1 + q = (0, 1, ..., 1) >= 0 with x' w = 0.
TestProblem MurtyExponentialLcp(int n) {
  DenseMatrix M = DenseMatrix::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    M(i, i) = 1.0;
    for (int j = 0; j < i; ++j) M(i, j) = 2.0;
  }
  TestProblem p;
  p.name = "explcp-" + std::to_string(n);
  p.source =
      "Murty (1978), Math. Programming Study 7, the exponential LCP for Lemke's method "
      "(the family of MCPLIB explcp)";
  p.F = std::make_unique<AffineFunction>(DenseToSparse(M), -Vector::Ones(n));
  MakeStandardNcp(&p);
  p.starts = {{"zero", Vector::Zero(n)}, {"ones", Vector::Ones(n)}};
  p.solutions = {Vector::Unit(n, 0)};
  p.notes = "P-matrix (triangular, unit diagonal): unique solution e_1, nondegenerate";
  return p;
}

// ---- a box MCP with every kind of bound ---------------------------------------------
// F(x) = M x + q + x.^3 / 10 (small_problems.hpp). The products are summed in plain loops
// in a fixed order, so that F4 at the start "degenerate" is (M x)_4 + q4 = 0 exactly.
namespace {

class CubicAffineFunction : public internal::DenseJacobianFunction {
 public:
  CubicAffineFunction(DenseMatrix M, Vector q)
      : DenseJacobianFunction(static_cast<int>(q.size())),
        M_(std::move(M)),
        q_(std::move(q)) {}
  bool Evaluate(const Vector& x, Vector* F) override {
    for (Eigen::Index i = 0; i < x.size(); ++i)
      (*F)(i) = Product(i, x) + q_(i) + 0.1 * x(i) * x(i) * x(i);
    return true;
  }
  /// (M x)_i, summed over j in order.
  double Product(Eigen::Index i, const Vector& x) const {
    double sum = 0.0;
    for (Eigen::Index j = 0; j < x.size(); ++j) sum += M_(i, j) * x(j);
    return sum;
  }
  void set_q(Eigen::Index i, double value) { q_(i) = value; }

 protected:
  bool DenseJacobian(const Vector& x, DenseMatrix* J) override {
    *J = M_;
    for (Eigen::Index i = 0; i < x.size(); ++i) (*J)(i, i) += 0.3 * x(i) * x(i);
    return true;
  }

 private:
  DenseMatrix M_;
  Vector q_;
};

}  // namespace

TestProblem EveryBoundCubic() {
  constexpr int n = 10;
  DenseMatrix K(n, n), B(n, n);
  Vector q(n);
  for (int i = 0; i < n; ++i) {
    q(i) = std::sin(7.0 * i);
    for (int j = 0; j < n; ++j) {
      K(i, j) = std::sin(1.0 + i + 2.0 * j);
      B(i, j) = std::cos(3.0 * i - j);
    }
  }
  const DenseMatrix M =
      2.0 * DenseMatrix::Identity(n, n) + (K - K.transpose()) + B * B.transpose() / n;
  Vector degenerate = Vector::Constant(n, 0.5);
  degenerate(4) = 0.0;
  degenerate(9) = 0.3;
  auto F = std::make_unique<CubicAffineFunction>(M, q);
  F->set_q(4, -F->Product(4, degenerate));  // F4(degenerate) = 0 (x4^3 = 0)
  TestProblem p;
  p.name = "every-bound-cubic";
  p.source = "constructed (small_problems.hpp): strongly monotone, every kind of bound";
  p.F = std::move(F);
  p.lower = Vec({-internal::kInf, -internal::kInf, -internal::kInf, -internal::kInf, 0.0,
                 0.0, -0.5, -internal::kInf, -1.0, 0.3});
  p.upper = Vec({internal::kInf, internal::kInf, internal::kInf, internal::kInf,
                 internal::kInf, internal::kInf, internal::kInf, 1.0, 1.0, 0.3});
  Vector half = Vector::Constant(n, 0.5);
  half(9) = 0.3;
  p.starts = {{"zero", Vector::Zero(n)}, {"half", half}, {"degenerate", degenerate}};
  p.notes = "one solution (strongly monotone F); not computed in closed form";
  return p;
}

}  // namespace ncp::collection
