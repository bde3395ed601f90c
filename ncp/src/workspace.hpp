// Solver::Workspace: what a Solver keeps between solves (solver.cpp runs Algorithm 1 on
// it). The Jacobian of Phi with a cached pattern, the linear solver, and every vector of
// the iteration, sized by Solve() before the first iteration (reallocated only when n, m
// or the Jacobian pattern change). The iterations then allocate only inside the numeric
// factorization of a sparse backend (SuiteSparse for UMFPACK and KLU, and
// Eigen::SparseLU) and for Summary::trace with keep_trace; the Summary's message is built
// when the solve ends (tests/contact/test_no_allocation.cpp).
#pragma once

#include <memory>
#include <vector>

#include "box_mcp.hpp"
#include "globalization.hpp"
#include "linear_solver.hpp"
#include "ncp/solver.hpp"
#include "sparse_pattern.hpp"
#include "strategy.hpp"

namespace ncp {

struct Solver::Workspace {
  std::unique_ptr<internal::LinearSolver> linear_solver;
  // The last box MCP in mixed form, reused when the same F and bounds come again.
  internal::BoxMcpCache box_mcp;
  // The backend of the last solve; dense: J is the dense Jd and dense_lu factorizes it
  // (the light path of small problems: no pattern bookkeeping, no sparse matrix, no
  // allocation).
  LinearSolverType backend = LinearSolverType::kAuto;
  bool dense = false;
  DenseMatrix Jd;
  internal::DenseLU dense_lu;
  // Options::scale_newton_system: dense_lu holds the LU of Js = diag(r) Jd diag(c) when
  // `equilibrated` (the rows or columns of Jd spread over more than 2^20).
  internal::Equilibration equilibration;
  bool equilibrated = false;
  DenseMatrix Js;
  Vector scaled_rhs;
  // Options::minimum_norm_step: the least-squares step of a singular J.
  internal::RankRevealingSolver rank_revealing;

  // Cached patterns of the user's JE, JA, JB; a change triggers a new symbolic analysis.
  internal::SparsePattern pattern[3];
  bool have_pattern = false;

  // J = [JE; diag(da) JA + diag(db) JB], pattern = union; map[s][k] is where the k-th
  // stored entry of source s lands in J's value array.
  SparseMatrix J;
  std::vector<int> map[3];

  SparseMatrix JE, JA, JB;
  // Row weights 1 / (scale + floor / tolerance) of MixedProblem::Scales (when
  // `weighted`).
  bool weighted = false;
  ResidualScales scales;
  Vector we, wa, wb;
  Vector E, A, B, Et, At, Bt;  // current point and trial point
  Vector phi, phi_trial, grad, d, x_trial, da, db, z, za, zb, newton_rhs, newton_residual,
      newton_terms;
  // Round-off floor (Options::roundoff_ulps): row i of |J||x| summed entry by entry, i.e.
  // |J_E||x| for an equation and |da| |J_A||x| + |db| |J_B||x| for a pair.
  Vector sensitivity;
  // flop/s of the last timed numeric factorization (0: none timed yet).
  double measured_flop_rate = 0.0;
  // Levenberg-Marquardt system J'J + mu I, its own solver and pattern bookkeeping.
  std::unique_ptr<internal::LinearSolver> regularized_solver;
  SparseMatrix normal_matrix, identity;
  bool regularized_analyzed = false;
  Eigen::Index regularized_nonzeros = -1;
  // The nonmonotone Armijo reference and the stagnation test (globalization.hpp).
  internal::NonmonotoneReference armijo_reference;
  internal::StagnationTest stagnation;
  // The hybrid default (Options::hybrid, strategy.hpp).
  internal::StrategySchedule schedule;
  internal::StrategyProgress progress;

  /// Sizes every vector of the iteration for n unknowns and m equations (zeros).
  void Resize(int n, int m);

  /// Returns true when the pattern differs from the cached one (and rebuilds J's
  /// pattern).
  bool UpdatePattern(int m);

  /// Calls add(s, k, row, col, value) for the k-th stored entry of source s (JE, JA,
  /// JB) as an entry of J = [JE; diag(da) JA + diag(db) JB]: the row of J, the value
  /// scaled by da or db.
  template <class Add>
  void ForEachJacobianEntry(int m, Add&& add) const;

  /// Jd = J, dense (the light path); sensitivity = |J||x| row by row (with the partials
  /// da, db inside, the round-off floor's r; see WithinRoundoffFloor).
  void FillDenseJacobian(int m, const Vector& x);

  /// out = J' v.
  void MultiplyJacobianTransposed(const Vector& v, Vector* out) const;

  /// *residual = J v + b and returns max_i (|J||v|)_i, the size of the terms summed in
  /// J v (its round-off is relative to that, not to |J v|); one pass over J.
  double ResidualAndTerms(const Vector& v, const Vector& b, Vector* residual,
                          Vector* terms) const;

  /// J values = [JE; diag(da) JA + diag(db) JB] on the cached pattern; sensitivity as
  /// above.
  void FillJacobian(int m, const Vector& x);

  /// Row weights from the problem's own scales (MixedProblem::Scales) at x0, once per
  /// solve: sets we, wa, wb and `weighted` (false: the problem gives none).
  void SetWeights(MixedProblem& problem, const Vector& x0, int m, int p,
                  double tolerance);
  /// JE, JA, JB rows *= we, wa, wb (the Jacobian of the weighted rows).
  void WeightJacobianRows();
};

}  // namespace ncp
