// Bueler's radially symmetric obstacle problem; the math is stated in
// bueler_obstacle.hpp.
#include "bueler_obstacle.hpp"

#include <algorithm>
#include <cmath>

namespace ncp_petsc_bench {
namespace {

/// Outer radius of the radial problem (u(kOuterRadius) = 0): half the side of S.
constexpr double kOuterRadius = 2.0;

double HemisphereSlope(double r) { return -r / std::sqrt(1.0 - r * r); }

struct GridSpacing {
  double hx, hy;
  double diagonal() const { return 2.0 * (hy / hx + hx / hy); }
};

GridSpacing SpacingOf(const DMDALocalInfo& info) {
  return {(kDomainMax - kDomainMin) / (info.mx - 1),
          (kDomainMax - kDomainMin) / (info.my - 1)};
}

double NodeX(const DMDALocalInfo& info, PetscInt i) {
  return kDomainMin + i * SpacingOf(info).hx;
}
double NodeY(const DMDALocalInfo& info, PetscInt j) {
  return kDomainMin + j * SpacingOf(info).hy;
}

bool OnBoundary(const DMDALocalInfo& info, PetscInt i, PetscInt j) {
  return i == 0 || j == 0 || i == info.mx - 1 || j == info.my - 1;
}

/// Value of neighbour (i, j): its Dirichlet value on the boundary, else the unknown.
double NeighbourValue(const DMDALocalInfo& info, PetscScalar** u, PetscInt i,
                      PetscInt j) {
  return OnBoundary(info, i, j) ? ExactSolution(NodeX(info, i), NodeY(info, j)) : u[j][i];
}

}  // namespace

double FreeBoundaryRadius() {
  // g(a) = a^2 (log 2 - log a) - (1 - a^2): g(0+) = -1 < 0, g(1) = log 2 > 0, g
  // increasing.
  auto g = [](double a) {
    return a * a * (std::log(kOuterRadius) - std::log(a)) - (1.0 - a * a);
  };
  double lo = 1e-3, hi = 1.0 - 1e-12;
  for (int k = 0; k < 200 && hi - lo > 4e-16; ++k) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double Obstacle(double x, double y) {
  const double r = std::hypot(x, y);
  if (r <= kSkirtRadius) return std::sqrt(1.0 - r * r);
  return std::sqrt(1.0 - kSkirtRadius * kSkirtRadius) +
         HemisphereSlope(kSkirtRadius) * (r - kSkirtRadius);
}

double ExactSolution(double x, double y) {
  static const double a = FreeBoundaryRadius();
  static const double A = a * a / std::sqrt(1.0 - a * a);
  const double r = std::hypot(x, y);
  if (r <= a) return std::sqrt(1.0 - r * r);
  return A * std::log(kOuterRadius / r);
}

PetscErrorCode CreateGrid(MPI_Comm comm, PetscInt nodes_per_side, DM* da) {
  PetscFunctionBeginUser;
  PetscCheck(nodes_per_side >= 3, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "grid: nodes per side = %" PetscInt_FMT ", accepted >= 3", nodes_per_side);
  PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_STAR,
                         nodes_per_side, nodes_per_side, PETSC_DECIDE, PETSC_DECIDE, 1, 1,
                         nullptr, nullptr, da));
  PetscCall(DMSetUp(*da));
  PetscCall(DMDASetUniformCoordinates(*da, kDomainMin, kDomainMax, kDomainMin, kDomainMax,
                                      0.0, 0.0));
  PetscFunctionReturn(0);
}

PetscErrorCode FormResidualLocal(DMDALocalInfo* info, PetscScalar** u, PetscScalar** f,
                                 void*) {
  PetscFunctionBeginUser;
  const GridSpacing h = SpacingOf(*info);
  for (PetscInt j = info->ys; j < info->ys + info->ym; ++j) {
    for (PetscInt i = info->xs; i < info->xs + info->xm; ++i) {
      if (OnBoundary(*info, i, j)) {
        f[j][i] =
            h.diagonal() * (u[j][i] - ExactSolution(NodeX(*info, i), NodeY(*info, j)));
        continue;
      }
      f[j][i] =
          h.diagonal() * u[j][i] -
          h.hy / h.hx *
              (NeighbourValue(*info, u, i + 1, j) + NeighbourValue(*info, u, i - 1, j)) -
          h.hx / h.hy *
              (NeighbourValue(*info, u, i, j + 1) + NeighbourValue(*info, u, i, j - 1));
    }
  }
  PetscCall(PetscLogFlops(10.0 * info->xm * info->ym));
  PetscFunctionReturn(0);
}

PetscErrorCode FormJacobianLocal(DMDALocalInfo* info, PetscScalar**, Mat J, Mat P,
                                 void*) {
  PetscFunctionBeginUser;
  const GridSpacing h = SpacingOf(*info);
  for (PetscInt j = info->ys; j < info->ys + info->ym; ++j) {
    for (PetscInt i = info->xs; i < info->xs + info->xm; ++i) {
      MatStencil row{0, j, i, 0};
      MatStencil cols[5];
      PetscScalar values[5];
      PetscInt count = 0;
      cols[count] = row;
      values[count++] = h.diagonal();
      if (!OnBoundary(*info, i, j)) {
        const PetscInt di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
          if (OnBoundary(*info, i + di[k], j + dj[k]))
            continue;  // a Dirichlet value, not an unknown
          cols[count] = MatStencil{0, j + dj[k], i + di[k], 0};
          values[count++] = -(di[k] != 0 ? h.hy / h.hx : h.hx / h.hy);
        }
      }
      PetscCall(MatSetValuesStencil(P, 1, &row, count, cols, values, INSERT_VALUES));
    }
  }
  PetscCall(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
  if (J != P) {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode EvaluateResidual(DM da, Vec u, Vec f) {
  PetscFunctionBeginUser;
  DMDALocalInfo info;
  Vec u_local;
  PetscScalar **u_array, **f_array;
  PetscCall(DMDAGetLocalInfo(da, &info));
  PetscCall(DMGetLocalVector(da, &u_local));
  PetscCall(DMGlobalToLocalBegin(da, u, INSERT_VALUES, u_local));
  PetscCall(DMGlobalToLocalEnd(da, u, INSERT_VALUES, u_local));
  PetscCall(DMDAVecGetArrayRead(da, u_local, &u_array));
  PetscCall(DMDAVecGetArray(da, f, &f_array));
  PetscCall(FormResidualLocal(&info, u_array, f_array, nullptr));
  PetscCall(DMDAVecRestoreArray(da, f, &f_array));
  PetscCall(DMDAVecRestoreArrayRead(da, u_local, &u_array));
  PetscCall(DMRestoreLocalVector(da, &u_local));
  PetscFunctionReturn(0);
}

PetscErrorCode EvaluateJacobian(DM da, Vec, Mat J) {
  PetscFunctionBeginUser;
  DMDALocalInfo info;
  PetscCall(DMDAGetLocalInfo(da, &info));
  PetscCall(FormJacobianLocal(&info, nullptr, J, J, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode FormBounds(DM da, Vec lower, Vec upper) {
  PetscFunctionBeginUser;
  DMDALocalInfo info;
  PetscScalar** l;
  PetscCall(DMDAGetLocalInfo(da, &info));
  PetscCall(DMDAVecGetArray(da, lower, &l));
  for (PetscInt j = info.ys; j < info.ys + info.ym; ++j) {
    for (PetscInt i = info.xs; i < info.xs + info.xm; ++i) {
      l[j][i] = OnBoundary(info, i, j) ? PETSC_NINFINITY
                                       : Obstacle(NodeX(info, i), NodeY(info, j));
    }
  }
  PetscCall(DMDAVecRestoreArray(da, lower, &l));
  PetscCall(VecSet(upper, PETSC_INFINITY));
  PetscFunctionReturn(0);
}

PetscErrorCode ComputeBoundsOnSnesGrid(SNES snes, Vec lower, Vec upper) {
  PetscFunctionBeginUser;
  DM da;
  PetscCall(SNESGetDM(snes, &da));
  PetscCall(FormBounds(da, lower, upper));
  PetscFunctionReturn(0);
}

PetscErrorCode CellArea(DM da, double* area) {
  PetscFunctionBeginUser;
  DMDALocalInfo info;
  PetscCall(DMDAGetLocalInfo(da, &info));
  const GridSpacing h = SpacingOf(info);
  *area = h.hx * h.hy;
  PetscFunctionReturn(0);
}

PetscErrorCode ComputeErrorVsExact(DM da, Vec u, ErrorVsExact* error) {
  PetscFunctionBeginUser;
  DMDALocalInfo info;
  const PetscScalar** v;
  PetscCall(DMDAGetLocalInfo(da, &info));
  PetscCall(DMDAVecGetArrayRead(da, u, &v));
  double local[2] = {0.0, 0.0};  // max |e|, sum e^2
  for (PetscInt j = info.ys; j < info.ys + info.ym; ++j) {
    for (PetscInt i = info.xs; i < info.xs + info.xm; ++i) {
      const double e = v[j][i] - ExactSolution(NodeX(info, i), NodeY(info, j));
      local[0] = std::max(local[0], std::abs(e));
      local[1] += e * e;
    }
  }
  PetscCall(DMDAVecRestoreArrayRead(da, u, &v));
  double max_norm = 0.0, sum_squares = 0.0;
  PetscCallMPI(MPI_Allreduce(&local[0], &max_norm, 1, MPI_DOUBLE, MPI_MAX,
                             PetscObjectComm((PetscObject)da)));
  PetscCallMPI(MPI_Allreduce(&local[1], &sum_squares, 1, MPI_DOUBLE, MPI_SUM,
                             PetscObjectComm((PetscObject)da)));
  const GridSpacing h = SpacingOf(info);
  error->max_norm = max_norm;
  error->discrete_l2 = std::sqrt(h.hx * h.hy * sum_squares);
  PetscFunctionReturn(0);
}

PetscErrorCode ComputeNaturalResidual(DM da, Vec u, double* natural_residual) {
  PetscFunctionBeginUser;
  Vec f, lower, upper;
  PetscCall(VecDuplicate(u, &f));
  PetscCall(VecDuplicate(u, &lower));
  PetscCall(VecDuplicate(u, &upper));
  PetscCall(EvaluateResidual(da, u, f));
  PetscCall(FormBounds(da, lower, upper));
  const PetscScalar *uv, *fv, *lv;
  PetscInt n;
  PetscCall(VecGetLocalSize(u, &n));
  PetscCall(VecGetArrayRead(u, &uv));
  PetscCall(VecGetArrayRead(f, &fv));
  PetscCall(VecGetArrayRead(lower, &lv));
  double local = 0.0;
  for (PetscInt k = 0; k < n; ++k) {
    const double r = lv[k] <= PETSC_NINFINITY ? fv[k] : std::min(uv[k] - lv[k], fv[k]);
    local = std::isfinite(r) ? std::max(local, std::abs(r)) : INFINITY;
  }
  PetscCall(VecRestoreArrayRead(lower, &lv));
  PetscCall(VecRestoreArrayRead(f, &fv));
  PetscCall(VecRestoreArrayRead(u, &uv));
  double area = 0.0;
  PetscCall(CellArea(da, &area));
  PetscCallMPI(MPI_Allreduce(&local, natural_residual, 1, MPI_DOUBLE, MPI_MAX,
                             PetscObjectComm((PetscObject)da)));
  *natural_residual /= area;
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&lower));
  PetscCall(VecDestroy(&upper));
  PetscFunctionReturn(0);
}

}  // namespace ncp_petsc_bench
