// PCMG restricted to the inactive set of the reduced Newton system
// (Solver::SetMultigridGrid).
#pragma once

#include <petscdm.h>
#include <petscksp.h>

#include <algorithm>
#include <vector>

#include "huge_page_memory.hpp"
#include "log_events.hpp"
#include "petsc_support.hpp"

namespace ncp::petsc {

// PCMG for the reduced Newton system of the symmetric mode (Iteration::Symmetrize) on a
// structured grid, as a reduced-space active-set method restricts its multigrid to the
// inactive set: the hierarchy is made once by coarsening the user's grid (DMCoarsen,
// DMCreateInterpolation: P_l from level l - 1 to l), and at every Newton step the coarse
// operators are the Galerkin products of the reduced system alone,
//
//   A_{l-1} = P_l,r' A_l P_l,r = P_l' A_l,0 P_l,   P_l,r = diag(m_l) P_l,
//
// with m_l = 1 on the unknowns left in the system at level l and 0 on the eliminated
// ones, whose rows and columns in A_l are zero but for a 1 on the diagonal (A_l,0: that
// 1 removed for the product). A coarse node whose column of P_l,r is zero (no kept fine
// node near it) has a zero row and column in A_{l-1}: it gets a 1 on the diagonal, is
// decoupled, and m_{l-1} = 0 there. PCMG interpolates with P_l itself: the values it
// puts on a decoupled row are overwritten by the post-smoother (SOR solves an identity
// row exactly) and reach no other row, so the V-cycle is that of P_l,r.
class InactiveSetMultigrid {
 public:
  // The Galerkin product C = P' A P, symbolic and numeric (MAT_REUSE_MATRIX of MatPtAP
  // recomputes it for new values of A). On several ranks by hypre's RAP when PETSc has
  // hypre: PETSc's own MPIAIJ PtAP has a symbolic phase per grid and a MatGetLocalMat of
  // P in every numeric phase, and was measured slower
  // (benchmarks/results/petsc/solver/README.md); on one rank PETSc's SeqAIJ product,
  // measured faster. The options database's -mat_product_algorithm still chooses
  // (MatProductSetFromOptions).
  static Mat NewGalerkinProduct(Mat A, Mat P) {
    Mat C = nullptr;
    NCP_PETSC_CHECK(MatProductCreate(A, P, nullptr, &C));
    NCP_PETSC_CHECK(MatProductSetType(C, MATPRODUCT_PtAP));
#if defined(PETSC_HAVE_HYPRE)
    PetscMPIInt ranks = 1;
    NCP_PETSC_CHECK(
        MPI_Comm_size(PetscObjectComm(reinterpret_cast<PetscObject>(A)), &ranks));
    if (ranks > 1) NCP_PETSC_CHECK(MatProductSetAlgorithm(C, "hypre"));
#endif
    NCP_PETSC_CHECK(MatProductSetFill(C, PETSC_DEFAULT));
    NCP_PETSC_CHECK(MatProductSetFromOptions(C));
    NCP_PETSC_CHECK(MatProductSymbolic(C));
    NCP_PETSC_CHECK(MatProductNumeric(C));
    return C;
  }

  ~InactiveSetMultigrid() { Clear(); }
  DM grid() const { return grid_; }
  bool attached() const { return attached_; }

  void SetGrid(DM grid) {
    Clear();
    if (grid) NCP_PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(grid)));
    grid_ = grid;
  }

  // Levels from PCMG `pc` (its -pc_mg_levels), the hierarchy from the grid; PCMG
  // computes no Galerkin operators itself.
  void Attach(PC pc) {
    PetscInt levels = 1;
    NCP_PETSC_CHECK(PCMGGetLevels(pc, &levels));
    const auto count = static_cast<size_t>(std::max<PetscInt>(levels, 1));
    dms_.assign(count, nullptr);
    interpolation_.assign(count, nullptr);
    coarse_.assign(count, nullptr);
    decoupled_.assign(count, nullptr);
    NCP_PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(grid_)));
    dms_[count - 1] = grid_;
    const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(grid_));
    for (size_t l = count - 1; l >= 1; --l) {
      // The grid this one was refined from (DMGetCoarseDM, e.g. the previous grid of a
      // nested iteration) with its interpolation made once (GridInterpolation), else a
      // coarsening made here.
      DM refined_from = nullptr;
      NCP_PETSC_CHECK(DMGetCoarseDM(dms_[l], &refined_from));
      if (!AnyRank(comm, refined_from == nullptr)) {
        NCP_PETSC_CHECK(
            PetscObjectReference(reinterpret_cast<PetscObject>(refined_from)));
        dms_[l - 1] = refined_from;
        interpolation_[l] = GridInterpolation(refined_from, dms_[l]);
        NCP_PETSC_CHECK(
            PetscObjectReference(reinterpret_cast<PetscObject>(interpolation_[l])));
      } else {
        NCP_PETSC_CHECK(DMCoarsen(dms_[l], comm, &dms_[l - 1]));
        NCP_PETSC_CHECK(
            DMCreateInterpolation(dms_[l - 1], dms_[l], &interpolation_[l], nullptr));
      }
      NCP_PETSC_CHECK(MatCreateVecs(interpolation_[l], &decoupled_[l - 1], nullptr));
      NCP_PETSC_CHECK(
          PCMGSetInterpolation(pc, static_cast<PetscInt>(l), interpolation_[l]));
    }
    NCP_PETSC_CHECK(PCMGSetGalerkin(pc, PC_MG_GALERKIN_NONE));
    attached_ = true;
  }

  // The coarse operators for the reduced system S of this Newton step; eliminated: 1 - m
  // of the finest level (1 on the eliminated rows of S, 0 on the others).
  void Update(PC pc, Mat S, Vec eliminated) {
    LogScope scope(SolverLogEvents().mg_update);
    Mat A = S;
    Vec decoupled = eliminated;
    for (size_t l = coarse_.size() - 1; l >= 1; --l) {
      NCP_PETSC_CHECK(VecScale(decoupled, -1.0));  // A_l,0 for the product ...
      NCP_PETSC_CHECK(MatDiagonalSet(A, decoupled, ADD_VALUES));
      if (!coarse_[l - 1]) {
        coarse_[l - 1] = NewGalerkinProduct(A, interpolation_[l]);
        CreateVecsOfMatInBlocks(coarse_[l - 1]);  // PCMG's level vectors
      } else {
        NCP_PETSC_CHECK(MatPtAP(A, interpolation_[l], MAT_REUSE_MATRIX, PETSC_DEFAULT,
                                &coarse_[l - 1]));
      }
      NCP_PETSC_CHECK(VecScale(decoupled, -1.0));  // ... and A_l again
      NCP_PETSC_CHECK(MatDiagonalSet(A, decoupled, ADD_VALUES));
      Mat coarse = coarse_[l - 1];
      Vec coarse_decoupled = decoupled_[l - 1];
      NCP_PETSC_CHECK(MatGetDiagonal(coarse, coarse_decoupled));
      PetscInt local = 0;
      NCP_PETSC_CHECK(VecGetLocalSize(coarse_decoupled, &local));
      {
        // A_{l-1} = P_r' A_l P_r with A_l positive definite on the kept rows: its
        // diagonal entry j is zero exactly when column j of P_r is.
        LocalWrite d(coarse_decoupled);
        for (PetscInt j = 0; j < local; ++j)
          d[j] = PetscRealPart(d[j]) == 0.0 ? 1.0 : 0.0;
      }
      NCP_PETSC_CHECK(MatDiagonalSet(coarse, coarse_decoupled, ADD_VALUES));
      KSP smoother = nullptr;
      NCP_PETSC_CHECK(PCMGGetSmoother(pc, static_cast<PetscInt>(l - 1), &smoother));
      NCP_PETSC_CHECK(KSPSetOperators(smoother, coarse, coarse));
      A = coarse;
      decoupled = coarse_decoupled;
    }
  }

 private:
  void Clear() {
    for (std::vector<Mat>* M : {&interpolation_, &coarse_})
      for (Mat& m : *M) DestroyMat(&m);
    for (Vec& v : decoupled_)
      if (v) VecDestroy(&v);
    for (DM& dm : dms_)
      if (dm) DMDestroy(&dm);
    dms_.clear();
    interpolation_.clear();
    coarse_.clear();
    decoupled_.clear();
    if (grid_) DMDestroy(&grid_);
    grid_ = nullptr;
    attached_ = false;
  }

  DM grid_ = nullptr;
  bool attached_ = false;
  std::vector<DM> dms_;             // level l = 0 (coarsest) ... finest
  std::vector<Mat> interpolation_;  // [l]: P_l from level l - 1 to l
  std::vector<Mat> coarse_;         // [l]: A_l of the coarse levels
  std::vector<Vec> decoupled_;      // [l]: 1 - m_l of the coarse levels
};

}  // namespace ncp::petsc
