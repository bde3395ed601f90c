// StepMethod::kCondensed: the step over the contact unknowns only, the other dofs
// eliminated exactly with M^-1 (a CHOLMOD factor or the lumped diagonal), solved by
// semismooth Newton.
#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>

#include "delassus.hpp"
#include "step/newton_step.hpp"
#include "step/step_method.hpp"

namespace contact::internal {
namespace {

// Exact elimination of the non-contact dofs from one step (StepMethod::kCondensed).
// With the Delassus operator W = H S^-1 H' (delassus.hpp), x_c = W F - H S^-1 q, hence
// F = W^-1 x_c + W^-1 H S^-1 q: a ContactSystem over the contact unknowns with S_c = W^-1
// and q_c = W^-1 H S^-1 q, whose solution is the same as that of the full system.
// Frictionless, H takes only the normal displacement of each node (W dim^2 times
// smaller).
class CondensedStep : public StepAlgorithm {
 public:
  /// S = M / m_max: S^-1 = m_max M^-1 through `mass` (which must outlive this).
  CondensedStep(const DynamicModel& model, MassInverse* mass, double m_max,
                const ncp::Options& ncp_options, bool friction)
      : dim_(model.dim),
        nodes_(model.contact_nodes),
        delassus_(model, mass, m_max, !friction),
        newton_(ncp_options, friction) {
    const Eigen::LLT<Eigen::MatrixXd> llt(delassus_.W());
    if (llt.info() != Eigen::Success)
      throw std::invalid_argument(
          "contact::RunDynamics: the Delassus operator H M^-1 H' is not "
          "positive definite; use the full step");
    inverse_delassus_ =
        llt.solve(Eigen::MatrixXd::Identity(delassus_.W().rows(), delassus_.W().rows()));
    system_ = std::make_unique<ContactSystem>(
        dim_, inverse_delassus_.sparseView(0.0, 0.0), delassus_.condensed_nodes());
    normal_only_ = !friction;
  }

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    system_->SetGaps(step.gap);
    Update(step.q, step.u, step.bound);
    // Forces to tolerance F, displacements to tolerance D (in system units).
    system_->SetResidualScales(step.scales.force / step.force_scale,
                               step.scales.displacement);
    const StepOutcome out = newton_.Solve(system_.get(), Restrict(step.guess), &z_);
    *result = Expand(system_->Extract(z_), step.q);
    if (out.ok) newton_.KeepFriction(*result);
    return out;
  }

  Eigen::MatrixXd WarmStart() const override { return newton_.kept_friction(); }
  void SetWarmStart(const Eigen::MatrixXd& warm_start) override {
    newton_.RestoreFriction(warm_start, dim_ - 1,
                            static_cast<Eigen::Index>(nodes_.size()));
  }

 private:
  /// x_c = H x.
  Eigen::VectorXd Restrict(const Eigen::VectorXd& x) const { return delassus_.H() * x; }

  /// Data of one step: q and u0 on all free dofs.
  void Update(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
              const Eigen::VectorXd& bound) {
    delassus_.SolveS(q, &full_);
    contact_.noalias() = delassus_.H() * full_;
    q_c_.noalias() = inverse_delassus_ * contact_;  // W^-1 H S^-1 q
    contact_.noalias() = delassus_.H() * u0;
    system_->Update(q_c_, contact_, bound);
  }

  /// The full result from the condensed one: du = S^-1 (H' F - q), F = S_c x_c + q_c,
  /// with the q of the last Update(). Normal-only: the slip t_a . du_c from the full du.
  ContactSystem::Result Expand(ContactSystem::Result condensed,
                               const Eigen::VectorXd& q) {
    contact_.noalias() = inverse_delassus_ * condensed.x;
    contact_ += q_c_;  // F
    full_.noalias() = delassus_.H().transpose() * contact_;
    full_ -= q;
    delassus_.SolveS(full_, &condensed.x);
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

  int dim_;
  std::vector<ContactNode> nodes_;
  bool normal_only_ = false;
  DelassusOperator delassus_;
  Eigen::MatrixXd inverse_delassus_;
  std::unique_ptr<ContactSystem> system_;
  Eigen::VectorXd q_c_, full_, contact_;  // (buffers: no allocation per step)
  NewtonStep newton_;
  ncp::Vector z_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeCondensedStep(const DynamicModel& model,
                                                 MassInverse* mass, double m_max,
                                                 const ncp::Options& ncp_options,
                                                 bool friction) {
  return std::make_unique<CondensedStep>(model, mass, m_max, ncp_options, friction);
}

}  // namespace contact::internal
