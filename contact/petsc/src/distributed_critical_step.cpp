#include "distributed_critical_step.hpp"

#include <stdexcept>
#include <vector>

#include "contact/dynamics.hpp"
#include "critical_time_step.hpp"
#include "petsc_check.hpp"

namespace contact::petsc::internal {

double DeterministicDot(MPI_Comm comm, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& y) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const double local = x.dot(y);
  std::vector<double> parts(static_cast<size_t>(size));
  MPI_Allgather(&local, 1, MPI_DOUBLE, parts.data(), 1, MPI_DOUBLE, comm);
  double sum = 0.0;
  for (const double part : parts) sum += part;
  return sum;
}

CriticalTimeStep DistributedCriticalTimeStep(const DistributedBody& body,
                                             const MassSolve& solve_consistent) {
  const Mat K = body.stiffness();
  const Vec m = body.lumped_mass();
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(m));
  PetscInt local_size = 0, global_size = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(m, &local_size));
  CONTACT_PETSC_CHECK(VecGetSize(m, &global_size));
  // The owned free dofs' serial indices and lumped masses [kg].
  std::vector<long long> serial_index(static_cast<size_t>(local_size), -1);
  for (int i = 0; i < body.NumLocalVertices(); ++i)
    for (int a = 0; a < body.dim(); ++a)
      if (body.OwnedIndex(i, a) >= 0)
        serial_index[static_cast<size_t>(body.OwnedIndex(i, a))] =
            static_cast<long long>(body.Data(i)[a]);
  Eigen::VectorXd mass(local_size);
  const PetscScalar* values = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(m, &values));
  for (PetscInt k = 0; k < local_size; ++k) mass(k) = PetscRealPart(values[k]);
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(m, &values));
  // The products and solves on Eigen vectors: two Vecs of the DM's layout lent their
  // memory.
  Vec x = nullptr, y = nullptr;
  CONTACT_PETSC_CHECK(DMGetGlobalVector(body.dm(), &x));
  CONTACT_PETSC_CHECK(DMGetGlobalVector(body.dm(), &y));
  const auto apply = [&](const std::function<void(Vec, Vec)>& operation,
                         const Eigen::VectorXd& in, Eigen::VectorXd* out) {
    out->resize(in.size());
    CONTACT_PETSC_CHECK(VecPlaceArray(x, const_cast<PetscScalar*>(in.data())));
    CONTACT_PETSC_CHECK(VecPlaceArray(y, out->data()));
    try {
      operation(x, y);
    } catch (...) {
      VecResetArray(y);
      VecResetArray(x);
      throw;
    }
    CONTACT_PETSC_CHECK(VecResetArray(y));
    CONTACT_PETSC_CHECK(VecResetArray(x));
  };
  const auto multiply = [](Mat A) {
    return [A](Vec in, Vec out) { CONTACT_PETSC_CHECK(MatMult(A, in, out)); };
  };

  ::contact::internal::LanczosOperators op;
  op.global_size = global_size;
  op.global_index = [&serial_index](Eigen::Index k) {
    return serial_index[static_cast<size_t>(k)];
  };
  op.multiply_K = [&](const Eigen::VectorXd& in, Eigen::VectorXd* out) {
    apply(multiply(K), in, out);
  };
  if (solve_consistent) {
    const Mat M = body.mass_matrix();
    if (!M)
      throw std::logic_error(
          "DistributedCriticalTimeStep: a consistent mass needs the body's mass matrix");
    op.multiply_M = [&, M](const Eigen::VectorXd& in, Eigen::VectorXd* out) {
      apply(multiply(M), in, out);
    };
    op.solve_M = [&](const Eigen::VectorXd& b, Eigen::VectorXd* out) {
      apply(solve_consistent, b, out);
    };
  } else {
    op.multiply_M = [&mass](const Eigen::VectorXd& in, Eigen::VectorXd* out) {
      *out = in.cwiseProduct(mass);
    };
    op.solve_M = [&mass](const Eigen::VectorXd& b, Eigen::VectorXd* out) {
      *out = b.cwiseQuotient(mass);  // (MassInverse::Solve of a diagonal M)
    };
  }
  op.dot = [comm](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return DeterministicDot(comm, a, b);
  };
  CriticalTimeStep crit;
  try {
    crit = ::contact::internal::Lanczos(op, local_size, kCriticalStepTolerance,
                                        kCriticalStepMaxIterations);
  } catch (...) {
    DMRestoreGlobalVector(body.dm(), &y);
    DMRestoreGlobalVector(body.dm(), &x);
    throw;
  }
  CONTACT_PETSC_CHECK(DMRestoreGlobalVector(body.dm(), &y));
  CONTACT_PETSC_CHECK(DMRestoreGlobalVector(body.dm(), &x));
  return crit;
}

}  // namespace contact::petsc::internal
