// The Coulomb law of one contact written as Phi(r, u) = 0, with its generalized Jacobian
// blocks A = dPhi/dr and B = dPhi/du (components: normal, tangent 1[, tangent 2]; in 2D
// the third row and column stay zero).
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "ncp/fc/solver.hpp"

namespace ncp::fc::internal {

using Block = Eigen::Matrix3d;

/// Alart-Curnier (Alart & Curnier 1991; Christensen & Pang 1998), with s_N = r_N - rho_N
/// u_N, s_T = r_T - rho_T u_T, radius R = mu max(0, s_N):
///   Phi_N = r_N - max(0, s_N),   Phi_T = r_T - P_{B(0,R)}(s_T).
/// Jacobian: the element of the B-subdifferential that takes max'(0) = 0 and, on the disk
/// boundary |s_T| = R, the sticking branch.
void AlartCurnierLaw(int d, double mu, double rho_n, double rho_t, const double* r,
                     const double* u, double* phi, Block* A, Block* B);

/// Natural map of the De Saxce form (Siconos NSN_NM): u_hat = u + (mu |u_T|, 0, 0),
///   Phi = r - P_{C_mu}(r - rho u_hat),
/// A = I - J_P, B = rho J_P (I + mu e_N (0, u_T/|u_T|)'), J_P the Jacobian of the cone
/// projection (identity inside, zero in the polar cone, Hiriart-Urruty's formula
/// between).
void NaturalMapLaw(int d, double mu, double rho, const double* r, const double* u,
                   double* phi, Block* A, Block* B);

/// Fischer-Burmeister function of the second-order cone (Fukushima, Luo & Tseng 2001) on
/// the scaled pair x = (mu r_N, r_T) in K, y = (u_N + mu |u_T|, mu u_T) in K (K = C_1 is
/// self-dual and x . y = mu r . u_hat, so x, y complementary in K <=> the Coulomb law):
///   Phi = x + y - (x o x + y o y)^(1/2)   (o: Jordan product; the square root spectral).
/// dPhi = dx + dy - L_z^-1 (L_x dx + L_y dy), z = (x o x + y o y)^(1/2), L_v the arrow
/// matrix [v0, v_bar'; v_bar, v0 I], where z is interior; at the boundary L_z + eps I. mu
/// = 0: Phi = (r_N + u_N - |(r_N, u_N)|, r_T) (scalar FB and r_T = 0).
void FischerBurmeisterLaw(int d, double mu, const double* r, const double* u, double* phi,
                          Block* A, Block* B);

/// The rho of one contact (solver.hpp, Formulation): rho_n = 1 / W_NN, rho_t = 1 /
/// mean(W_TT), rho_nm = 1 / mean(diag W_aa), from the diagonal of its block (d entries);
/// a zero entry takes `fallback` (1 / the largest diagonal entry of W, or 1).
struct Rho {
  double n = 1.0, t = 1.0, nm = 1.0;
};
Rho RhoFromDiagonal(int d, const double* diagonal, double fallback);

/// Phi and the blocks A, B of contact law `formulation` (not kHybrid) with rho times
/// `scale` (Options::rho_scale times the attempt's factor).
void EvaluateLaw(Formulation formulation, int d, double mu, const Rho& rho, double scale,
                 const double* r, const double* u, double* phi, Block* A, Block* B);

/// One attempt of a solve: a formulation with rho times rho_factor.
struct Attempt {
  Formulation formulation;
  double rho_factor;
};
/// A fixed sequence of attempts (static storage: nothing allocated per solve).
struct AttemptList {
  const Attempt* first;
  int count;
  const Attempt* begin() const { return first; }
  const Attempt* end() const { return first + count; }
};
/// The attempts of a solve: kHybrid's sequence (solver.hpp) or the one formulation asked
/// for.
AttemptList AttemptSequence(Formulation formulation);

/// The end of a Newton attempt at natural-map error `error` (the previous iterate's:
/// `previous`): error <= tolerance, or error <= acceptable_tolerance without halving
/// (Options::acceptable_tolerance).
inline bool Converged(const Options& options, double error, double previous) {
  return error <= options.tolerance ||
         (error <= options.acceptable_tolerance && error > 0.5 * previous);
}
/// The bookkeeping of one Newton attempt after each of its steps: the best iterate,
/// convergence (Converged) and stalling (the error not halved within
/// Options::stall_window steps).
class AttemptProgress {
 public:
  AttemptProgress(const Options& options, double start_error)
      : options_(options), stall_reference_(start_error), previous_(start_error) {}
  /// After a step to r with natural-map error `error`: r into *best_r if it is the best
  /// so far; returns kConverged, kStalled, or kNotSolved to go on.
  Termination Update(double error, const Vector& r, double* best_error, Vector* best_r) {
    if (error < *best_error) {
      *best_error = error;
      *best_r = r;
    }
    if (Converged(options_, error, previous_)) return Termination::kConverged;
    previous_ = error;
    if (error <= 0.5 * stall_reference_) {
      stall_reference_ = error;
      since_progress_ = 0;
    } else if (++since_progress_ >= options_.stall_window) {
      return Termination::kStalled;
    }
    return Termination::kNotSolved;
  }
  /// The error of the previous step (the start's before the first).
  double previous_error() const { return previous_; }

 private:
  const Options& options_;
  double stall_reference_, previous_;
  int since_progress_ = 0;
};

/// kAtRoundoffFloor for a solve that ended kConverged by the round-off floor (error above
/// Options::tolerance, at most Options::acceptable_tolerance); else `status`.
inline Termination RoundoffFloorStatus(const Options& options, Termination status,
                                       double error) {
  return status == Termination::kConverged && error > options.tolerance
             ? Termination::kAtRoundoffFloor
             : status;
}

/// Converged, or at the round-off floor (Summary::IsSolutionUsable).
inline bool Usable(Termination status) {
  return status == Termination::kConverged || status == Termination::kAtRoundoffFloor;
}

/// "natural-map error e <= tolerance t" (or "<= acceptable tolerance a (round-off
/// floor)", or "> tolerance t") into *out (assigned: no allocation when its capacity
/// suffices).
void ErrorReport(const Options& options, bool converged, double error, std::string* out);

/// *summary reset to its defaults (Summary()) for a new solve of `num_contacts` contacts,
/// the counters of every solver at 0, keeping the storage of its trace and message.
void ResetSummary(const Options& options, int num_contacts, Summary* summary);

}  // namespace ncp::fc::internal
