#include "distributed_sparse_step.hpp"

#include <limits>
#include <stdexcept>
#include <utility>

namespace contact::petsc::internal {

DelassusProducts::DelassusProducts(MPI_Comm comm, Product product, Input input,
                                   Output output)
    : comm_(comm),
      product_(std::move(product)),
      input_(std::move(input)),
      output_(std::move(output)) {
  MPI_Comm_rank(comm, &rank_);
}

bool DelassusProducts::Run(const std::function<void()>& work) {
  failed_ = false;
  failure_.clear();
  if (rank_ != 0) {
    for (;;) {
      int command = kDone;
      MPI_Bcast(&command, 1, MPI_INT, 0, comm_);
      if (command == kDone) break;
      if (!product_()) failed_ = true;
      ++products_;
    }
  } else {
    try {
      work();
    } catch (const std::exception& e) {
      failed_ = true;
      failure_ = e.what();
    }
    int command = kDone;
    MPI_Bcast(&command, 1, MPI_INT, 0, comm_);
    if (failed_ && failure_.empty())
      failure_ = "a solve with the mass matrix in a product with W did not converge";
  }
  // (Every rank saw the same outcome of each collective product; shared for safety.)
  int failed = failed_ ? 1 : 0;
  MPI_Bcast(&failed, 1, MPI_INT, 0, comm_);
  return failed == 0;
}

void DelassusProducts::Apply(const Eigen::VectorXd& F, Eigen::VectorXd* x) {
  int command = kProduct;
  MPI_Bcast(&command, 1, MPI_INT, 0, comm_);
  input_(F);
  ++products_;
  if (!product_()) {
    failed_ = true;
    x->setConstant(F.size(), std::numeric_limits<double>::quiet_NaN());
    return;
  }
  output_(x);
}

}  // namespace contact::petsc::internal
