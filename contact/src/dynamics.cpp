#include "contact/dynamics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include "contact/convex_qp.hpp"
#include "contact/static_contact.hpp"
#include "cholmod_factor.hpp"
#include "parallel.hpp"
#include "text_format.hpp"

namespace contact {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

bool IsDiagonal(const Eigen::SparseMatrix<double>& A) {
  for (int col = 0; col < A.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it)
      if (it.row() != it.col() && it.value() != 0.0) return false;
  return true;
}

double MaxAbsEntry(const Eigen::SparseMatrix<double>& A) {
  double m = 0.0;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) m = std::max(m, std::abs(A.valuePtr()[k]));
  return m;
}

ncp::NcpFunction FunctionOf(StepSolver s) {
  switch (s) {
    case StepSolver::kMin: return ncp::NcpFunction::kMin;
    case StepSolver::kPenalizedFischerBurmeister: return ncp::NcpFunction::kPenalizedFischerBurmeister;
    default: return ncp::NcpFunction::kFischerBurmeister;
  }
}

// M^-1: elementwise for a diagonal (lumped) mass, else one CHOLMOD factor - computed once
// per run and shared by the critical step, the prescribed start and the condensed step.
class MassInverse {
 public:
  /// Throws std::invalid_argument starting with `who` if M is not positive definite.
  MassInverse(const Eigen::SparseMatrix<double>& M, const std::string& who) : diagonal_(M.diagonal()) {
    if (IsDiagonal(M)) {
      if (!(diagonal_.size() == 0 || diagonal_.minCoeff() > 0.0))
        throw std::invalid_argument(who + "the mass matrix is not positive definite");
      return;
    }
    factor_ = std::make_unique<internal::CholmodFactor>(M);
    if (!factor_->ok())
      throw std::invalid_argument(who + "the mass matrix is not positive definite (Cholesky failed)");
  }
  /// x = M^-1 b (no allocation once x is sized).
  void Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    if (factor_) factor_->Solve(b, x);
    else *x = b.cwiseQuotient(diagonal_);
  }
  /// X = M^-1 B.
  void Solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) {
    if (factor_) factor_->Solve(B, X);
    else *X = diagonal_.cwiseInverse().asDiagonal() * B;
  }

 private:
  Eigen::VectorXd diagonal_;
  std::unique_ptr<internal::CholmodFactor> factor_;
};

// Lanczos on the pencil (K, M), i.e. on M^-1 K, which is self-adjoint in the M inner
// product: with M-orthonormal v_1, v_2, ...
//   w = M^-1 K v_j - alpha_j v_j - beta_{j-1} v_{j-1},  alpha_j = v_j' K v_j,
//   beta_j = sqrt(w' M w),  v_{j+1} = w / beta_j,
// the largest eigenvalue theta of the tridiagonal T_j = tridiag(beta, alpha, beta) rises
// to lambda_max = omega_max^2 from below (in far fewer steps than power iteration). M v is
// carried along (M w = K v_j - alpha_j M v_j - beta_{j-1} M v_{j-1}), so one step costs one
// product with K and one solve with M. No reorthogonalization: the loss of orthogonality
// only adds copies of converged Ritz values, not wrong extreme ones. The start vector
// alternates in sign node by node so it is rich in high-frequency modes.
CriticalTimeStep Lanczos(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                         MassInverse* mass, double relative_tolerance, int max_iterations) {
  CriticalTimeStep out;
  const Eigen::Index n = K.rows();
  if (n == 0) return out;
  Eigen::VectorXd v(n), Mv(n), v_old = Eigen::VectorXd::Zero(n), Mv_old = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd Kv(n), w(n);
  for (Eigen::Index i = 0; i < n; ++i)
    v(i) = ((i / 2) % 2 == 0 ? 1.0 : -1.0) * (1.0 + 1e-3 * static_cast<double>(i % 7));
  Mv.noalias() = M * v;
  const double norm = std::sqrt(v.dot(Mv));
  v /= norm;
  Mv /= norm;
  std::vector<double> alpha, beta;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal;
  double theta = 0.0, beta_old = 0.0;
  int stable_count = 0;
  const int limit = static_cast<int>(std::min<Eigen::Index>(max_iterations, n));
  for (int j = 1; j <= limit; ++j) {
    internal::SymmetricMultiply(K, v, &Kv);
    const double a = v.dot(Kv);
    // M w = K v - a M v - beta_old M v_old, then w = M^-1 (M w).
    Kv -= a * Mv + beta_old * Mv_old;
    mass->Solve(Kv, &w);
    const double b = std::sqrt(std::max(w.dot(Kv), 0.0));
    alpha.push_back(a);
    out.iterations = j;
    // Invariant subspace (b ~ 0): T_j holds exact eigenvalues of the pencil.
    const bool exhausted = !(b > 1e-14 * std::max(std::abs(a), 1e-300)) || j == n;
    // theta of T_j every third step (its eigenvalues cost O(j^2)): converged when it moved
    // by at most relative_tolerance over two such checks in a row.
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
  out.dt_crit = theta > 0.0 ? 2.0 / out.omega_max : std::numeric_limits<double>::infinity();
  return out;
}

// Exact elimination of the non-contact dofs from one step (StepMethod::kCondensed).
// With H mapping the displacements to the contact unknowns x_c = H du, the step equation
//     S du + q = H' F          (F: the contact forces conjugate to x_c)
// gives du = S^-1 (H' F - q) and x_c = W F - H S^-1 q with the Delassus operator
// W = H S^-1 H'. Hence F = W^-1 x_c + W^-1 H S^-1 q: a ContactSystem over the contact
// unknowns with S_c = W^-1 and q_c = W^-1 H S^-1 q, whose solution is the same as that of
// the full system. W is formed once from one solve with the Cholesky factor of S per row of H.
//   With friction, H selects every free component of every contact node (the condensed
//   nodes keep their frames). Frictionless, only the normal displacement n_c . du_c of each
//   node enters the contact conditions, so H has one row per node (the condensed node has
//   normal e_x and no tangent): W is dim^2 times smaller and its solves dim^3 times cheaper.
class CondensedStep {
 public:
  /// n free dofs, S = M / m_max: S^-1 = m_max M^-1 through `mass` (which must outlive this).
  CondensedStep(int dim, Eigen::Index n, MassInverse* mass, double m_max,
                const std::vector<ContactNode>& nodes, bool frictionless)
      : dim_(dim), nodes_(nodes), mass_(mass), m_max_(m_max) {
    // H, and the nodes renumbered onto the contact unknowns.
    std::vector<Eigen::Triplet<double>> h;
    std::vector<ContactNode> condensed = nodes;
    int rows = 0;
    for (ContactNode& node : condensed) {
      if (frictionless) {
        for (int a = 0; a < dim; ++a)
          if (node.dofs[a] >= 0) h.emplace_back(rows, node.dofs[a], node.normal(a));
        node.dofs[0] = rows++;
        node.dofs[1] = node.dofs[2] = -1;
        node.normal = Eigen::Vector3d::UnitX();
        node.tangent1.setZero();
        node.tangent2.setZero();
        CompleteContactFrame(dim, &node);
        continue;
      }
      for (int a = 0; a < dim; ++a) {
        if (node.dofs[a] < 0) continue;
        h.emplace_back(rows, node.dofs[a], 1.0);
        node.dofs[a] = rows++;
      }
    }
    H_.resize(rows, n);
    H_.setFromTriplets(h.begin(), h.end());
    // W = H (S^-1 H'), in blocks of columns of H' (at most ~256 MB of right-hand sides).
    const Eigen::SparseMatrix<double> Ht = H_.transpose();
    Eigen::MatrixXd W(rows, rows), block, solved;
    const int width = static_cast<int>(std::clamp<Eigen::Index>((1 << 25) / std::max<Eigen::Index>(n, 1), 1, 256));
    for (int first = 0; first < rows; first += width) {
      const int count = std::min(width, rows - first);
      block = Eigen::MatrixXd(Ht.middleCols(first, count));
      mass_->Solve(block, &solved);
      solved *= m_max_;  // S^-1 = m_max M^-1
      W.middleCols(first, count) = H_ * solved;
    }
    W = 0.5 * (W + W.transpose());
    const Eigen::LLT<Eigen::MatrixXd> llt(W);
    if (llt.info() != Eigen::Success)
      throw std::invalid_argument("contact::RunDynamics: the Delassus operator H M^-1 H' is not "
                                  "positive definite; use the full step");
    inverse_delassus_ = llt.solve(Eigen::MatrixXd::Identity(rows, rows));
    system_ = std::make_unique<ContactSystem>(dim, inverse_delassus_.sparseView(0.0, 0.0), condensed);
    normal_only_ = frictionless;
  }

  ContactSystem& system() { return *system_; }

  /// x_c = H x.
  Eigen::VectorXd Restrict(const Eigen::VectorXd& x) const { return H_ * x; }

  /// Data of one step: q and u0 on all free dofs.
  void Update(const Eigen::VectorXd& q, const Eigen::VectorXd& u0, const Eigen::VectorXd& bound) {
    SolveS(q, &full_);
    contact_.noalias() = H_ * full_;
    q_c_.noalias() = inverse_delassus_ * contact_;  // W^-1 H S^-1 q
    contact_.noalias() = H_ * u0;
    system_->Update(q_c_, contact_, bound);
  }

  /// The full result from the condensed one: du = S^-1 (H' F - q), F = S_c x_c + q_c, with
  /// the q of the last Update(). Normal-only: the slip t_a . du_c from the full du.
  ContactSystem::Result Expand(ContactSystem::Result condensed, const Eigen::VectorXd& q) {
    contact_.noalias() = inverse_delassus_ * condensed.x;
    contact_ += q_c_;  // F
    full_.noalias() = H_.transpose() * contact_;
    full_ -= q;
    SolveS(full_, &condensed.x);
    if (normal_only_)
      for (size_t c = 0; c < nodes_.size(); ++c) {
        const ContactNode& node = nodes_[c];
        for (int a = 1; a < dim_; ++a) {
          const Eigen::Vector3d& t = a == 1 ? node.tangent1 : node.tangent2;
          double slip = 0.0;
          for (int b = 0; b < dim_; ++b)
            if (node.dofs[b] >= 0) slip += t(b) * condensed.x(node.dofs[b]);
          condensed.slip(a - 1, static_cast<Eigen::Index>(c)) = slip;
        }
      }
    return condensed;
  }

 private:
  int dim_;
  std::vector<ContactNode> nodes_;
  bool normal_only_ = false;
  MassInverse* mass_;
  double m_max_;
  void SolveS(const Eigen::VectorXd& b, Eigen::VectorXd* x) {  // x = S^-1 b
    mass_->Solve(b, x);
    *x *= m_max_;
  }
  Eigen::SparseMatrix<double> H_;
  Eigen::MatrixXd inverse_delassus_;
  std::unique_ptr<ContactSystem> system_;
  Eigen::VectorXd q_c_, full_, contact_;  // (buffers: no allocation per step)
};

// The step with a diagonal S (StepMethod::kExplicit). Node by node, in the local frame of
// its free components (S restricted to a node is m I, so the rotation keeps it diagonal):
//   m y + q = F,  F = (-lambda, tau):
//   normal:  y_n = -q_n / m predicted; if it would close past the obstacle
//            (s - u0_n - y_n < 0) then y_n = s - u0_n and lambda = -(m y_n + q_n) >= 0;
//   tangent: stick (y_T = 0, tau = q_T) if |q_T| <= g, else slide with tau = g q_T / |q_T|
//            and y_T = (tau - q_T) / m - the return map onto the friction disc.
// Non-contact dofs: y = -q / m. The result is the exact solution of the step system.
class ExplicitStep {
 public:
  ExplicitStep(int dim, const Eigen::SparseMatrix<double>& S, const std::vector<ContactNode>& nodes)
      : dim_(dim), nodes_(nodes), diagonal_(S.rows()) {
    diagonal_ = S.diagonal();
    if (!IsDiagonal(S) || !(diagonal_.minCoeff() > 0.0))
      throw std::invalid_argument("contact::RunDynamics: the explicit step needs a lumped "
                                  "(diagonal) mass matrix; use mass = \"lumped\" or another step");
    for (const ContactNode& node : nodes_) {
      double m = -1.0;
      for (int a = 0; a < dim_; ++a) {
        if (node.dofs[a] < 0) continue;
        if (m >= 0.0 && std::abs(diagonal_(node.dofs[a]) - m) > 1e-12 * m)
          throw std::invalid_argument("contact::RunDynamics: the explicit step needs the same "
                                      "lumped mass in every component of contact node " +
                                      std::to_string(node.node));
        m = diagonal_(node.dofs[a]);
      }
    }
  }

  /// du and the contact result, in system units, for S du + q = F with bounds g.
  /// (*out is reused: no allocation once it has the sizes.)
  void Solve(const Eigen::VectorXd& q, const Eigen::VectorXd& u0, const Eigen::VectorXd& bound,
             ContactSystem::Result* result) const {
    const auto N = static_cast<Eigen::Index>(nodes_.size());
    ContactSystem::Result& out = *result;
    out.x = -q.cwiseQuotient(diagonal_);
    out.normal_force.setZero(N);
    out.gap.setZero(N);
    out.tangent_force.setZero(dim_ - 1, N);
    out.slip.setZero(dim_ - 1, N);
    for (Eigen::Index c = 0; c < N; ++c) {
      const ContactNode& node = nodes_[static_cast<size_t>(c)];
      const Eigen::Vector3d frame[3] = {node.normal, node.tangent1, node.tangent2};
      int slots[3] = {0, 0, 0}, axes[3] = {0, 0, 0}, num_free = 0;
      for (int a = 0; a < dim_; ++a)
        if (node.dofs[a] >= 0) slots[num_free] = node.dofs[a], axes[num_free++] = a;
      const double m = diagonal_(slots[0]);
      auto local = [&](const Eigen::VectorXd& v, int a) {
        double sum = 0.0;
        for (int b = 0; b < num_free; ++b) sum += frame[a](axes[b]) * v(slots[b]);
        return sum;
      };
      // Normal.
      const double qn = local(q, 0), u0n = local(u0, 0);
      double yn = -qn / m, lambda = 0.0;
      if (node.gap - u0n - yn < 0.0) {
        yn = node.gap - u0n;
        lambda = -(m * yn + qn);
      }
      // Tangent: the return map onto |tau| <= g.
      const double g = bound.size() ? bound(c) : 0.0;
      Eigen::Vector2d qt = Eigen::Vector2d::Zero(), yt = Eigen::Vector2d::Zero(), tau = Eigen::Vector2d::Zero();
      for (int a = 1; a < num_free; ++a) qt(a - 1) = local(q, a);
      if (g > 0.0 && qt.norm() <= g) {
        tau = qt;  // stick: y_T = 0
      } else {
        tau = g > 0.0 ? Eigen::Vector2d(g * qt / qt.norm()) : Eigen::Vector2d::Zero();
        yt = (tau - qt) / m;
      }
      // Back to the global components of the node.
      for (int b = 0; b < num_free; ++b) {
        double v = frame[0](axes[b]) * yn;
        for (int a = 1; a < num_free; ++a) v += frame[a](axes[b]) * yt(a - 1);
        out.x(slots[b]) = v;
      }
      out.normal_force(c) = lambda;
      out.gap(c) = node.gap - u0n - yn;
      for (int a = 1; a < num_free; ++a) {
        out.tangent_force(a - 1, c) = tau(a - 1);
        out.slip(a - 1, c) = yt(a - 1);
      }
    }
  }

 private:
  int dim_;
  std::vector<ContactNode> nodes_;
  Eigen::VectorXd diagonal_;
};

// The scales a step is solved against, in newtons and metres (dynamics.hpp, kAccuracySlack).
struct StepScales {
  double force = 0.0;         // F [N]
  double displacement = 0.0;  // D [m]
};
StepScales ComputeStepScales(const Eigen::VectorXd& f, const Eigen::VectorXd& Ku,
                             double contact_force_max, const Eigen::VectorXd& du_previous,
                             const std::vector<ContactNode>& nodes, const Eigen::VectorXd& u,
                             double m_max, double dt) {
  StepScales out;
  out.force = std::max({f.lpNorm<Eigen::Infinity>(), Ku.lpNorm<Eigen::Infinity>(), contact_force_max});
  double penetration = 0.0;
  for (const ContactNode& node : nodes) {
    double un = 0.0;
    for (int a = 0; a < 3; ++a)
      if (node.dofs[a] >= 0) un += node.normal(a) * u(node.dofs[a]);
    penetration = std::max(penetration, un - node.gap);
  }
  const double step_of_force = out.force * dt * dt / m_max;
  out.displacement = std::max({du_previous.lpNorm<Eigen::Infinity>(), step_of_force, penetration});
  if (out.force == 0.0) out.force = out.displacement * m_max / (dt * dt);
  if (out.force == 0.0) out.force = out.displacement = 1.0;  // nothing moves, loads or touches
  return out;
}

// Accuracy of a completed step, recomputed from the state in newtons and metres:
//   equilibrium: r = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k - f^k (given) must equal the
//     contact forces -lambda_c n_c + tau_c at the contact nodes and 0 elsewhere;
//   penetration: max(0, -(s_c - n_c . u^{k+1}_c));
//   complementarity: lambda_c >= 0, and lambda_c = 0 where the gap is open by more than
//     kAccuracySlack displacement accuracies;
//   friction: |tau_c| <= g_c, and tau_c = -g_c slip_c / |slip_c| where the node slips by more
//     than kAccuracySlack displacement accuracies (g_c [N] the step's Tresca bound).
void MeasureStepAccuracy(int dim, const std::vector<ContactNode>& nodes, const Eigen::VectorXd& r,
                         const ContactSystem::Result& contact, double force_scale,
                         const Eigen::VectorXd& u_next, const Eigen::VectorXd& bound,
                         Eigen::VectorXd* residual, StepRecord* rec) {
  // (bound and the contact result in system units: times force_scale for newtons.)
  *residual = r;  // minus the contact forces below
  double penetration = 0.0, complementarity = 0.0, friction = 0.0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const ContactNode& node = nodes[i];
    const auto c = static_cast<Eigen::Index>(i);
    const double lambda = force_scale * contact.normal_force(c);
    Eigen::Vector3d force = -lambda * node.normal;
    Eigen::Vector2d tau = Eigen::Vector2d::Zero(), slip = Eigen::Vector2d::Zero();
    for (int a = 1; a < dim; ++a) {
      const Eigen::Vector3d& t = a == 1 ? node.tangent1 : node.tangent2;
      tau(a - 1) = force_scale * contact.tangent_force(a - 1, c);
      slip(a - 1) = contact.slip(a - 1, c);
      force += tau(a - 1) * t;
    }
    double un = 0.0;
    for (int a = 0; a < dim; ++a) {
      if (node.dofs[a] < 0) continue;
      (*residual)(node.dofs[a]) -= force(a);
      un += node.normal(a) * u_next(node.dofs[a]);
    }
    const double gap = node.gap - un;
    penetration = std::max(penetration, -gap);
    complementarity = std::max(complementarity, -lambda);
    if (gap > kAccuracySlack * rec->displacement_accuracy)  // open: no force
      complementarity = std::max(complementarity, lambda);
    const double g = bound.size() ? force_scale * bound(c) : 0.0;
    friction = std::max(friction, tau.norm() - g);
    if (slip.norm() > kAccuracySlack * rec->displacement_accuracy)  // slipping: tau opposes it
      friction = std::max(friction, (tau + g * slip / slip.norm()).norm());
  }
  rec->equilibrium_residual = residual->lpNorm<Eigen::Infinity>();
  rec->max_penetration = std::max(0.0, penetration);
  rec->complementarity_residual = complementarity;
  rec->friction_residual = friction;
  rec->accurate = rec->equilibrium_residual <= kAccuracySlack * rec->force_accuracy &&
                  rec->complementarity_residual <= kAccuracySlack * rec->force_accuracy &&
                  rec->friction_residual <= kAccuracySlack * rec->force_accuracy &&
                  rec->max_penetration <= kAccuracySlack * rec->displacement_accuracy;
}

}  // namespace

void SymmetricMultiply(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                       Eigen::VectorXd* y) {
  if (A.rows() != A.cols() || x.size() != A.cols())
    throw std::invalid_argument("SymmetricMultiply: A must be square with as many columns as x has entries");
  internal::SymmetricMultiply(A, x, y);
}

const char* ToString(StepMethod m) {
  switch (m) {
    case StepMethod::kFull: return "full";
    case StepMethod::kCondensed: return "condensed";
    case StepMethod::kExplicit: return "explicit";
  }
  return "unknown";
}

const char* ToString(StepSolver s) {
  switch (s) {
    case StepSolver::kFischerBurmeister: return "fb";
    case StepSolver::kMin: return "min";
    case StepSolver::kPenalizedFischerBurmeister: return "penalized-fb";
    case StepSolver::kIpopt: return "ipopt";
  }
  return "unknown";
}

const char* ToString(DynamicStatus s) {
  switch (s) {
    case DynamicStatus::kNotRun: return "not-run";
    case DynamicStatus::kCompleted: return "completed";
    case DynamicStatus::kSolverFailure: return "solver-failure";
    case DynamicStatus::kEnergyBlowUp: return "energy-blow-up";
    case DynamicStatus::kRefusedUnstable: return "refused-unstable-time-step";
    case DynamicStatus::kAccuracyNotReached: return "accuracy-not-reached";
  }
  return "unknown";
}

CriticalTimeStep EstimateCriticalTimeStep(const Eigen::SparseMatrix<double>& K,
                                          const Eigen::SparseMatrix<double>& M,
                                          double relative_tolerance, int max_iterations) {
  if (K.rows() != M.rows() || K.cols() != M.cols() || K.rows() != K.cols())
    throw std::invalid_argument("EstimateCriticalTimeStep: K and M must be square of equal size");
  MassInverse mass(M, "EstimateCriticalTimeStep: ");
  return Lanczos(K, M, &mass, relative_tolerance, max_iterations);
}

DynamicSummary RunDynamics(const DynamicModel& model, const DynamicOptions& options) {
  const auto start = Clock::now();
  const Eigen::Index n = model.K.rows();
  const std::string who = "contact::RunDynamics: ";
  if (model.dim != 2 && model.dim != 3)
    throw std::invalid_argument(who + "dim must be 2 or 3, got " + std::to_string(model.dim));
  if (model.M.rows() != n || model.M.cols() != n || model.K.cols() != n)
    throw std::invalid_argument(who + "K and M must both be " + std::to_string(n) + " x " +
                                std::to_string(n));
  if (!model.load) throw std::invalid_argument(who + "the load function is not set");
  if (!(options.dt > 0.0) || !std::isfinite(options.dt))
    throw std::invalid_argument(who + "dt must be > 0, got " + std::to_string(options.dt));
  if (!(options.end_time >= options.start_time) || !std::isfinite(options.end_time) ||
      !std::isfinite(options.start_time))
    throw std::invalid_argument(who + "end_time must be finite and >= start_time");
  // Counted in double: (end_time - start_time) / dt may exceed every integer type.
  const double step_count = std::ceil((options.end_time - options.start_time) / options.dt - 1e-3);
  if (!(step_count <= kMaxTimeSteps))
    throw std::invalid_argument(who + "(end_time - start_time) / dt = " + internal::FormatShort(step_count) +
                                " time steps; at most " + internal::FormatShort(kMaxTimeSteps) + " are accepted");
  if (!(options.friction_coefficient >= 0.0))
    throw std::invalid_argument(who + "friction_coefficient must be >= 0, got " +
                                std::to_string(options.friction_coefficient));
  if ((options.solver == StepSolver::kIpopt || options.compare_with_ipopt) &&
      options.friction_coefficient > 0.0)
    throw std::invalid_argument(who + "the Ipopt step solver handles frictionless contact only "
                                      "(friction_coefficient = " +
                                std::to_string(options.friction_coefficient) + ")");
  if (!internal::IsSymmetric(model.K, 1e-12) || !internal::IsSymmetric(model.M, 1e-12))
    throw std::invalid_argument(who + "K and M must be symmetric (to 1e-12 of their largest entry)");
  if (options.initial_state == InitialState::kPrescribed &&
      (options.u0.size() != n || options.v0.size() != n))
    throw std::invalid_argument(who + "prescribed u0 and v0 must have size " + std::to_string(n));

  DynamicSummary summary;
  const double dt = options.dt;

  // Stability: central differences need dt <= 2 / omega_max.
  MassInverse mass(model.M, who);
  const CriticalTimeStep crit =
      Lanczos(model.K, model.M, &mass, kCriticalStepTolerance, kCriticalStepMaxIterations);
  summary.critical_time_step = crit.dt_crit;
  // omega_max = 0 (no stiffness, e.g. a rigid mass) gives dt_crit = inf: any dt is stable.
  if (!(crit.dt_crit > 0) || !(crit.omega_max >= 0) || !std::isfinite(crit.omega_max))
    throw std::invalid_argument(who + "the critical time step 2/omega_max = " + internal::FormatShort(crit.dt_crit) +
                                " s is not a positive finite number (omega_max = " +
                                internal::FormatShort(crit.omega_max) +
                                " rad/s): K or M is out of the range of double precision (check the "
                                "Young's modulus [Pa], density [kg/m^3] and mesh size [m])");
  if (dt > crit.dt_crit && !options.allow_unstable_time_step) {
    summary.status = DynamicStatus::kRefusedUnstable;
    char buffer[256];
    std::snprintf(buffer, sizeof buffer,
                  "time step dt = %.6g s exceeds the critical step dt_crit = 2/omega_max = %.6g s "
                  "of central differences (omega_max = %.6g rad/s); set "
                  "allow_unstable_time_step to run anyway",
                  dt, crit.dt_crit, crit.omega_max);
    summary.message = buffer;
    summary.seconds = Seconds(start);
    return summary;
  }

  // Initial state.
  Eigen::VectorXd f(n), u(n), u_previous(n);
  model.load(options.start_time, &f);
  Eigen::VectorXd lambda_physical = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.contact_nodes.size()));
  if (options.initial_state == InitialState::kStaticEquilibrium) {
    StaticContactOptions static_options;
    static_options.ncp = options.ncp;
    const StaticContactResult s = SolveStaticContact(model.dim, model.K, f, model.contact_nodes, static_options);
    if (!s.converged) {
      summary.status = DynamicStatus::kSolverFailure;
      summary.message = "static initial state: " + s.message;
      summary.seconds = Seconds(start);
      return summary;
    }
    u = s.u;
    u_previous = u;
    lambda_physical = s.normal_force;
  } else {
    u = options.u0;
    Eigen::VectorXd a0(n);  // M a0 = f - K u0
    mass.Solve(f - model.K * u, &a0);
    u_previous = u - dt * options.v0 + 0.5 * dt * dt * a0;
  }

  // The step system: S = M / Mmax is the same every step.
  const double m_max = MaxAbsEntry(model.M);
  const double force_scale = m_max / (dt * dt);  // system units -> newtons
  const bool use_condensed =
      options.solver != StepSolver::kIpopt && options.step_method == StepMethod::kCondensed;
  // S itself only where it is used (the condensed step works with the factor of M): a copy
  // of a consistent M is as large as M.
  Eigen::SparseMatrix<double> S;
  if (!use_condensed || options.compare_with_ipopt) S = model.M / m_max;
  // One of: the full system (kFull, and Ipopt's results), the condensed one, the explicit one.
  std::unique_ptr<ContactSystem> full;
  std::unique_ptr<CondensedStep> condensed;
  std::unique_ptr<ExplicitStep> explicit_step;
  if (use_condensed)
    condensed = std::make_unique<CondensedStep>(model.dim, n, &mass, m_max, model.contact_nodes,
                                                options.friction_coefficient == 0.0);
  else if (options.solver != StepSolver::kIpopt && options.step_method == StepMethod::kExplicit)
    explicit_step = std::make_unique<ExplicitStep>(model.dim, S, model.contact_nodes);
  else
    full = std::make_unique<ContactSystem>(model.dim, S, model.contact_nodes);
  ncp::Options ncp_options = options.ncp;
  ncp_options.ncp_function = FunctionOf(options.solver);
  // The condensed system's matrix W^-1 is dense: a dense LU beats a sparse one at any size.
  if (condensed && ncp_options.linear_solver == ncp::LinearSolverType::kAuto)
    ncp_options.linear_solver = ncp::LinearSolverType::kDenseLU;
  ncp::Solver solver(ncp_options);

  // Ipopt reference: rows n_c . du_c <= s_c - n_c . u^k, i.e. G = Y R.
  Eigen::SparseMatrix<double> G;
  if (options.solver == StepSolver::kIpopt || options.compare_with_ipopt) {
    const RestrictionMaps maps = MakeRestrictionMaps(model.dim, static_cast<int>(n), model.contact_nodes);
    G = maps.Y * maps.R;
  }
  Eigen::VectorXd gap0(static_cast<Eigen::Index>(model.contact_nodes.size()));
  for (size_t c = 0; c < model.contact_nodes.size(); ++c) gap0(static_cast<Eigen::Index>(c)) = model.contact_nodes[c].gap;

  // Every step needs one product with K and one with M, carried between steps so that no
  // product is formed twice (and nothing is allocated in the loop):
  //   Ku = K u^k,  Mdu_previous = M (u^k - u^{k-1}),  Mdu = M (u^{k+1} - u^k).
  // Shadow energy of central differences at k + 1/2 (conserved exactly without forces):
  //   E = 1/2 v' M v + 1/2 (u^k)' K u^{k+1},  v = (u^{k+1} - u^k) / dt.
  // It cannot reveal an instability (the cross term turns negative), so the blow-up guard
  // uses the positive 1/2 v' M v + 1/2 u' K u.
  Eigen::VectorXd Ku(n), Ku_next(n), Mdu_previous(n), Mdu(n);
  // (Products by internal::SymmetricMultiply: parallel, same result for any thread count.)
  internal::SymmetricMultiply(model.K, u, &Ku);
  Mdu = u - u_previous;  // (as a temporary for the product)
  internal::SymmetricMultiply(model.M, Mdu, &Mdu_previous);
  const double kinetic0 = 0.5 * (u - u_previous).dot(Mdu_previous) / (dt * dt);
  const double energy0 = kinetic0 + 0.5 * u_previous.dot(Ku);
  const double strain0 = 0.5 * u.dot(Ku);
  double external_work = 0.0, normal_work = 0.0, friction_dissipation = 0.0, work_scale = 0.0;

  Eigen::VectorXd du = u - u_previous;  // start guess of the first step
  Eigen::MatrixXd friction_previous;     // local friction forces of the previous step
  Eigen::VectorXd Q(n), q(n), r(n), residual(n), u_next(n), bound, lambda_now;
  double contact_force_max = 0.0;  // |r^k|_inf of the previous step [N]
  StepRecord first_inaccurate;
  ContactSystem::Result contact;
  const long num_steps = static_cast<long>(step_count);
  double last_progress = 0.0;
  summary.records.reserve(static_cast<size_t>(std::max(0L, num_steps)));

  for (long k = 0; k < num_steps; ++k) {
    const auto step_start = Clock::now();
    const double t_k = options.start_time + static_cast<double>(k) * dt;
    model.load(t_k, &f);
    // Q^k = M (u^{k-1} - u^k) / dt^2 + K u^k - f^k   (eq. 73), scaled by dt^2 / Mmax (eq. 81).
    Q = Ku - f - Mdu_previous / (dt * dt);
    q = Q / force_scale;
    if (options.friction_coefficient > 0.0)
      bound = (options.friction_coefficient / force_scale) * lambda_physical.cwiseMax(0.0);
    else
      bound.resize(0);
    // The step's scales (dynamics.hpp): the accuracy every step method is held to.
    Mdu = u - u_previous;  // (du of the previous step, as a temporary)
    const StepScales scales = ComputeStepScales(f, Ku, contact_force_max, Mdu, model.contact_nodes,
                                                u, m_max, dt);
    ContactSystem* step_system = condensed ? &condensed->system() : full.get();
    if (step_system) {
      if (condensed) condensed->Update(q, u, bound);
      else full->Update(q, u, bound);
      step_system->SetResidualScales(scales.force / force_scale, scales.displacement);
    }

    StepRecord rec;
    rec.step = static_cast<int>(k + 1);
    rec.time = t_k + dt;
    // Frictionless reference: the step as the convex QP
    //   min 1/2 du' S du + q' du  s.t.  n_c . du_c <= s_c - n_c . u^k_c,
    // whose multipliers are the normal reactions (system units).
    auto solve_qp = [&]() {
      // Posed in the step's own scales (du = D xi, forces = F z), so that Ipopt's tests at
      // tol = ncp.tolerance - stationarity, constraint violation and lambda_c gap_c - mean
      // tolerance F, tolerance D and tolerance F D in the units of the step:
      //   min 1/2 xi' (S D / F) xi + (q / F)' xi   s.t.  G xi <= (s - G u^k) / D.
      const double F = scales.force / force_scale, D = scales.displacement;
      ConvexQpOptions qp_options;
      qp_options.tolerance = options.ncp.tolerance;
      qp_options.dual_infeasibility_tolerance = options.ncp.tolerance;
      qp_options.constraint_violation_tolerance = options.ncp.tolerance;
      qp_options.complementarity_tolerance = options.ncp.tolerance;
      ConvexQpResult qp = SolveConvexQpIpopt((D / F) * S, q / F, G, (gap0 - G * u) / D, du / D, qp_options);
      qp.x *= D;
      qp.multipliers *= F;
      return qp;
    };
    bool ok;
    const auto solve_start = Clock::now();
    if (options.solver == StepSolver::kIpopt) {
      const ConvexQpResult qp = solve_qp();
      rec.solve_seconds = Seconds(solve_start);
      ok = qp.status == ConvexQpStatus::kSolved;
      rec.solver_status = ok ? "converged" : qp.message;
      rec.newton_iterations = qp.iterations;
      contact = full->Extract(full->StartPoint(qp.x));
      contact.normal_force = qp.multipliers;
    } else if (explicit_step) {
      explicit_step->Solve(q, u, bound, &contact);
      rec.solve_seconds = Seconds(solve_start);
      ok = contact.x.allFinite();
      rec.solver_status = ok ? "converged" : "non-finite values in the explicit step";
    } else {
      const Eigen::VectorXd guess = condensed ? condensed->Restrict(du) : du;
      ncp::Vector z = step_system->StartPoint(guess, friction_previous);
      ncp::Summary s;
      solver.Solve(*step_system, &z, &s);
      rec.newton_iterations = s.iterations;
      rec.jacobian_evaluations = s.jacobian_evaluations;
      rec.residual_evaluations = s.residual_evaluations;
      // With friction, the start from the previous friction forces can sit next to the
      // degenerate point of eq. (94) (a friction force much smaller than its bound leaves
      // the direction t nearly undetermined; seen in Table 3 at step 29). Retry once from
      // the start without the force guess (direction from the slip, or t1 with g_c / 2).
      if (!s.IsSolutionUsable() && step_system->num_friction_nodes() > 0 && friction_previous.size()) {
        z = step_system->StartPoint(guess);
        solver.Solve(*step_system, &z, &s);
        rec.newton_iterations += s.iterations;
        rec.jacobian_evaluations += s.jacobian_evaluations;
        rec.residual_evaluations += s.residual_evaluations;
        ++summary.friction_restarts;
      }
      rec.solve_seconds = Seconds(solve_start);
      ok = s.IsSolutionUsable();
      rec.solver_status = ok ? "converged" : s.message;
      contact = condensed ? condensed->Expand(step_system->Extract(z), q) : step_system->Extract(z);
      if (ok && options.compare_with_ipopt) {
        const ConvexQpResult qp = solve_qp();
        rec.ipopt_relative_difference =
            qp.status == ConvexQpStatus::kSolved
                ? (contact.x - qp.x).lpNorm<Eigen::Infinity>() /
                      std::max(contact.x.lpNorm<Eigen::Infinity>(), 1e-300)
                : std::numeric_limits<double>::infinity();
        summary.max_ipopt_relative_difference =
            std::max(summary.max_ipopt_relative_difference, rec.ipopt_relative_difference);
      }
    }
    summary.newton_iterations += rec.newton_iterations;
    summary.jacobian_evaluations += rec.jacobian_evaluations;
    summary.residual_evaluations += rec.residual_evaluations;
    if (!ok) {
      summary.status = DynamicStatus::kSolverFailure;
      summary.message = "step " + std::to_string(k + 1) + " (t = " + std::to_string(rec.time) +
                        " s): " + rec.solver_status;
      break;
    }
    du = contact.x;
    if (options.friction_coefficient > 0.0) friction_previous = contact.tangent_force;
    u_next = u + du;
    internal::SymmetricMultiply(model.M, du, &Mdu);
    internal::SymmetricMultiply(model.K, u_next, &Ku_next);

    // Contact forces r^{k+1} = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k - f^k, in newtons,
    // and the work increments over the half span (u^{k+1} - u^{k-1}) / 2.
    r = Mdu / (dt * dt) + Q;
    // Accuracy asked for (tolerance times the scales, plus the round-off of the terms of r and
    // of the positions) and reached, measured from the state.
    const double eps = std::numeric_limits<double>::epsilon();
    rec.force_accuracy = options.ncp.tolerance * scales.force +
                         ContactSystem::kRoundoffUlps * eps *
                             (Q.lpNorm<Eigen::Infinity>() + Mdu.lpNorm<Eigen::Infinity>() / (dt * dt));
    rec.displacement_accuracy = options.ncp.tolerance * scales.displacement +
                                ContactSystem::kRoundoffUlps * eps *
                                    (u_next.lpNorm<Eigen::Infinity>() + gap0.lpNorm<Eigen::Infinity>());
    MeasureStepAccuracy(model.dim, model.contact_nodes, r, contact, force_scale, u_next,
                        bound, &residual, &rec);
    contact_force_max = (r - residual).lpNorm<Eigen::Infinity>();
    const double dw_ext = 0.5 * (f.dot(u_next) - f.dot(u_previous));
    external_work += dw_ext;
    work_scale += std::abs(dw_ext);
    double dw_normal = 0.0;
    for (size_t c = 0; c < model.contact_nodes.size(); ++c) {
      const ContactNode& node = model.contact_nodes[c];
      Eigen::Vector3d rc = Eigen::Vector3d::Zero(), sc = Eigen::Vector3d::Zero();
      for (int a = 0; a < model.dim; ++a) {
        if (node.dofs[a] < 0) continue;  // constrained component: no motion, no work
        rc(a) = r(node.dofs[a]);
        sc(a) = 0.5 * (u_next(node.dofs[a]) - u_previous(node.dofs[a]));
      }
      const double rn = rc.dot(node.normal), sn = sc.dot(node.normal);
      dw_normal += rn * sn;
      friction_dissipation -= rc.dot(sc) - rn * sn;
    }
    normal_work += dw_normal;

    // Bookkeeping of the record.
    rec.kinetic = 0.5 * du.dot(Mdu) / (dt * dt);
    const double shadow = rec.kinetic + 0.5 * u.dot(Ku_next);
    rec.strain = 0.5 * u_next.dot(Ku_next);
    rec.external_work = external_work;
    rec.normal_contact_work = normal_work;
    rec.friction_dissipation = friction_dissipation;
    rec.energy_balance_error =
        shadow - energy0 - external_work - normal_work + friction_dissipation;
    lambda_now = force_scale * contact.normal_force;
    rec.normal_force_sum = lambda_now.sum();
    for (Eigen::Index c = 0; c < contact.tangent_force.cols(); ++c)
      rec.tangent_force_sum += force_scale * contact.tangent_force.col(c).norm();
    rec.active_nodes = static_cast<int>((lambda_now.array() > 0.0).count());
    rec.seconds = Seconds(step_start);
    summary.max_penetration = std::max(summary.max_penetration, rec.max_penetration);
    summary.max_equilibrium_residual = std::max(summary.max_equilibrium_residual, rec.equilibrium_residual);
    summary.max_complementarity_residual =
        std::max(summary.max_complementarity_residual, rec.complementarity_residual);
    summary.max_friction_residual = std::max(summary.max_friction_residual, rec.friction_residual);
    if (!rec.accurate && summary.inaccurate_steps++ == 0) first_inaccurate = rec;
    summary.energy_balance_error = std::max(summary.energy_balance_error, std::abs(rec.energy_balance_error));
    summary.steps = rec.step;
    summary.records.push_back(rec);
    if (options.on_step) options.on_step(rec, u_next, contact, force_scale);

    // Advance: u^{k-1} <- u^k <- u^{k+1}, with the products that go along.
    lambda_physical.swap(lambda_now);
    u_previous.swap(u);
    u.swap(u_next);
    Ku.swap(Ku_next);
    Mdu_previous.swap(Mdu);

    const double energy = rec.kinetic + rec.strain;
    // The reference is zero until energy enters (a body at rest under a step load): no
    // ratio test before that, so round-off energy cannot trip it.
    const double reference = kinetic0 + strain0 + work_scale;
    if (!std::isfinite(energy) ||
        (reference > 0.0 && energy > options.energy_blowup_factor * reference)) {
      summary.status = DynamicStatus::kEnergyBlowUp;
      char buffer[200];
      std::snprintf(buffer, sizeof buffer,
                    "energy blow-up at step %d (t = %.6g s): E = %.3e J against %.3e J of initial "
                    "energy and external work",
                    rec.step, rec.time, energy, reference);
      summary.message = buffer;
      break;
    }
    if (options.progress && Seconds(start) - last_progress > 1.0) {
      last_progress = Seconds(start);
      std::fprintf(stderr, "  step %d / %ld, t = %.6g s, %d Newton iterations, %.1f s\n", rec.step,
                   num_steps, rec.time, rec.newton_iterations, last_progress);
    }
  }
  if (summary.status == DynamicStatus::kNotRun && summary.inaccurate_steps > 0) {
    summary.status = DynamicStatus::kAccuracyNotReached;
    char buffer[400];
    std::snprintf(buffer, sizeof buffer,
                  "%d of %d steps missed their accuracy; the first, step %d (t = %.6g s): "
                  "equilibrium %.3e N, contact %.3e N, friction %.3e N against %.3e N, "
                  "penetration %.3e m against %.3e m (x %g allowed)",
                  summary.inaccurate_steps, summary.steps, first_inaccurate.step,
                  first_inaccurate.time, first_inaccurate.equilibrium_residual,
                  first_inaccurate.complementarity_residual, first_inaccurate.friction_residual,
                  first_inaccurate.force_accuracy, first_inaccurate.max_penetration,
                  first_inaccurate.displacement_accuracy, kAccuracySlack);
    summary.message = buffer;
  }
  if (summary.status == DynamicStatus::kNotRun) {
    summary.status = DynamicStatus::kCompleted;
    summary.message = "completed " + std::to_string(summary.steps) + " steps";
  }
  summary.u = u;
  summary.seconds = Seconds(start);
  return summary;
}

}  // namespace contact
