// StepMethod::kExplicit: the step with a lumped (diagonal) mass in closed form, node by
// node.
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "step/explicit_contact_node.hpp"
#include "step/step_method.hpp"

namespace contact::internal {
namespace {

// The step with a diagonal S (StepMethod::kExplicit): node by node in closed form
// (SolveExplicitContactNode, explicit_contact_node.hpp); non-contact dofs y = -q / m. The
// result is the exact solution of the step system.
class ExplicitStep : public StepAlgorithm {
 public:
  ExplicitStep(int dim, const Eigen::SparseMatrix<double>& S,
               const std::vector<ContactNode>& nodes)
      : dim_(dim), nodes_(nodes), diagonal_(S.rows()) {
    diagonal_ = S.diagonal();
    if (!IsDiagonal(S) || !(diagonal_.minCoeff() > 0.0))
      throw std::invalid_argument(
          "contact::RunDynamics: the explicit step needs a lumped "
          "(diagonal) mass matrix; use mass = \"lumped\" or another step");
    const int unequal = UnequalLumpedMassNode(dim_, diagonal_, nodes_);
    if (unequal >= 0)
      throw std::invalid_argument(
          "contact::RunDynamics: the explicit step needs the same "
          "lumped mass in every component of contact node " +
          std::to_string(unequal));
  }

  /// du and the contact result, in system units, for S du + q = F with bounds g (no
  /// iteration: the scales do not enter). (*result is reused: no allocation once it has
  /// the sizes.)
  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    const auto start = std::chrono::steady_clock::now();
    SolveClosedForm(step.q, step.u, step.bound, step.gap, step.obstacle_step, result);
    StepOutcome out;
    out.solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.ok = result->x.allFinite();
    out.status = out.ok ? "converged" : "non-finite values in the explicit step";
    return out;
  }
  bool TakesObstacleSlip() const override { return true; }

 private:
  void SolveClosedForm(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
                       const Eigen::VectorXd& bound, const Eigen::VectorXd& gap,
                       const Eigen::VectorXd* obstacle_step,
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
      const int first_free = node.dofs[0] >= 0   ? node.dofs[0]
                             : node.dofs[1] >= 0 ? node.dofs[1]
                                                 : node.dofs[2];
      const ExplicitNodeStep step = SolveExplicitContactNode(
          dim_, node, diagonal_(first_free), gap(c), bound.size() ? bound(c) : 0.0,
          q.data(), u0.data(), out.x.data(),
          obstacle_step ? obstacle_step->data() : nullptr);
      out.normal_force(c) = step.normal_force;
      out.gap(c) = step.gap;
      for (int a = 0; a < dim_ - 1; ++a) {
        out.tangent_force(a, c) = step.tangent_force(a);
        out.slip(a, c) = step.slip(a);
      }
    }
  }

  int dim_;
  std::vector<ContactNode> nodes_;
  Eigen::VectorXd diagonal_;
};

}  // namespace

int UnequalLumpedMassNode(int dim, const Eigen::VectorXd& diagonal,
                          const std::vector<ContactNode>& nodes) {
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
