// StepMethod::kCondensed: the step over the contact unknowns only, the other dofs eliminated
// exactly with M^-1 (a CHOLMOD factor or the lumped diagonal), solved by semismooth Newton.
#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>

#include "newton_step.hpp"
#include "step_method.hpp"

namespace contact::internal {
namespace {

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
class CondensedStep : public StepAlgorithm {
 public:
  /// S = M / m_max: S^-1 = m_max M^-1 through `mass` (which must outlive this).
  CondensedStep(const DynamicModel& model, MassInverse* mass, double m_max,
                const ncp::Options& ncp_options, bool friction)
      : dim_(model.dim), nodes_(model.contact_nodes), mass_(mass), m_max_(m_max),
        newton_(ncp_options, friction) {
    const int dim = model.dim;
    const Eigen::Index n = model.M.rows();
    const std::vector<ContactNode>& nodes = model.contact_nodes;
    const bool frictionless = !friction;
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

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    Update(step.q, step.u, step.bound);
    // Forces to tolerance F, displacements to tolerance D (in system units).
    system_->SetResidualScales(step.scales.force / step.force_scale, step.scales.displacement);
    const StepOutcome out = newton_.Solve(system_.get(), Restrict(step.guess), &z_);
    *result = Expand(system_->Extract(z_), step.q);
    if (out.ok) newton_.KeepFriction(*result);
    return out;
  }

 private:
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
  NewtonStep newton_;
  ncp::Vector z_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeCondensedStep(const DynamicModel& model, MassInverse* mass,
                                                 double m_max, const ncp::Options& ncp_options,
                                                 bool friction) {
  return std::make_unique<CondensedStep>(model, mass, m_max, ncp_options, friction);
}

}  // namespace contact::internal
