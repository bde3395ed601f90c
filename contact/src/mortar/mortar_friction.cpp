#include "mortar/mortar_friction.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "ncp/fc/error.hpp"

namespace contact::internal {

MortarFrictionSolve::MortarFrictionSolve(const SparseMatrix& S, const SparseMatrix& B,
                                         const SparseMatrix& T, const Vector& mu) {
  const Eigen::Index n = S.rows(), m = B.rows();
  if (S.cols() != n || B.cols() != n || T.rows() != m || T.cols() != n || mu.size() != m)
    throw std::invalid_argument(
        "MortarFrictionSolve: S is " + std::to_string(n) + " x " +
        std::to_string(S.cols()) + ", B " + std::to_string(m) + " x " +
        std::to_string(B.cols()) + ", T " + std::to_string(T.rows()) + " x " +
        std::to_string(T.cols()) + ", mu " + std::to_string(mu.size()));
  std::vector<Eigen::Triplet<double>> t;
  for (int pass = 0; pass < 2; ++pass) {
    const SparseMatrix& rows = pass == 0 ? B : T;
    for (int c = 0; c < rows.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(rows, c); it; ++it)
        t.emplace_back(static_cast<int>(2 * it.row() + pass), c, it.value());
  }
  H_.resize(2 * m, n);
  H_.setFromTriplets(t.begin(), t.end());
  factor_.compute(S);
  // A body held neither by Dirichlet conditions has a rigid motion: a zero pivot.
  const Vector pivots = factor_.vectorD();
  if (factor_.info() != Eigen::Success ||
      !(pivots.minCoeff() > 1e-12 * pivots.cwiseAbs().maxCoeff()))
    throw std::invalid_argument(
        "contact with friction: the matrix of the free dofs is singular - every body "
        "must be held by its Dirichlet conditions (static; the Delassus form condenses "
        "on the bodies) or have mass (dynamic)");
  G_ = factor_.solve(Eigen::MatrixXd(H_.transpose()));
  Eigen::MatrixXd W = H_ * G_;
  W = 0.5 * (W + W.transpose()).eval();
  w_max_ = std::max(W.diagonal().maxCoeff(), 0.0);
  if (!(w_max_ > 0.0)) w_max_ = 1.0;
  ncp::fc::FrictionProblem problem;
  problem.dimension = 2;
  problem.num_contacts = static_cast<int>(m);
  problem.W = (W / w_max_).sparseView(0.0, 0.0);
  problem.q = Vector::Zero(2 * m);
  problem.mu = mu;
  problem.name = "mortar contact";
  solver_ = std::make_unique<ncp::fc::Solver>(problem);
}

bool MortarFrictionSolve::Solve(const Vector& q, const Vector& gap_base,
                                const Vector& slip_base, double scale, double tolerance,
                                Outcome* out) {
  const Eigen::Index m = gap_base.size();
  if (q.size() != G_.rows() || 2 * m != H_.rows() || slip_base.size() != m ||
      !(scale > 0.0) || !(tolerance > 0.0))
    throw std::invalid_argument("MortarFrictionSolve::Solve: sizes or scales disagree");
  // Scaled unknowns: u = D u', r = F r' with F = D / w_max, so W' = W / w_max.
  const double D = scale, F = D / w_max_;
  const Vector x_free = -factor_.solve(q);
  Vector q_fc = H_ * x_free;
  for (Eigen::Index j = 0; j < m; ++j) {
    q_fc(2 * j) += gap_base(j);
    q_fc(2 * j + 1) += slip_base(j);
  }
  q_fc /= D;
  solver_->SetQ(q_fc);
  ncp::fc::Options options;
  options.linear_solver = ncp::LinearSolverType::kDenseLU;
  // ncp::fc's error is relative to 1 + ||q'||_2: every force to tolerance F, every gap
  // and slip to tolerance D.
  options.tolerance = tolerance / (1.0 + q_fc.norm());
  if (r_.size() != 2 * m) r_ = Vector::Zero(2 * m);
  solver_->Solve(options, &r_, &out->summary);
  for (Eigen::Index j = 0; j < m; ++j)
    ncp::fc::ProjectOnCone(solver_->problem().mu(j), 2, r_.data() + 2 * j);
  const Vector r = F * r_;
  out->x = x_free + G_ * r;
  out->lambda.resize(m);
  out->tau.resize(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    out->lambda(j) = r(2 * j);
    out->tau(j) = r(2 * j + 1);
  }
  return out->summary.IsSolutionUsable();
}

}  // namespace contact::internal
