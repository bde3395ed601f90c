// Placeholder while the implementation lands (the API of ncp/petsc/solver.hpp is fixed).
#include "ncp/petsc/solver.hpp"

#include <stdexcept>

namespace ncp::petsc {

struct Solver::Impl {
  Options options;
  KspReport report;
  KSP ksp = nullptr;
};

BoxMcp BoxMcp::FromFunctionPointers(ResidualFunctionPointer residual, JacobianFunctionPointer jacobian,
                                    void* context, Mat jacobian_matrix, Vec lower, Vec upper) {
  BoxMcp p;
  p.residual = [residual, context](Vec x, Vec f) { return residual(x, f, context); };
  p.jacobian = [jacobian, context](Vec x, Mat J) { return jacobian(x, J, context); };
  p.jacobian_matrix = jacobian_matrix;
  p.lower = lower;
  p.upper = upper;
  return p;
}

Solver::Solver(MPI_Comm, const Options& options, const std::string&) : impl_(new Impl) {
  impl_->options = options;
}
Solver::~Solver() = default;
const Options& Solver::options() const { return impl_->options; }
KSP Solver::ksp() const { return impl_->ksp; }
const KspReport& Solver::ksp_report() const { return impl_->report; }
void Solver::Solve(const BoxMcp&, Vec, Summary*) {
  throw std::logic_error("ncp::petsc::Solver::Solve: not implemented yet");
}

}  // namespace ncp::petsc
