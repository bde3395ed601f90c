#include "local_laws.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ncp/fc/error.hpp"

namespace ncp::fc::internal {

namespace {

/// The tangential part of a d-vector as a 3-vector (third entry 0 in 2D).
Eigen::Vector3d Tangent(int d, const double* v) {
  return Eigen::Vector3d(0.0, v[1], d == 3 ? v[2] : 0.0);
}

/// Selector of the tangential components: diag(0, 1[, 1]).
Block TangentSelector(int d) {
  Block E = Block::Zero();
  for (int i = 1; i < d; ++i) E(i, i) = 1.0;
  return E;
}

/// Jacobian of the projection onto C_mu at s (see ProjectOnCone). With t = |s_T|,
/// n = s_T / t, a = (s_N + mu t) / (1 + mu^2), between the cones:
///   J_P = [1, mu n'; mu n, mu^2 n n'] / (1 + mu^2) + (mu a / t) (E_T - n n').
Block ConeProjectionJacobian(int d, double mu, const Eigen::Vector3d& s) {
  const Eigen::Vector3d sT = Tangent(d, s.data());
  const double t = sT.norm();
  if (s[0] >= 0.0 && t <= mu * s[0])
    return d == 3 ? Block::Identity() : Block(Eigen::Vector3d(1, 1, 0).asDiagonal());
  if (mu * t <= -s[0]) return Block::Zero();
  const Eigen::Vector3d n = sT / t;
  const double a = (s[0] + mu * t) / (1.0 + mu * mu);
  Eigen::Vector3d v = mu * n;  // (1, mu n) / sqrt(1 + mu^2) is the boundary direction
  v[0] = 1.0;
  Block J = v * v.transpose() / (1.0 + mu * mu);
  J += (mu * a / t) * (TangentSelector(d) - n * n.transpose());
  return J;
}

}  // namespace

void AlartCurnierLaw(int d, double mu, double rho_n, double rho_t, const double* r,
                     const double* u, double* phi, Block* A, Block* B) {
  A->setZero();
  B->setZero();
  const Block ET = TangentSelector(d);
  const double sN = r[0] - rho_n * u[0];
  const bool open = sN > 0.0;  // normal force active
  if (open) {
    phi[0] = rho_n * u[0];
    (*B)(0, 0) = rho_n;
  } else {
    phi[0] = r[0];
    (*A)(0, 0) = 1.0;
  }
  const Eigen::Vector3d rT = Tangent(d, r), sT = rT - rho_t * Tangent(d, u);
  const double radius = mu * std::max(0.0, sN), t = sT.norm();
  if (t <= radius) {  // sticking: Phi_T = rho_t u_T
    for (int i = 1; i < d; ++i) phi[i] = rho_t * u[i];
    B->bottomRows<2>() += rho_t * ET.bottomRows<2>();
    return;
  }
  // sliding: Phi_T = r_T - R n, n = s_T / t;
  // dP = (R / t)(E_T - n n') ds_T + n dR, ds_T = E_T (dr - rho_t du), dR = mu [s_N > 0]
  // ds_N.
  const Eigen::Vector3d n = sT / t;
  for (int i = 1; i < d; ++i) phi[i] = r[i] - radius * n[i];
  const Block Pt = (radius / t) * (ET - n * n.transpose());
  *A += ET - Pt;
  *B += rho_t * Pt;
  if (open) {
    A->col(0) -= mu * n;
    B->col(0) += mu * rho_n * n;
  }
}

void NaturalMapLaw(int d, double mu, double rho, const double* r, const double* u,
                   double* phi, Block* A, Block* B) {
  const Eigen::Vector3d uT = Tangent(d, u);
  const double ut = uT.norm();
  Eigen::Vector3d s = Eigen::Vector3d::Zero(), P;
  s[0] = r[0] - rho * (u[0] + mu * ut);
  for (int i = 1; i < d; ++i) s[i] = r[i] - rho * u[i];
  const Block JP = ConeProjectionJacobian(d, mu, s);
  P = s;
  ProjectOnCone(mu, d, P.data());
  for (int i = 0; i < d; ++i) phi[i] = r[i] - P[i];
  Block I = Block::Identity();
  if (d == 2) I(2, 2) = 0.0;
  Block D = I;  // d u_hat / d u
  if (ut > 0.0) D.row(0) += mu * (uT / ut).transpose();
  *A = I - JP;
  *B = rho * JP * D;
}

namespace {

/// Arrow matrix L_v = [v0, v_bar'; v_bar, v0 I] of the Jordan product: L_v w = v o w.
Block Arrow(const Eigen::Vector3d& v) {
  Block L = v[0] * Block::Identity();
  L.block<1, 2>(0, 1) = v.tail<2>().transpose();
  L.block<2, 1>(1, 0) = v.tail<2>();
  return L;
}

}  // namespace

void FischerBurmeisterLaw(int d, double mu, const double* r, const double* u, double* phi,
                          Block* A, Block* B) {
  A->setZero();
  B->setZero();
  if (mu == 0.0) {  // scalar FB on (r_N, u_N), and r_T = 0
    const double norm = std::hypot(r[0], u[0]);
    phi[0] = r[0] + u[0] - norm;
    (*A)(0, 0) = norm > 0.0 ? 1.0 - r[0] / norm : 1.0 - 1.0 / std::sqrt(2.0);
    (*B)(0, 0) = norm > 0.0 ? 1.0 - u[0] / norm : 1.0 - 1.0 / std::sqrt(2.0);
    for (int i = 1; i < d; ++i) {
      phi[i] = r[i];
      (*A)(i, i) = 1.0;
    }
    return;
  }
  const Eigen::Vector3d uT = Tangent(d, u);
  const double ut = uT.norm();
  const Eigen::Vector3d x(mu * r[0], r[1], d == 3 ? r[2] : 0.0);
  const Eigen::Vector3d y(u[0] + mu * ut, mu * u[1], d == 3 ? mu * u[2] : 0.0);
  // w = x o x + y o y = (|x|^2 + |y|^2, 2 (x0 x_bar + y0 y_bar)), spectral values w0 -+
  // |w_bar|
  const double w0 = x.squaredNorm() + y.squaredNorm();
  const Eigen::Vector2d wbar = 2.0 * (x[0] * x.tail<2>() + y[0] * y.tail<2>());
  const double wn = wbar.norm();
  const Eigen::Vector2d e =
      wn > 0.0 ? Eigen::Vector2d(wbar / wn) : Eigen::Vector2d(1.0, 0.0);
  const double s1 = std::sqrt(std::max(0.0, w0 - wn)), s2 = std::sqrt(w0 + wn);
  Eigen::Vector3d z;
  z[0] = 0.5 * (s1 + s2);
  z.tail<2>() = 0.5 * (s2 - s1) * e;
  const Eigen::Vector3d f = x + y - z;
  for (int i = 0; i < d; ++i) phi[i] = f[i];
  // L_z is singular on the boundary of K (s1 = 0); shift it there.
  Block Lz = Arrow(z);
  const double eps = 1e-12 * std::max(1.0, z[0]);
  if (s1 <= eps) Lz += eps * Block::Identity();
  const Eigen::PartialPivLU<Block> lu(Lz);
  const Block I = Block::Identity();
  Block Dx = Block::Zero();  // dx/dr
  Dx(0, 0) = mu;
  for (int i = 1; i < d; ++i) Dx(i, i) = 1.0;
  Block Dy = Block::Zero();  // dy/du
  Dy(0, 0) = 1.0;
  if (ut > 0.0) Dy.block<1, 2>(0, 1) = mu * (uT.tail<2>() / ut).transpose();
  for (int i = 1; i < d; ++i) Dy(i, i) = mu;
  *A = (I - lu.solve(Arrow(x))) * Dx;
  *B = (I - lu.solve(Arrow(y))) * Dy;
}

Rho RhoFromDiagonal(int d, const double* diagonal, double fallback) {
  auto inverse = [fallback](double w) { return w > 0.0 ? 1.0 / w : fallback; };
  double tangential = 0.0;
  for (int i = 1; i < d; ++i) tangential += diagonal[i] / (d - 1);
  Rho rho;
  rho.n = inverse(diagonal[0]);
  rho.t = inverse(tangential);
  rho.nm = inverse((diagonal[0] + tangential * (d - 1)) / d);
  return rho;
}

void EvaluateLaw(Formulation formulation, int d, double mu, const Rho& rho, double scale,
                 const double* r, const double* u, double* phi, Block* A, Block* B) {
  if (formulation == Formulation::kAlartCurnier)
    AlartCurnierLaw(d, mu, scale * rho.n, scale * rho.t, r, u, phi, A, B);
  else if (formulation == Formulation::kNaturalMap)
    NaturalMapLaw(d, mu, scale * rho.nm, r, u, phi, A, B);
  else
    FischerBurmeisterLaw(d, mu, r, u, phi, A, B);
}

void ErrorReport(const Options& options, bool converged, double error, std::string* out) {
  char buffer[160];
  if (converged && error > options.tolerance)
    std::snprintf(
        buffer, sizeof buffer,
        "natural-map error %g <= acceptable tolerance %g (round-off floor; tolerance %g)",
        error, options.acceptable_tolerance, options.tolerance);
  else
    std::snprintf(buffer, sizeof buffer, "natural-map error %g %s tolerance %g", error,
                  converged ? "<=" : ">", options.tolerance);
  out->assign(buffer);
}

void ResetSummary(const Options& options, int num_contacts, Summary* summary) {
  std::vector<IterationRecord> trace = std::move(summary->trace);
  std::string message = std::move(summary->message);
  trace.clear();
  *summary = Summary();
  message = summary->message;
  // Room for the longest message of a solve (ErrorReport's 160 characters, the counts
  // and the termination): repeated solves then write it in place.
  message.reserve(256);
  summary->trace = std::move(trace);
  summary->message = std::move(message);
  summary->formulation_requested = options.formulation;
  summary->num_contacts = num_contacts;
  summary->iterations = 0;
  summary->gauss_seidel_sweeps = 0;
  summary->fallback_sweeps = 0;
  summary->attempts = 0;
  summary->backtracks = 0;
  summary->linear_solver_failures = 0;
  summary->levenberg_marquardt_steps = 0;
}

AttemptList AttemptSequence(Formulation formulation) {
  static constexpr Attempt kHybrid[] = {
      {Formulation::kAlartCurnier, 1.0}, {Formulation::kFischerBurmeister, 1.0},
      {Formulation::kNaturalMap, 1.0},   {Formulation::kAlartCurnier, 10.0},
      {Formulation::kNaturalMap, 0.1},   {Formulation::kAlartCurnier, 0.1},
      {Formulation::kNaturalMap, 10.0}};
  static constexpr Attempt kSingle[] = {{Formulation::kAlartCurnier, 1.0},
                                        {Formulation::kNaturalMap, 1.0},
                                        {Formulation::kFischerBurmeister, 1.0}};
  switch (formulation) {
    case Formulation::kAlartCurnier:
      return {&kSingle[0], 1};
    case Formulation::kNaturalMap:
      return {&kSingle[1], 1};
    case Formulation::kFischerBurmeister:
      return {&kSingle[2], 1};
    case Formulation::kHybrid:
      break;
  }
  return {kHybrid, static_cast<int>(sizeof kHybrid / sizeof kHybrid[0])};
}

}  // namespace ncp::fc::internal
