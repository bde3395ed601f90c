/// \file bueler_obstacle.hpp
/// Bueler's radially symmetric obstacle problem (the problem of PETSc's SNES tutorial
/// ex9, written here from its mathematical description) on a DMDA with the 5-point
/// stencil.
///
///   -Laplace u = 0 where u > psi,  u >= psi,  -Laplace u >= 0   on S = (-2, 2)^2,
///   u = u_exact on the boundary of S.
///
/// Obstacle (r = |(x, y)|): the upper unit hemisphere, continued by its tangent beyond
/// r0:
///   psi(r) = sqrt(1 - r^2)                         for r <= r0 = 0.9,
///   psi(r) = psi(r0) + psi'(r0) (r - r0)           for r >  r0,  psi'(r0) = -r0 / sqrt(1
///   - r0^2).
/// Exact solution: u = psi on r <= a, u = A log(2 / r) on r > a, where the free boundary
/// a solves a^2 (log 2 - log a) = 1 - a^2 (u, u' continuous at r = a; u(2) = 0) and A =
/// a^2 / sqrt(1 - a^2)  (E. Bueler, PETSc for Partial Differential Equations, SIAM 2021,
/// ch. 12). a ~ 0.698 < r0, so the exact solution never meets the tangent "skirt".
///
/// Discretization: nodes x_i = -2 + i h_x, i = 0..M-1 (same in y); F is the 5-point
/// -Laplacian scaled by the cell area h_x h_y (the load a node carries, in the units of
/// u), so that both arguments of the NCP function, u - psi and F, are in the units of u
/// (and the discrete system is the finite-element one with mass lumping):
///   interior: F = 2 (h_y/h_x + h_x/h_y) u_ij - h_y/h_x (u_E + u_W) - h_x/h_y (u_N +
///   u_S),
///             with boundary neighbours replaced by their Dirichlet values, so the
///             interior block of the Jacobian is the symmetric positive definite 5-point
///             Laplacian;
///   boundary: F = 2 (h_y/h_x + h_x/h_y) (u_ij - u_exact) (same diagonal as the
///   interior).
/// A residual r in these units is a Laplacian residual r / (h_x h_y), which bounds the
/// algebraic error in u by about r / (h_x h_y lambda_min(-Laplace)), lambda_min = pi^2
/// / 8. Bounds: lower = psi on interior nodes, -inf on boundary nodes; upper = +inf.
#pragma once

#include <petscdmda.h>
#include <petscsnes.h>

namespace ncp_petsc_bench {

/// Domain S = (kDomainMin, kDomainMax)^2 (dimensionless lengths).
constexpr double kDomainMin = -2.0;
constexpr double kDomainMax = 2.0;
/// Radius where the hemisphere obstacle is continued by its tangent.
constexpr double kSkirtRadius = 0.9;

/// The free-boundary radius a of the exact solution: root of a^2 (log 2 - log a) = 1 -
/// a^2 in (0, 1), found by bisection to machine precision.
double FreeBoundaryRadius();
/// Obstacle psi(x, y).
double Obstacle(double x, double y);
/// Exact solution u(x, y).
double ExactSolution(double x, double y);

/// Creates the M x M node DMDA on S (star stencil, width 1, coordinates set). M >= 3.
PetscErrorCode CreateGrid(MPI_Comm comm, PetscInt nodes_per_side, DM* da);

/// Residual F(u) as a DMDA local function (DMDASNESSetFunctionLocal signature).
PetscErrorCode FormResidualLocal(DMDALocalInfo* info, PetscScalar** u, PetscScalar** f,
                                 void* ctx);
/// Jacobian F'(u) as a DMDA local function (DMDASNESSetJacobianLocal signature).
PetscErrorCode FormJacobianLocal(DMDALocalInfo* info, PetscScalar** u, Mat J, Mat P,
                                 void* ctx);
/// Global-vector forms of the two above on grid `da` (for callers without a SNES).
PetscErrorCode EvaluateResidual(DM da, Vec u, Vec f);
PetscErrorCode EvaluateJacobian(DM da, Vec u, Mat J);

/// Fills lower = psi (interior) / -inf (boundary) and upper = +inf on grid `da`.
PetscErrorCode FormBounds(DM da, Vec lower, Vec upper);
/// SNESVISetComputeVariableBounds callback: FormBounds on the SNES's current DM (so
/// bounds follow -snes_grid_sequence refinements).
PetscErrorCode ComputeBoundsOnSnesGrid(SNES snes, Vec lower, Vec upper);

/// The cell area h_x h_y of grid `da`: the factor between a tolerance on -Laplace u and
/// one on F.
PetscErrorCode CellArea(DM da, double* area);

/// Errors of the grid function u against the exact solution at the nodes.
struct ErrorVsExact {
  double max_norm = -1.0;     ///< max_ij |u_ij - u_exact(x_i, y_j)|
  double discrete_l2 = -1.0;  ///< sqrt(h_x h_y sum_ij (u_ij - u_exact)^2)
};
PetscErrorCode ComputeErrorVsExact(DM da, Vec u, ErrorVsExact* error);

/// Natural residual of the complementarity problem, recomputed from the problem data:
/// max_i |min(u_i - lower_i, F_i(u))| (free rows: |F_i(u)|) / (h_x h_y), i.e. in the
/// units of -Laplace u like RunSettings::tolerance.
PetscErrorCode ComputeNaturalResidual(DM da, Vec u, double* natural_residual);

}  // namespace ncp_petsc_bench
