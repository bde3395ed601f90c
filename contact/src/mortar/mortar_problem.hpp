// The mixed complementarity problem of one mortar contact solve (bodies_contact.hpp):
//     E = S x + q - B' lambda = 0,     0 <= lambda  perp  g_base + B x >= 0,
// unknowns z = (x, lambda), n equations, m pairs (lambda_j, gap_j). Its Jacobian is
// constant: JE = [S, -B'], JA = [0, I], JB = [B, 0].
#pragma once

#include "contact/types.hpp"
#include "ncp/problem.hpp"

namespace contact::internal {

class MortarContactProblem final : public ncp::MixedProblem {
 public:
  /// S: n x n symmetric positive definite; B: m x n.
  MortarContactProblem(const SparseMatrix& S, const SparseMatrix& B);

  /// The data of one solve: q (size n), g_base (size m) and the displacement scale
  /// [units of x] the rows are solved relative to (> 0).
  void Update(const Vector& q, const Vector& gap_base, double scale);

  int NumVariables() const override { return n_ + m_; }
  int NumEquations() const override { return n_; }
  bool Evaluate(const ncp::Vector& z, ncp::Vector* E, ncp::Vector* A,
                ncp::Vector* B) override;
  bool Jacobian(const ncp::Vector& z, ncp::SparseMatrix* JE, ncp::SparseMatrix* JA,
                ncp::SparseMatrix* JB) override;
  /// Every row relative to the displacement scale of Update().
  bool Scales(const ncp::Vector& z0, ncp::ResidualScales* scales) override;

 private:
  int n_, m_;
  SparseMatrix S_, B_, Bt_;
  SparseMatrix JE_, JA_, JB_;
  Vector q_, gap_base_;
  double scale_ = 1.0;
};

}  // namespace contact::internal
