// Equilibrium problems of MCPLIB / the GAMS model library, transcribed from the published
// formulas and data (sources cited per problem; no code was copied). Each Jacobian is the
// analytic derivative of the residual written above it.
#include "ncp_collection/mcplib_equilibrium.hpp"

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "dense_function.hpp"
#include "problem_building.hpp"

namespace ncp::collection {
namespace {

using internal::Vec;

// ---- nash: Harker's 10-firm Nash-Cournot oligopoly ------------------------------------
// F. H. Murphy, H. D. Sherali and A. L. Soyster, Math. Programming 24 (1982) 92-106;
// P. T. Harker, Math. Programming 41 (1988) 29-59; MCPLIB nash (Dirkse and Ferris, Optim.
// Methods Softw. 5 (1995) 319-345).
// Read: the GAMS model library model NASH (SEQ=269), copy in github Rhh98/GAMS-MIRO,
// oligopoly/nashemp.gms (data table IData, gamma, dbar, start q.l = 1), and the AMPL form
// of MCPLIB nash (netlib ampl/models/compl/nash.mod, "#==>nash.gms") for the residual.
// Firm i produces q_i >= 0 with total cost
//   TC_i(q_i) = c_i q_i + beta_i/(1+beta_i) L_i^(1/beta_i) q_i^((1+beta_i)/beta_i),
// marginal cost TC_i'(q_i) = c_i + (L_i q_i)^(1/beta_i); inverse demand
//   p(Q) = (dbar / Q)^(1/gamma),  Q = sum_j q_j,  dbar = 5000, gamma = 1.2.
// Nash equilibrium: q >= 0 perp F_i(q) = TC_i'(q_i) - p(Q) - q_i p'(Q) >= 0 with
//   p'(Q) = -p(Q) / (gamma Q),  p''(Q) = (1 + 1/gamma) p(Q) / (gamma Q^2),
//   dF_i/dq_j = delta_ij (TC_i'' - p') - p' - q_i p'',
//   TC_i''(q_i) = (1/beta_i) L_i^(1/beta_i) q_i^(1/beta_i - 1).
// Data (i = 1..10): c = (5 3 8 5 1 3 7 4 6 3), L = 10,
//   beta = (1.2 1 .9 .6 1.5 1 .7 1.1 .95 .75).
// Evaluate() returns false unless q >= 0 and Q > 0; Jacobian() returns false at q_i = 0
// with beta_i > 1 (TC_i'' = +inf there).
class Nash10Function : public internal::DenseJacobianFunction {
 public:
  Nash10Function() : DenseJacobianFunction(kN) {}
  bool Evaluate(const Vector& q, Vector* F) override {
    double Q = 0;
    if (!Total(q, &Q)) return false;
    const double p = Price(Q), dp = -p / (kGamma * Q);
    for (int i = 0; i < kN; ++i)
      (*F)(i) = kC[i] + std::pow(kL * q(i), 1.0 / kBeta[i]) - p - q(i) * dp;
    return true;
  }

 protected:
  bool DenseJacobian(const Vector& q, DenseMatrix* J) override {
    double Q = 0;
    if (!Total(q, &Q)) return false;
    const double p = Price(Q);
    const double dp = -p / (kGamma * Q);
    const double d2p = (1.0 + 1.0 / kGamma) * p / (kGamma * Q * Q);
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) (*J)(i, j) = -dp - q(i) * d2p;
      const double tc2 =
          std::pow(kL, 1.0 / kBeta[i]) / kBeta[i] * std::pow(q(i), 1.0 / kBeta[i] - 1.0);
      if (!std::isfinite(tc2)) return false;
      (*J)(i, i) += tc2 - dp;
    }
    return true;
  }

 private:
  static constexpr int kN = 10;
  static constexpr double kC[kN] = {5, 3, 8, 5, 1, 3, 7, 4, 6, 3};
  static constexpr double kBeta[kN] = {1.2, 1, .9, .6, 1.5, 1, .7, 1.1, .95, .75};
  static constexpr double kL = 10;
  static constexpr double kGamma = 1.2;
  static constexpr double kDbar = 5000;

  static bool Total(const Vector& q, double* Q) {
    for (int i = 0; i < kN; ++i)
      if (!(q(i) >= 0.0)) return false;
    *Q = q.sum();
    return *Q > 0.0;
  }
  static double Price(double Q) { return std::pow(kDbar / Q, 1.0 / kGamma); }
};

}  // namespace

TestProblem Nash10() {
  TestProblem p;
  p.name = "nash";
  p.source =
      "Murphy, Sherali and Soyster, Math. Programming 24 (1982); Harker, Math. "
      "Programming "
      "41 (1988); MCPLIB nash (Dirkse and Ferris 1995); data and start of GAMS model "
      "library NASH (SEQ=269), read in github Rhh98/GAMS-MIRO oligopoly/nashemp.gms; F "
      "as "
      "in netlib ampl/models/compl/nash.mod";
  p.F = std::make_unique<Nash10Function>();
  internal::MakeStandardNcp(&p);
  p.starts = {{"gams", Vector::Ones(10)}, {"tens", Vector::Constant(10, 10.0)}};
  // Computed with this library (FB, default options, both starts agree to 1e-15) and
  // checked by the natural residual in tests/ncp/test_mcplib_equilibrium.cpp (no
  // published listing of the solution was available to compare with). Firms 2 and 6 have
  // identical data, and q_2 = q_6.
  p.solutions = {
      Vec({7.4415466970587349, 4.0978104473473209, 2.590643747438953, 0.9353857680722274,
           17.94895234200661, 4.0978104473473209, 1.3047257576800071, 5.5900825435576307,
           3.2221794538246153, 1.6770943168393271})};
  p.notes =
      "start \"gams\" is q.l = 1 of the GAMS model; \"tens\" (q = 10) is an additional "
      "start of this collection, not from MCPLIB. The solution is interior (F = 0), "
      "computed with this library and verified by its natural residual";
  return p;
}

std::vector<TestProblem> McplibEquilibriumProblems() {
  std::vector<TestProblem> problems;
  problems.push_back(Nash10());
  return problems;
}

}  // namespace ncp::collection
