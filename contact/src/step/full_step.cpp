// StepMethod::kFull: the step's ContactSystem over all free dofs, as the thesis (eq. 82,
// 90, 94), solved by semismooth Newton.
#include "step/newton_step.hpp"
#include "step/step_method.hpp"

namespace contact::internal {
namespace {

class FullStep : public StepAlgorithm {
 public:
  FullStep(const DynamicModel& model, double m_max, const ncp::Options& ncp_options,
           bool friction)
      : dim_(model.dim),
        system_(model.dim, model.M / m_max, model.contact_nodes),
        newton_(ncp_options, friction) {}

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    system_.SetGaps(step.gap);
    system_.Update(step.q, step.u, step.bound);
    // Forces to tolerance F, displacements to tolerance D (in system units).
    system_.SetResidualScales(step.scales.force / step.force_scale,
                              step.scales.displacement);
    const StepOutcome out = newton_.Solve(&system_, step.guess, &z_);
    *result = system_.Extract(z_);
    if (out.ok) newton_.KeepFriction(*result);
    return out;
  }

  Eigen::MatrixXd WarmStart() const override { return newton_.kept_friction(); }
  void SetWarmStart(const Eigen::MatrixXd& warm_start) override {
    newton_.RestoreFriction(warm_start, dim_ - 1,
                            static_cast<Eigen::Index>(system_.nodes().size()));
  }

 private:
  int dim_;
  ContactSystem system_;  // S = M / m_max
  NewtonStep newton_;
  ncp::Vector z_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeFullStep(const DynamicModel& model, double m_max,
                                            const ncp::Options& ncp_options,
                                            bool friction) {
  return std::make_unique<FullStep>(model, m_max, ncp_options, friction);
}

}  // namespace contact::internal
