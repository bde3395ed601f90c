#include "critical_time_step.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "parallel.hpp"

namespace contact {
namespace internal {

double LanczosStartEntry(long long i) {
  return ((i / 2) % 2 == 0 ? 1.0 : -1.0) * (1.0 + 1e-3 * static_cast<double>(i % 7));
}

// Lanczos on the pencil (K, M), i.e. on M^-1 K, which is self-adjoint in the M inner
// product: with M-orthonormal v_1, v_2, ...
//   w = M^-1 K v_j - alpha_j v_j - beta_{j-1} v_{j-1},  alpha_j = v_j' K v_j,
//   beta_j = sqrt(w' M w),  v_{j+1} = w / beta_j,
// the largest eigenvalue theta of the tridiagonal T_j = tridiag(beta, alpha, beta) rises
// to lambda_max = omega_max^2 from below (in far fewer steps than power iteration). M v
// is carried along (M w = K v_j - alpha_j M v_j - beta_{j-1} M v_{j-1}), so one step
// costs one product with K and one solve with M. No reorthogonalization: the loss of
// orthogonality only adds copies of converged Ritz values, not wrong extreme ones. The
// start vector alternates in sign node by node so it is rich in high-frequency modes.
CriticalTimeStep Lanczos(const LanczosOperators& op, Eigen::Index local_size,
                         double relative_tolerance, int max_iterations) {
  CriticalTimeStep out;
  const long long n = op.global_size;
  if (n == 0) return out;
  const Eigen::Index m = local_size;
  Eigen::VectorXd v(m), Mv(m), v_old = Eigen::VectorXd::Zero(m),
                               Mv_old = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd Kv(m), w(m);
  for (Eigen::Index i = 0; i < m; ++i) v(i) = LanczosStartEntry(op.global_index(i));
  op.multiply_M(v, &Mv);
  const double norm = std::sqrt(op.dot(v, Mv));
  v /= norm;
  Mv /= norm;
  std::vector<double> alpha, beta;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal;
  double theta = 0.0, beta_old = 0.0;
  int stable_count = 0;
  const int limit = static_cast<int>(std::min<long long>(max_iterations, n));
  for (int j = 1; j <= limit; ++j) {
    op.multiply_K(v, &Kv);
    const double a = op.dot(v, Kv);
    // M w = K v - a M v - beta_old M v_old, then w = M^-1 (M w).
    Kv -= a * Mv + beta_old * Mv_old;
    op.solve_M(Kv, &w);
    const double b = std::sqrt(std::max(op.dot(w, Kv), 0.0));
    alpha.push_back(a);
    out.iterations = j;
    // Invariant subspace (b ~ 0): T_j holds exact eigenvalues of the pencil.
    const bool exhausted = !(b > 1e-14 * std::max(std::abs(a), 1e-300)) || j == n;
    // theta of T_j every third step (its eigenvalues cost O(j^2)): converged when it
    // moved by at most relative_tolerance over two such checks in a row.
    if (exhausted || j % 3 == 0 || j == limit) {
      Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(alpha.data(), j);
      Eigen::VectorXd e = Eigen::Map<const Eigen::VectorXd>(beta.data(), j - 1);
      tridiagonal.computeFromTridiagonal(d, e, Eigen::EigenvaluesOnly);
      const double next = std::max(tridiagonal.eigenvalues().maxCoeff(), 0.0);
      if (exhausted || std::abs(next - theta) <= relative_tolerance * next) {
        if (exhausted || ++stable_count >= 2) {
          theta = next;
          out.converged = true;
          break;
        }
      } else {
        stable_count = 0;
      }
      theta = next;
    }
    beta.push_back(b);
    beta_old = b;
    v_old.swap(v);
    Mv_old.swap(Mv);
    v = w / b;
    Mv = Kv / b;
  }
  out.omega_max = std::sqrt(theta);
  out.dt_crit =
      theta > 0.0 ? 2.0 / out.omega_max : std::numeric_limits<double>::infinity();
  return out;
}

CriticalTimeStep Lanczos(const Eigen::SparseMatrix<double>& K,
                         const Eigen::SparseMatrix<double>& M, MassInverse* mass,
                         double relative_tolerance, int max_iterations) {
  LanczosOperators op;
  op.global_size = K.rows();
  op.global_index = [](Eigen::Index i) { return static_cast<long long>(i); };
  op.multiply_K = [&K](const Eigen::VectorXd& x, Eigen::VectorXd* y) {
    SymmetricMultiply(K, x, y);
  };
  op.multiply_M = [&M](const Eigen::VectorXd& x, Eigen::VectorXd* y) {
    y->noalias() = M * x;
  };
  op.solve_M = [mass](const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    mass->Solve(b, x);
  };
  op.dot = [](const Eigen::VectorXd& x, const Eigen::VectorXd& y) { return x.dot(y); };
  return Lanczos(op, K.rows(), relative_tolerance, max_iterations);
}

}  // namespace internal

CriticalTimeStep EstimateCriticalTimeStep(const Eigen::SparseMatrix<double>& K,
                                          const Eigen::SparseMatrix<double>& M,
                                          double relative_tolerance, int max_iterations) {
  if (K.rows() != M.rows() || K.cols() != M.cols() || K.rows() != K.cols())
    throw std::invalid_argument(
        "EstimateCriticalTimeStep: K and M must be square of equal size");
  internal::MassInverse mass(M, "EstimateCriticalTimeStep: ");
  return internal::Lanczos(K, M, &mass, relative_tolerance, max_iterations);
}

}  // namespace contact
