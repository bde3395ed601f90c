// StepMethod::kExplicit: the step with a lumped (diagonal) mass in closed form, node by node.
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "step/step_method.hpp"

namespace contact::internal {
namespace {

// The step with a diagonal S (StepMethod::kExplicit). Node by node, in the local frame of
// its free components (S restricted to a node is m I, so the rotation keeps it diagonal):
//   m y + q = F,  F = (-lambda, tau):
//   normal:  y_n = -q_n / m predicted; if it would close past the obstacle
//            (s - u0_n - y_n < 0) then y_n = s - u0_n and lambda = -(m y_n + q_n) >= 0;
//   tangent: stick (y_T = 0, tau = q_T) if |q_T| <= g, else slide with tau = g q_T / |q_T|
//            and y_T = (tau - q_T) / m - the return map onto the friction disc.
// Non-contact dofs: y = -q / m. The result is the exact solution of the step system.
class ExplicitStep : public StepAlgorithm {
 public:
  ExplicitStep(int dim, const Eigen::SparseMatrix<double>& S, const std::vector<ContactNode>& nodes)
      : dim_(dim), nodes_(nodes), diagonal_(S.rows()) {
    diagonal_ = S.diagonal();
    if (!IsDiagonal(S) || !(diagonal_.minCoeff() > 0.0))
      throw std::invalid_argument("contact::RunDynamics: the explicit step needs a lumped "
                                  "(diagonal) mass matrix; use mass = \"lumped\" or another step");
    const int unequal = UnequalLumpedMassNode(dim_, diagonal_, nodes_);
    if (unequal >= 0)
      throw std::invalid_argument("contact::RunDynamics: the explicit step needs the same "
                                  "lumped mass in every component of contact node " +
                                  std::to_string(unequal));
  }

  /// du and the contact result, in system units, for S du + q = F with bounds g (no
  /// iteration: the scales do not enter). (*result is reused: no allocation once it has the
  /// sizes.)
  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    const auto start = std::chrono::steady_clock::now();
    SolveClosedForm(step.q, step.u, step.bound, step.gap, result);
    StepOutcome out;
    out.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.ok = result->x.allFinite();
    out.status = out.ok ? "converged" : "non-finite values in the explicit step";
    return out;
  }

 private:
  void SolveClosedForm(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
                       const Eigen::VectorXd& bound, const Eigen::VectorXd& gap,
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
      if (gap(c) - u0n - yn < 0.0) {
        yn = gap(c) - u0n;
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
      out.gap(c) = gap(c) - u0n - yn;
      for (int a = 1; a < num_free; ++a) {
        out.tangent_force(a - 1, c) = tau(a - 1);
        out.slip(a - 1, c) = yt(a - 1);
      }
    }
  }

  int dim_;
  std::vector<ContactNode> nodes_;
  Eigen::VectorXd diagonal_;
};

}  // namespace

int UnequalLumpedMassNode(int dim, const Eigen::VectorXd& diagonal, const std::vector<ContactNode>& nodes) {
  for (const ContactNode& node : nodes) {
    double m = -1.0;
    for (int a = 0; a < dim; ++a) {
      if (node.dofs[a] < 0) continue;
      if (m >= 0.0 && std::abs(diagonal(node.dofs[a]) - m) > 1e-12 * m) return node.node;
      m = diagonal(node.dofs[a]);
    }
  }
  return -1;
}

std::unique_ptr<StepAlgorithm> MakeExplicitStep(const DynamicModel& model, double m_max) {
  return std::make_unique<ExplicitStep>(model.dim, model.M / m_max, model.contact_nodes);
}

}  // namespace contact::internal
