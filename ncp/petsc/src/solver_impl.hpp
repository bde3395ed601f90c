// ncp::petsc::Solver's state kept between solves (private to ncp/petsc/src).
#pragma once

#include <petscksp.h>

#include <memory>
#include <string>
#include <vector>

#include "absolute_product.hpp"
#include "huge_page_memory.hpp"
#include "inactive_set_multigrid.hpp"
#include "log_events.hpp"
#include "mixed_layout.hpp"
#include "outer_residual_test.hpp"
#include "petsc_support.hpp"
#include "rank_revealing.hpp"

namespace ncp::petsc {

// solver's symbolic factorization is reused while F' keeps its pattern).

struct Solver::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  Options options;
  std::string prefix;
  KSP ksp = nullptr;
  bool ksp_configured = false;
  KspReport report;
  // The KSP's operator on the pattern of G (plus its diagonal; G = F' without slacks),
  // built for the user's matrix `source` in the nonzero state `source_state`: J of the
  // mixed_layout.hpp, or with symmetric_newton the reduced symmetric system
  // (Iteration::Symmetrize: rows with c_F != 0 divided by c_F, the others eliminated;
  // KspReport::symmetric_newton). Products with J itself (gradient, backward error) are
  // formed from G and c_F, c_I (Iteration::MultNewton), so the symmetric mode keeps a
  // second matrix only for the LM direction (lm_jacobian).
  Mat newton = nullptr;
  Mat source = nullptr;
  PetscObjectState source_state = -1;
  bool same_pattern = true;    // the operator's pattern is F''s (no diagonal entry added)
  AbsoluteProduct abs_source;  // |G| v (round-off floor, backward error)
  bool symmetric_newton = false;
  // With two-sided bounds: G of mixed_layout.hpp for the layout `layout_rows`.
  SlackMatrix slack;
  LocalArray<Row> layout_rows;
  // The Levenberg-Marquardt system J'J + mu I (Options::regularized_direction and the
  // hybrid's "+lm" strategies) and its own KSP, options prefix <prefix>lm_.
  // With symmetric_newton J is not `newton`: lm_jacobian holds it, built on demand.
  KSP lm_ksp = nullptr;
  Mat normal = nullptr, lm_jacobian = nullptr;
  // PCMG restricted to the inactive set (Solver::SetMultigridGrid), or no grid.
  InactiveSetMultigrid multigrid;
  // The Newton KSP's test tied to the outer stopping test (OuterResidualTest).
  OuterResidualTest outer_test;
  // MUMPS' ICNTL(14) after a factorization ran out of workspace (KspSolve), 0: default.
  int newton_workspace_percent = 0, lm_workspace_percent = 0;
  // Options::scale_newton_system: the scales of the last Newton matrix the LU failed on.
  DistributedEquilibration equilibration;
  // Options::minimum_norm_step: MUMPS with null-pivot detection, options <prefix>mn_.
  std::unique_ptr<MinimumNormSolver> minimum_norm;

  ~Impl() {
    DestroyMat(&newton);
    DestroyMat(&normal);
    DestroyMat(&lm_jacobian);
    if (ksp) KSPDestroy(&ksp);
    if (lm_ksp) KSPDestroy(&lm_ksp);
  }

  // N = J'J + mu I for the J of the current iterate (the matrix J), on lm_ksp; the
  // product's structure is kept while J's is.
  void PrepareNormalMatrix(Mat J, double mu) {
    NCP_PETSC_CHECK(MatTransposeMatMult(
        J, J, normal ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, PETSC_DEFAULT, &normal));
    NCP_PETSC_CHECK(MatShift(normal, mu));
    NCP_PETSC_CHECK(KSPSetOperators(lm_ksp, normal, normal));
  }

  // The matrix G of mixed_layout.hpp: F' itself without slacks.
  Mat SourceMatrix(Mat F) const { return slack.matrix() ? slack.matrix() : F; }

  // J's structure for the matrix F' and the layout (again when F' is another matrix or
  // changed pattern, or the bounds another layout). Returns true when J was (re)built.
  bool PrepareNewtonMatrix(Mat F, const MixedLayout& layout) {
    LogScope scope(SolverLogEvents().newton_mat);
    PetscObjectState state = 0;
    NCP_PETSC_CHECK(MatGetNonzeroState(F, &state));
    const bool same_layout = !AnyRank(comm, layout.rows != layout_rows);
    if (newton && source == F && state == source_state && same_layout) return false;
    DestroyMat(&newton);
    DestroyMat(&normal);
    DestroyMat(&lm_jacobian);
    layout_rows = layout.rows;
    if (layout.total_slacks > 0)
      slack.Build(comm, F, layout);
    else
      slack.Clear();
    // Its arrays in a huge-page-advised block (huge_page_memory.hpp).
    newton = DuplicateAijInBlock(SourceMatrix(F));
    if (!newton) NCP_PETSC_CHECK(MatDuplicate(SourceMatrix(F), MAT_COPY_VALUES, &newton));
    CreateVecsOfMatInBlocks(newton);  // the KSP's and PCMG's vectors on it
    abs_source.Prepare(SourceMatrix(F));
    PetscBool missing = PETSC_FALSE;
    PetscInt row = 0;
    NCP_PETSC_CHECK(MatMissingDiagonal(newton, &missing, &row));
    same_pattern = !AnyRank(comm, missing == PETSC_TRUE);
    if (!same_pattern) {  // c_I needs every diagonal entry: add the missing ones as zeros
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
      Vec zero = nullptr;
      NCP_PETSC_CHECK(MatCreateVecs(newton, &zero, nullptr));
      NCP_PETSC_CHECK(VecSet(zero, 0.0));
      NCP_PETSC_CHECK(MatDiagonalSet(newton, zero, ADD_VALUES));
      VecDestroy(&zero);
    }
    source = F;
    source_state = state;
    if (symmetric_newton) {  // MatZeroRowsColumns keeps the pattern for the next MatCopy
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    }
    NCP_PETSC_CHECK(KSPSetOperators(ksp, newton, newton));
    return true;
  }

  // Once, at the first solve: the KSP from the options database, and whether the Newton
  // systems are symmetrized: -<prefix>symmetric_newton <bool>, by default on for the KSPs
  // and PCs that need a symmetric operator (CG family, MINRES, Cholesky, ICC).
  void Configure() {
    if (ksp_configured) return;
    NCP_PETSC_CHECK(KSPSetFromOptions(ksp));
    NCP_PETSC_CHECK(KSPSetFromOptions(lm_ksp));
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    PetscBool symmetric_ksp = PETSC_FALSE, symmetric_pc = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(
        reinterpret_cast<PetscObject>(ksp), &symmetric_ksp, KSPCG, KSPPIPECG, KSPGROPPCG,
        KSPCR, KSPPIPECR, KSPMINRES, KSPSYMMLQ, ""));
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc),
                                              &symmetric_pc, PCCHOLESKY, PCICC, ""));
    PetscBool flag = symmetric_ksp || symmetric_pc ? PETSC_TRUE : PETSC_FALSE,
              set = PETSC_FALSE;
    NCP_PETSC_CHECK(
        PetscOptionsGetBool(nullptr, prefix.c_str(), "-symmetric_newton", &flag, &set));
    symmetric_newton = flag == PETSC_TRUE;
    report.symmetric_newton = symmetric_newton;
    InstallOuterResidualTest();
    ksp_configured = true;
  }

  // -<prefix>newton_residual_fraction f in [0, 1] (default kDefaultResidualFraction for
  // the min function): the Newton KSP runs until its residual passes f times the outer
  // stopping test (OuterResidualTest); 0 keeps the KSP's own test alone.
  void InstallOuterResidualTest() {
    PetscReal fraction = kDefaultResidualFraction;
    PetscBool set = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscOptionsGetReal(nullptr, prefix.c_str(),
                                        "-newton_residual_fraction", &fraction, &set));
    if (!(fraction >= 0.0 && fraction <= 1.0))
      throw std::invalid_argument(
          "ncp::petsc::Solver: -" + prefix + "newton_residual_fraction = " +
          FormatNumber("%g", fraction) + ": accepted a number in [0, 1] (0: off)");
    outer_test.Install(ksp, fraction, set == PETSC_TRUE);
  }

  // KspReport's names of the KSP, PC and factorization package in use.
  void DescribeKsp() {
    KSPType ksp_type = nullptr;
    PCType pc_type = nullptr;
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetType(ksp, &ksp_type));
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    NCP_PETSC_CHECK(PCGetType(pc, &pc_type));
    report.ksp_type = ksp_type ? ksp_type : "";
    report.pc_type = pc_type ? pc_type : "";
    PetscBool factor = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factor,
                                              PCLU, PCCHOLESKY, PCILU, PCICC, ""));
    MatSolverType solver_type = nullptr;
    if (factor) NCP_PETSC_CHECK(PCFactorGetMatSolverType(pc, &solver_type));
    report.factor_solver_type = solver_type ? solver_type : "";
  }
};

/// One solve of Algorithm 1 on the mixed form `layout` from x (iteration.cpp): x holds
/// the x part of the last iterate afterwards.
void RunIteration(Solver::Impl& impl, const BoxMcp& problem, Vec x, Summary* summary,
                  const MixedLayout& layout);

}  // namespace ncp::petsc
