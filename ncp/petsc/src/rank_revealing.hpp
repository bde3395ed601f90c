// The distributed counterparts of the serial solver's internal::Equilibration and
// internal::RankRevealingSolver (ncp/src/linear_solver.hpp), for
// Options::scale_newton_system and Options::minimum_norm_step over PETSc
// (docs/petsc-design.md, "Singular Newton systems").
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <string>

namespace ncp::petsc {

/// Row and column scaling of a square AIJ matrix by powers of two, the serial rule
/// (internal::Equilibration): As = diag(r) A diag(c), r_i = 2^-e with 2^e <= max_j |a_ij|
/// < 2^(e+1), then c_j the same on the columns of diag(r) A; zero rows and columns keep
/// the scale 1. Exact in floating point, so Unscale restores A to the bit. Collective.
class DistributedEquilibration {
 public:
  DistributedEquilibration() = default;
  ~DistributedEquilibration();
  DistributedEquilibration(const DistributedEquilibration&) = delete;
  DistributedEquilibration& operator=(const DistributedEquilibration&) = delete;

  /// Computes r and c for A; returns whether the spread (max/min of the nonzero row
  /// max-norms of A and column max-norms of diag(r) A) exceeds
  /// internal::Equilibration::kSpreadThreshold, the serial test.
  bool Compute(Mat A);
  /// A <- diag(r) A diag(c) with the r, c of the last Compute.
  void Scale(Mat A) const;
  /// A <- diag(r)^-1 A diag(c)^-1: undoes Scale exactly.
  void Unscale(Mat A) const;
  Vec row() const { return row_; }
  Vec column() const { return column_; }
  double spread() const { return spread_; }

 private:
  Vec row_ = nullptr, column_ = nullptr;  // r (A's row layout), c (its column layout)
  Vec inverse_row_ = nullptr, inverse_column_ = nullptr;
  double spread_ = 1.0;
};

/// MUMPS' null-pivot detection on the factor matrix F (from MatGetFactor or
/// PCFactorGetMatrix, before its symbolic factorization) of an n x n matrix A: ICNTL(24)
/// = 1, CNTL(3) = n eps, so that a pivot whose row in the Schur complement has an
/// inf-norm below n eps ||A_pre||_inf (A_pre: A after MUMPS' own scaling) is null - the
/// rank tolerance n eps of the serial dense LU (relative to the largest pivot), relative
/// to the matrix's own scale; and ICNTL(13) = 1 (no ScaLAPACK on the root front, which
/// PETSc sets with ICNTL(24) for a reliable detection). The factorization then succeeds
/// on a singular A and counts its null pivots (MumpsNullPivots).
void ArmNullPivotDetection(Mat F, PetscInt n);
/// INFOG(28) of MUMPS' factor matrix F: the null pivots of its last factorization (the
/// same on every rank).
int MumpsNullPivots(Mat F);

/// The least-norm solution of a square, possibly singular J x = rhs whose system is
/// consistent, from MUMPS' LU with null-pivot detection (ArmNullPivotDetection) of J
/// equilibrated (DistributedEquilibration, always, as the serial RankRevealingSolver):
/// Js = diag(r) J diag(c), Js y = diag(r) rhs, x = diag(c) y. MUMPS' solve with the k =
/// INFOG(28) null pivots fixed gives one solution y0; k probes give a basis N of null(Js)
/// (rank_revealing.cpp, NullVector); y = y0 - N (N'N)^-1 N' y0 is the solution of least
/// 2-norm in the scaled unknowns - the vector the serial complete orthogonal
/// decomposition (dense) and SuiteSparseQR of J' (sparse) give for a consistent system
/// when the ranks found agree. An inconsistent system gets a y that does not solve it
/// (the caller's backward-error check rejects it; the serial solver rejects its
/// least-squares step there as well). Collective.
class MinimumNormSolver {
 public:
  /// MUMPS options from the database under `options_prefix` (e.g. ncp_mn_) apply to the
  /// factorization, given after the null-pivot settings above.
  explicit MinimumNormSolver(std::string options_prefix)
      : prefix_(std::move(options_prefix)) {}
  /// x = diag(c) y as above (x laid out like J's columns); false when MUMPS' analysis or
  /// factorization failed, the null space's Gram matrix is singular, or x is not
  /// finite.
  bool Solve(Mat J, Vec rhs, Vec x);
  /// Null pivots MUMPS found at the last Solve (INFOG(28)), -1 before.
  int null_pivots() const { return null_pivots_; }

 private:
  std::string prefix_;
  DistributedEquilibration equilibration_;
  int null_pivots_ = -1;
};

}  // namespace ncp::petsc
