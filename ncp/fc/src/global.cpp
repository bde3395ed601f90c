// The global form M v = q + H r, u = H' v + b reduced to the local Delassus form
// (global.hpp). Sign conventions as Siconos' GlobalFrictionContactProblem
// (globalFrictionContact_computeGlobalVelocity: v = M^-1 (q + H r)).

#include "ncp/fc/global.hpp"

#include <Eigen/SparseLU>
#include <cmath>
#include <stdexcept>

#include "ncp/fc/error.hpp"

namespace ncp::fc {

namespace {

void Require(bool ok, const std::string& what, Eigen::Index expected, Eigen::Index got) {
  if (!ok)
    throw std::invalid_argument("GlobalFrictionProblem: " + what + " must be " +
                                std::to_string(expected) + ", got " +
                                std::to_string(got));
}

bool Finite(const SparseMatrix& A) {
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    if (!std::isfinite(A.valuePtr()[k])) return false;
  return true;
}

/// Sparse LU of M, checked (a singular M has no Delassus form).
class MassFactor {
 public:
  explicit MassFactor(const GlobalFrictionProblem& p) {
    SparseMatrix M = p.M;
    M.makeCompressed();
    lu_.compute(M);
    if (lu_.info() != Eigen::Success)
      throw std::runtime_error(
          "'" + p.name + "': the matrix M (" + std::to_string(M.rows()) + " x " +
          std::to_string(M.cols()) + ") is singular: no Delassus form W = H' M^-1 H (" +
          lu_.lastErrorMessage() + ")");
  }
  template <class Rhs>
  auto Solve(const Rhs& rhs) const {
    return lu_.solve(rhs);
  }

 private:
  Eigen::SparseLU<SparseMatrix> lu_;
};

}  // namespace

void GlobalFrictionProblem::Validate() const {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument("GlobalFrictionProblem: dimension must be 2 or 3, got " +
                                std::to_string(dimension));
  const Eigen::Index n = M.rows(), m = size();
  Require(M.cols() == n, "M's columns (square M)", n, M.cols());
  Require(H.rows() == n, "H's rows (M's size)", n, H.rows());
  Require(H.cols() == m, "H's columns (dimension x contacts)", m, H.cols());
  Require(q.size() == n, "the size of q", n, q.size());
  Require(b.size() == m, "the size of b", m, b.size());
  Require(mu.size() == num_contacts, "the size of mu", num_contacts, mu.size());
  if (!Finite(M) || !Finite(H) || !q.allFinite() || !b.allFinite() || !mu.allFinite())
    throw std::invalid_argument(
        "GlobalFrictionProblem: M, H, q, b and mu must be finite");
  for (Eigen::Index a = 0; a < mu.size(); ++a)
    if (mu[a] < 0.0)
      throw std::invalid_argument("GlobalFrictionProblem: mu[" + std::to_string(a) +
                                  "] = " + std::to_string(mu[a]) + " < 0");
}

FrictionProblem ReduceToLocal(const GlobalFrictionProblem& g) {
  g.Validate();
  const MassFactor factor(g);
  const Eigen::MatrixXd MinvH = factor.Solve(Eigen::MatrixXd(g.H));
  const Vector Minvq = factor.Solve(g.q);
  FrictionProblem p;
  p.dimension = g.dimension;
  p.num_contacts = g.num_contacts;
  p.W = (Eigen::MatrixXd(g.H.transpose()) * MinvH).sparseView();
  p.q = g.H.transpose() * Minvq + g.b;
  p.mu = g.mu;
  p.name = g.name;
  p.Validate();
  return p;
}

Vector GlobalVelocity(const GlobalFrictionProblem& g, const Vector& r) {
  g.Validate();
  if (r.size() != g.size())
    throw std::invalid_argument("GlobalVelocity: r has " + std::to_string(r.size()) +
                                " entries, expected " + std::to_string(g.size()));
  const MassFactor factor(g);
  return factor.Solve(Vector(g.q + g.H * r));
}

GlobalResidual ComputeGlobalResidual(const GlobalFrictionProblem& g, const Vector& v,
                                     const Vector& r) {
  g.Validate();
  if (v.size() != g.num_dofs() || r.size() != g.size())
    throw std::invalid_argument(
        "ComputeGlobalResidual: v has " + std::to_string(v.size()) +
        " entries (expected " + std::to_string(g.num_dofs()) + "), r " +
        std::to_string(r.size()) + " (expected " + std::to_string(g.size()) + ")");
  GlobalResidual out;
  out.motion = (g.M * v - g.q - g.H * r).norm() / (1.0 + g.q.norm());
  const Vector u = g.H.transpose() * v + g.b;
  out.contact = NaturalMapResidual(g.dimension, g.mu, r, u) / (1.0 + g.b.norm());
  return out;
}

}  // namespace ncp::fc
