// ncp::petsc::Solver's construction and accessors (the solve itself: iteration.cpp).

#include "ncp/petsc/solver.hpp"

#include <memory>
#include <stdexcept>
#include <string>

#include "solver_impl.hpp"

namespace ncp::petsc {

// ---------------------------------------------------------------------------------------
// The public API.

BoxMcp BoxMcp::FromFunctionPointers(ResidualFunctionPointer residual,
                                    JacobianFunctionPointer jacobian, void* context,
                                    Mat jacobian_matrix, Vec lower, Vec upper) {
  BoxMcp p;
  if (residual)
    p.residual = [residual, context](Vec x, Vec f) { return residual(x, f, context); };
  if (jacobian)
    p.jacobian = [jacobian, context](Vec x, Mat J) { return jacobian(x, J, context); };
  p.jacobian_matrix = jacobian_matrix;
  p.lower = lower;
  p.upper = upper;
  return p;
}

namespace {

// A KSP with the options prefix `prefix` and the default of both linear systems: one
// direct solve by MUMPS' LU (Amestoy et al. 2001), exact up to round-off like the serial
// backends, so that the iterates are the serial solver's.
KSP DirectKsp(MPI_Comm comm, const std::string& prefix) {
  KSP ksp = nullptr;
  NCP_PETSC_CHECK(KSPCreate(comm, &ksp));
  NCP_PETSC_CHECK(KSPSetOptionsPrefix(ksp, prefix.c_str()));
  NCP_PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  NCP_PETSC_CHECK(PCSetType(pc, PCLU));
  NCP_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  return ksp;
}

}  // namespace

Solver::Solver(MPI_Comm comm, const Options& options, const std::string& options_prefix)
    : impl_(new Impl) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    throw std::invalid_argument(
        "ncp::petsc::Solver: PETSc is not initialized; call PetscInitialize "
        "before constructing the solver (and PetscFinalize after destroying it)");
  std::string error;
  if (!options.IsValid(&error))
    throw std::invalid_argument("ncp::petsc::Solver: " + error);
  if (options.linear_solver != LinearSolverType::kAuto)
    throw std::invalid_argument(
        std::string("ncp::petsc::Solver: Options::linear_solver = ") +
        ToString(options.linear_solver) +
        " names a serial backend; over PETSc the Newton systems are solved by "
        "the KSP (leave kAuto, choose with -" +
        options_prefix + "ksp_type / -" + options_prefix + "pc_type)");
  impl_->comm = comm;
  impl_->options = options;
  impl_->prefix = options_prefix;
  impl_->ksp = DirectKsp(comm, options_prefix);
  impl_->lm_ksp = DirectKsp(comm, options_prefix + "lm_");
  impl_->minimum_norm = std::make_unique<MinimumNormSolver>(options_prefix + "mn_");
  int size = 0;
  MPI_Comm_size(comm, &size);
  impl_->report.ranks = size;
}

Solver::~Solver() = default;

void Solver::SetMultigridGrid(DM grid) { impl_->multigrid.SetGrid(grid); }

const Options& Solver::options() const { return impl_->options; }
KSP Solver::ksp() const { return impl_->ksp; }
const KspReport& Solver::ksp_report() const { return impl_->report; }

}  // namespace ncp::petsc
