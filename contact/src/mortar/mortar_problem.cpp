#include "mortar/mortar_problem.hpp"

#include <stdexcept>
#include <vector>

namespace contact::internal {

MortarContactProblem::MortarContactProblem(const SparseMatrix& S, const SparseMatrix& B)
    : n_(static_cast<int>(S.rows())),
      m_(static_cast<int>(B.rows())),
      S_(S),
      B_(B),
      Bt_(B.transpose()) {
  if (S.cols() != S.rows() || B.cols() != S.rows())
    throw std::invalid_argument("MortarContactProblem: S is " + std::to_string(S.rows()) +
                                " x " + std::to_string(S.cols()) + ", B has " +
                                std::to_string(B.cols()) + " columns (need n x n, n)");
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < n_; ++c)
    for (SparseMatrix::InnerIterator it(S_, c); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), c, it.value());
  for (int c = 0; c < m_; ++c)
    for (SparseMatrix::InnerIterator it(Bt_, c); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), n_ + c, -it.value());
  JE_.resize(n_, n_ + m_);
  JE_.setFromTriplets(t.begin(), t.end());
  t.clear();
  for (int j = 0; j < m_; ++j) t.emplace_back(j, n_ + j, 1.0);
  JA_.resize(m_, n_ + m_);
  JA_.setFromTriplets(t.begin(), t.end());
  t.clear();
  for (int c = 0; c < n_; ++c)
    for (SparseMatrix::InnerIterator it(B_, c); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), c, it.value());
  JB_.resize(m_, n_ + m_);
  JB_.setFromTriplets(t.begin(), t.end());
  q_ = Vector::Zero(n_);
  gap_base_ = Vector::Zero(m_);
}

void MortarContactProblem::Update(const Vector& q, const Vector& gap_base, double scale) {
  if (q.size() != n_ || gap_base.size() != m_ || !(scale > 0.0))
    throw std::invalid_argument(
        "MortarContactProblem::Update: sizes " + std::to_string(q.size()) + ", " +
        std::to_string(gap_base.size()) + " (need " + std::to_string(n_) + ", " +
        std::to_string(m_) + "), scale " + std::to_string(scale) + " (need > 0)");
  q_ = q;
  gap_base_ = gap_base;
  scale_ = scale;
}

bool MortarContactProblem::Evaluate(const ncp::Vector& z, ncp::Vector* E, ncp::Vector* A,
                                    ncp::Vector* B) {
  const auto x = z.head(n_);
  const auto lambda = z.tail(m_);
  E->noalias() = S_ * x;
  *E += q_;
  E->noalias() -= Bt_ * lambda;
  *A = lambda;
  B->noalias() = B_ * x;
  *B += gap_base_;
  return true;
}

bool MortarContactProblem::Jacobian(const ncp::Vector&, ncp::SparseMatrix* JE,
                                    ncp::SparseMatrix* JA, ncp::SparseMatrix* JB) {
  *JE = JE_;
  *JA = JA_;
  *JB = JB_;
  return true;
}

bool MortarContactProblem::Scales(const ncp::Vector&, ncp::ResidualScales* scales) {
  scales->equation = Vector::Constant(n_, scale_);
  scales->a = Vector::Constant(m_, scale_);
  scales->b = Vector::Constant(m_, scale_);
  return true;
}

}  // namespace contact::internal
