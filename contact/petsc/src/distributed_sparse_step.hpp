// The sparse frictional step on MPI ranks (StepMethod::kSparse on ranks;
// docs/petsc-contact-steps.md, "The sparse step on ranks"): the step of
// CondensedGatheredStep with W = H S^-1 H' never formed. Rank 0 runs the serial sparse
// step's contact Newton (CoulombStep's matrix-free form: ncp::fc's operator problem,
// GMRES) on the gathered x_free and u^k_c; each product x = W F it asks for is one
// distributed solve with M (F scattered to the owners of the contact nodes as H' F, S^-1
// by the parallel KSP, H y gathered back), in which every rank takes part.
//
// The protocol (rank 0 drives, the others serve): while rank 0 solves the contact
// problem, the other ranks wait in a broadcast of one command; per product rank 0
// broadcasts kProduct and every rank enters the collective product; at the end rank 0
// broadcasts kDone (also when the solve failed or threw), so no rank is left waiting.
// Only rank 0 decides: no branch of the contact Newton has to come out the same on every
// rank (redundant solves would need that, and a rank that decided otherwise would hang
// the run).
#pragma once

#include <mpi.h>

#include <Eigen/Core>
#include <functional>
#include <string>

namespace contact::petsc::internal {

class DelassusProducts {
 public:
  /// Collective on every rank: W times what rank 0 placed with SetInput, leaving it for
  /// Output; false on every rank if the solve with M failed.
  using Product = std::function<bool()>;
  /// Rank 0: F (n_u entries) into the product's input; x = its output.
  using Input = std::function<void(const Eigen::VectorXd& F)>;
  using Output = std::function<void(Eigen::VectorXd* x)>;

  DelassusProducts(MPI_Comm comm, Product product, Input input, Output output);

  /// Rank 0 runs `work`, whose products with W (Apply) every rank computes; the other
  /// ranks serve them until rank 0 is done. Collective. False on every rank when a
  /// product failed (the solve with M did not converge) or `work` threw; failure() then
  /// says which, on rank 0 (never thrown: no rank may leave the collective sequence).
  bool Run(const std::function<void()>& work);
  const std::string& failure() const { return failure_; }

  /// Rank 0, inside Run's work: x = W F. After a failed product x is NaN (the Newton
  /// stops on it; Run reports the failure).
  void Apply(const Eigen::VectorXd& F, Eigen::VectorXd* x);

  /// Products computed since construction (rank 0's count, on every rank after Run).
  long products() const { return products_; }

 private:
  enum Command : int { kDone = 0, kProduct = 1 };
  MPI_Comm comm_;
  int rank_ = 0;
  Product product_;
  Input input_;
  Output output_;
  bool failed_ = false;
  std::string failure_;
  long products_ = 0;
};

}  // namespace contact::petsc::internal
