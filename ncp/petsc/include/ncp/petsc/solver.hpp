/// \file solver.hpp
/// ncp's semismooth Newton method (ncp/solver.hpp: Algorithm 1 of the thesis with the
/// same ncp::Options and ncp::Summary) over distributed PETSc objects: the box MCP
///
///     l <= x <= u  perp  F(x)       (x, l, u, F(x) distributed Vecs, F'(x) a Mat)
///
/// on any number of MPI ranks. Every decision of the iteration (z-vector rule, descent
/// test, nonmonotone Armijo, merit restarts, the hybrid's strategy switches, stopping
/// tests) is the serial solver's own code (ncp/src/globalization.hpp, strategy.hpp); only
/// the linear algebra is PETSc's. Two-sided bounds are split with slack unknowns as the
/// serial solver does (ncp/src/box_mcp.cpp), the slacks living on the rank of their
/// component. The Newton
/// systems J d = -Phi are solved by a KSP: by default a direct LU factorization by MUMPS
/// (KSPPREONLY + PCLU + MATSOLVERMUMPS); any KSP/PC from PETSc's options database under
/// the solver's prefix, e.g. -ncp_ksp_type cg -ncp_pc_type gamg (docs/petsc.md). The
/// Levenberg-Marquardt systems (Options::regularized_direction and the hybrid's "+lm"
/// strategies) have their own KSP under <prefix>lm_, by default MUMPS LU as well.
///
/// The caller initializes PETSc (PetscInitialize) before constructing a Solver and
/// finalizes it after destroying it; the library never does either.
///
/// Errors: misuse (PETSc not initialized, Vecs of different layouts, l > u, NaN in a
/// bound or in x0, invalid Options) throws std::invalid_argument with the same message on
/// every rank of the communicator (the checks are collective). Numerical trouble (a
/// residual with NaN, a singular Newton matrix, a stalled line search) never throws: it
/// ends the solve with a TerminationType and a message in the Summary, again the same on
/// every rank.
#pragma once

#include <petscdm.h>
#include <petscksp.h>
#include <petscmat.h>
#include <petscvec.h>

#include <functional>
#include <memory>
#include <string>

#include "ncp/solver.hpp"

namespace ncp::petsc {

/// f = F(x). x and f have the layout of the start point. Return 0 when F could be
/// evaluated; a non-zero value (on any rank) means "F cannot be evaluated at x": the line
/// search then shortens the step, like `false` from ncp::SquareFunction::Evaluate.
using ResidualFunction = std::function<PetscErrorCode(Vec x, Vec f)>;
/// J = F'(x), assembled (MatAssemblyBegin/End) into the matrix BoxMcp::jacobian_matrix
/// with the same nonzero pattern at every call. Return value as for ResidualFunction.
using JacobianFunction = std::function<PetscErrorCode(Vec x, Mat J)>;

/// The same callbacks as PETSc-style function pointers with a user context.
using ResidualFunctionPointer = PetscErrorCode (*)(Vec x, Vec f, void* context);
using JacobianFunctionPointer = PetscErrorCode (*)(Vec x, Mat J, void* context);

/// The box MCP l <= x <= u perp F(x). The solver does not take ownership of any object.
struct BoxMcp {
  ResidualFunction residual;
  JacobianFunction jacobian;
  /// The matrix F'(x) is assembled into (e.g. from DMCreateMatrix or MatCreateAIJ):
  /// square, rows distributed like x. An AIJ type (MATSEQAIJ / MATMPIAIJ) is required.
  Mat jacobian_matrix = nullptr;
  /// Lower bounds, laid out like x; nullptr means -inf everywhere. An entry <=
  /// -Options::infinite_bound (PETSC_NINFINITY, -1e20) is no bound.
  Vec lower = nullptr;
  /// Upper bounds, laid out like x; nullptr means +inf everywhere. An entry >=
  /// Options::infinite_bound (PETSC_INFINITY, 1e20) is no bound.
  Vec upper = nullptr;

  /// A BoxMcp from PETSc-style function pointers and their context.
  static BoxMcp FromFunctionPointers(ResidualFunctionPointer residual,
                                     JacobianFunctionPointer jacobian, void* context,
                                     Mat jacobian_matrix, Vec lower, Vec upper);
};

/// Counters of the PETSc solver beyond ncp::Summary (Summary::linear_solver_used stays
/// kAuto: the Newton systems are solved by the KSP described here).
struct KspReport {
  std::string ksp_type;            ///< e.g. "preonly"
  std::string pc_type;             ///< e.g. "lu"
  std::string factor_solver_type;  ///< e.g. "mumps" (empty without a factorization)
  /// KSP iterations summed over all Newton (and Levenberg-Marquardt) systems
  int linear_iterations = -1;
  /// Of those, the Newton KSP's iterations past its own test (rtol, atol) until its
  /// residual passed -<prefix>newton_residual_fraction f times the outer stopping test
  /// (f in [0, 1], default 0.5 for the min function's systems, 0: off; docs/petsc.md)
  int residual_test_iterations = -1;
  /// The KSP solved the symmetrized Newton system (rows scaled, fixed rows eliminated;
  /// docs/petsc.md): on by default for CG-like KSPs and Cholesky/ICC, else off;
  /// -<prefix>symmetric_newton true|false decides.
  bool symmetric_newton = false;
  int ranks = -1;  ///< size of the communicator
};

/// The interpolation from the grid `coarse` to the grid `fine` (DMCreateInterpolation),
/// made at the first call for this pair and kept on `fine` (PetscObjectCompose): a
/// nested iteration that interpolates its start points with it and the solver's
/// multigrid on the refined grids (Solver::SetMultigridGrid, which follows
/// DMGetCoarseDM) make each interpolation of the sequence once. Borrowed: valid while
/// `fine` lives, not to be destroyed by the caller. Collective on fine's communicator.
Mat GridInterpolation(DM coarse, DM fine);

/// Keeps the KSP (and the symbolic factorization of a direct solver) between solves.
class Solver {
 public:
  /// comm: the communicator of every Vec and Mat of the problems solved. options_prefix:
  /// prefix of the KSP in PETSc's options database ("ncp_": -ncp_ksp_type, -ncp_pc_type,
  /// ...; the LM systems' KSP: -ncp_lm_ksp_type, ...). Throws std::invalid_argument
  /// (collectively) when PETSc is not initialized or the options are invalid, or when
  /// they name a serial linear solver (Options::linear_solver other than kAuto).
  explicit Solver(MPI_Comm comm, const Options& options = Options(),
                  const std::string& options_prefix = "ncp_");
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  const Options& options() const;
  /// The KSP of the Newton systems, configured from the options database at the first
  /// solve; set its type here (KSPSetType, KSPGetPC/PCSetType) to override the default
  /// before Solve (the options database still has the last word).
  KSP ksp() const;

  /// Multigrid restricted to the inactive set, for the symmetrized Newton systems
  /// (docs/petsc.md): with -<prefix>pc_type mg and a CG-like KSP, PCMG's hierarchy of
  /// -<prefix>pc_mg_levels levels is made from `grid` down: each level's coarser grid is
  /// the one it was refined from (DMGetCoarseDM, with GridInterpolation) where set, else
  /// DMCoarsen and DMCreateInterpolation; and at every Newton step the interpolation into
  /// each level keeps only the rows of the unknowns still in the reduced system (the
  /// others were eliminated: the active set of the min function), the coarse operators
  /// being Galerkin products of that reduced system - the multigrid of a reduced-space
  /// active-set method. `grid`'s global vectors must be laid out like x (checked at
  /// Solve, with the PC type and the symmetric mode: std::invalid_argument otherwise). Do
  /// not also give the grid to the KSP (KSPSetDM): PCMG is set up here. nullptr switches
  /// it off. The Solver keeps a reference to `grid`.
  void SetMultigridGrid(DM grid);

  /// Solves the box MCP; x holds the start point on entry and the last iterate on return
  /// (the solution when summary->IsSolutionUsable()), projected onto [l, u] like the
  /// serial solver's. Collective on the communicator. Bounds with two finite sides
  /// (l_i < u_i) add two slack unknowns each (Summary::num_variables counts them); they
  /// make the Newton matrix unsymmetric, so a solver whose KSP asks for the symmetrized
  /// system (CG-like, Cholesky/ICC) rejects them with std::invalid_argument.
  void Solve(const BoxMcp& problem, Vec x, Summary* summary);

  /// The KSP used by the last solve and its iteration count.
  const KspReport& ksp_report() const;

  /// The state kept between solves (opaque: defined in the library's sources).
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ncp::petsc
