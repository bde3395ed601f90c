/// \file problem.hpp
/// The mixed complementarity problem of the thesis (eq. 12 and 15) as a small interface.
///
/// Unknowns x in R^n. The first m rows are smooth equations E(x) = 0; the remaining
/// n - m rows are complementarity pairs
///     A_j(x) >= 0,  B_j(x) >= 0,  A_j(x) B_j(x) = 0,   j = 0 .. n-m-1.
/// The solver reformulates this as the square nonsmooth system
///     Phi(x) = [ E(x) ; phi(A_j(x), B_j(x)) ] = 0
/// and applies Algorithm 1 of the thesis (De Luca, Facchinei, Kanzow 1996).
///
/// The z-vector rule (DFK eq. 27, thesis section 3.1) needs a variable associated with
/// each row: row i of Phi is associated with variable i (so pair j belongs to variable
/// m + j). Order your unknowns so that this association is natural, e.g. for a standard
/// NCP pair j is (x_j, F_j(x)).
#pragma once

#include "ncp/types.hpp"

namespace ncp {

/// The accuracy a problem asks of each row, in the row's own units
/// (MixedProblem::Scales). Row i is converged when |row_i| <= floor_i + tolerance *
/// scale_i, with tolerance = Options::tolerance (then dimensionless, relative): an
/// absolute plus a relative accuracy per row, as ODE codes use atol + rtol |y|. For a
/// pair (A_j, B_j) the NCP function is applied to the rows divided by these accuracies,
/// phi(A_j / a_j, B_j / b_j), so that A_j and B_j may carry different units (e.g. a force
/// and a gap) and |phi| <= 1 means: A_j within its accuracy of 0, or B_j within its own,
/// with both >= minus their accuracy.
struct ResidualScales {
  Vector equation;  ///< typical magnitude of E_i (size m), > 0
  Vector a, b;      ///< typical magnitudes of A_j and B_j (size n - m), > 0
  Vector
      equation_floor;  ///< absolute accuracy of E_i (e.g. its round-off), >= 0; empty = 0
  Vector a_floor, b_floor;  ///< same for A_j and B_j; empty = 0
};

class MixedProblem {
 public:
  virtual ~MixedProblem() = default;

  /// n, the number of unknowns (= number of rows of Phi).
  virtual int NumVariables() const = 0;
  /// m, the number of smooth equations; the number of pairs is n - m.
  virtual int NumEquations() const = 0;

  /// Evaluates E (size m), A and B (size n - m) at x. The vectors arrive already sized.
  /// Returning false means "cannot evaluate at this x" (e.g. outside a domain): the
  /// line search then shortens the step.
  virtual bool Evaluate(const Vector& x, Vector* E, Vector* A, Vector* B) = 0;

  /// Jacobians dE/dx (m x n), dA/dx and dB/dx ((n-m) x n) at x, in compressed form.
  /// The sparsity patterns should stay fixed after the first call (explicit zeros are
  /// fine) so that the symbolic factorization is reused; a changed pattern is detected
  /// and triggers a new analysis. Jacobian() is only called at points where Evaluate()
  /// succeeded; returning false stops the solve with TerminationType::kEvaluationFailure.
  virtual bool Jacobian(const Vector& x, SparseMatrix* JE, SparseMatrix* JA,
                        SparseMatrix* JB) = 0;

  /// The variable associated with pair j for the z-vector rule (DFK eq. 27: z has a 1 at
  /// the associated variable of every degenerate pair). Default: m + j, the thesis's
  /// choice of row i <-> variable i. Override only if your ordering differs.
  virtual int PairVariable(int j) const { return NumEquations() + j; }

  /// Optional: the accuracy each row is to be solved to (see ResidualScales), evaluated
  /// once per solve at the start point x0. Return false (the default) to use the plain
  /// test
  /// ||Phi||_inf <= Options::tolerance in the units of the rows. When it returns true the
  /// solver works on the relative system E_i / t_i, phi(A_j / ta_j, B_j / tb_j) with
  /// t = scale + floor / tolerance, stops when its infinity norm is <= tolerance (i.e.
  /// every row within floor + tolerance * scale), and reports that norm in
  /// Summary::final_phi_inf (Summary::weighted_residual is true).
  virtual bool Scales(const Vector& x0, ResidualScales* scales) {
    (void)x0;
    (void)scales;
    return false;
  }

  /// Optional: the point a restart (Options::merit_restarts) continues from, given in *x
  /// the point where the solve got stuck. Default: x unchanged. The box MCP entry
  /// projects x onto [l, u]. Return false if no restart should be made.
  virtual bool RestartPoint(Vector* x) {
    (void)x;
    return true;
  }
};

}  // namespace ncp
