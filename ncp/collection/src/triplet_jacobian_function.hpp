// Internal: base class for the larger problems, whose sparse Jacobians are assembled from
// (row, column, value) triplets.
#pragma once

#include <vector>

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp::collection::internal {

/// Collects the entries of one Jacobian. Add() must be called for the same (row, column)
/// positions at every x, zero values included: the sparsity pattern then never changes
/// (duplicates are summed, explicit zeros are kept).
class JacobianEntries {
 public:
  void Add(int row, int column, double value) {
    entries_.emplace_back(row, column, value);
  }
  /// Adds only if column >= 0 (column < 0 marks a fixed, eliminated variable).
  void AddIfFree(int row, int column, double value) {
    if (column >= 0) Add(row, column, value);
  }

 private:
  friend class TripletJacobianFunction;
  std::vector<Eigen::Triplet<double>> entries_;
};

/// A SquareFunction whose Jacobian is given entry by entry (see JacobianEntries).
class TripletJacobianFunction : public SquareFunction {
 public:
  explicit TripletJacobianFunction(int n) : n_(n) {}
  int NumVariables() const override { return n_; }

  bool Jacobian(const Vector& x, SparseMatrix* J) override {
    entries_.entries_.clear();
    if (!AddJacobian(x, &entries_)) return false;
    J->resize(n_, n_);
    J->setFromTriplets(entries_.entries_.begin(), entries_.entries_.end());
    return true;
  }

 protected:
  /// The entries of dF/dx at x; false = cannot evaluate at x.
  virtual bool AddJacobian(const Vector& x, JacobianEntries* J) = 0;

 private:
  int n_;
  JacobianEntries entries_;
};

}  // namespace ncp::collection::internal
