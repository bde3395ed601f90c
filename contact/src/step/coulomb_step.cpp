#include "step/coulomb_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "ncp/fc/error.hpp"

namespace contact::internal {

CoulombStep::CoulombStep(int dim, const Eigen::MatrixXd& W,
                         std::vector<ContactNode> nodes, double friction_coefficient,
                         const ncp::fc::Options& fc_options)
    : dim_(dim), nodes_(std::move(nodes)), options_(fc_options) {
  if (W.rows() != W.cols())
    throw std::invalid_argument("contact::CoulombStep: W must be square, got " +
                                std::to_string(W.rows()) + " x " +
                                std::to_string(W.cols()));
  apply_W_ = [W](const Eigen::VectorXd& F, Eigen::VectorXd* x) { x->noalias() = W * F; };
  Build(W.rows(), friction_coefficient);
  // W_fc is dense (every contact sees every other through the body): dense LU.
  if (options_.linear_solver == ncp::LinearSolverType::kAuto)
    options_.linear_solver = ncp::LinearSolverType::kDenseLU;
  W_fc_ = E_ * W * E_.transpose();
  W_fc_ = 0.5 * (W_fc_ + W_fc_.transpose());
  // The solver keeps W_fc's structure for the run; per step only its scale F / D and q
  // change.
  problem_.W = W_fc_.sparseView(0.0, 0.0);
  problem_.q = Eigen::VectorXd::Zero(problem_.size());
  solver_ = std::make_unique<ncp::fc::Solver>(problem_);
  problem_.W = ncp::SparseMatrix();  // (the solver holds it)
}

CoulombStep::CoulombStep(int dim, Operator apply_W, const Eigen::VectorXd& W_diagonal,
                         std::vector<ContactNode> nodes, double friction_coefficient,
                         const ncp::fc::Options& fc_options, ncp::fc::Reduction reduction)
    : dim_(dim),
      nodes_(std::move(nodes)),
      apply_W_(std::move(apply_W)),
      matrix_free_(true),
      options_(fc_options) {
  Build(W_diagonal.size(), friction_coefficient);
  diagonal_fc_ = E_.cwiseAbs2() * W_diagonal;
  operator_problem_.dimension = dim;
  operator_problem_.num_contacts = problem_.num_contacts;
  operator_problem_.mu = problem_.mu;
  operator_problem_.name = problem_.name;
  operator_problem_.reduction = std::move(reduction);
  // W' r' = (F / D) E W E' r' with the scales of the current step.
  operator_problem_.apply_W = [this](const Eigen::VectorXd& r, Eigen::VectorXd* Wr) {
    spread_.noalias() = E_.transpose() * r;
    apply_W_(spread_, &applied_);
    Wr->noalias() = E_ * applied_;
    *Wr *= operator_scale_;
  };
}

void CoulombStep::Build(Eigen::Index num_unknowns, double friction_coefficient) {
  const std::string who = "contact::CoulombStep: ";
  const int dim = dim_;
  if (dim != 2 && dim != 3)
    throw std::invalid_argument(who + "dim must be 2 or 3, got " + std::to_string(dim));
  if (!(friction_coefficient >= 0.0) || !std::isfinite(friction_coefficient))
    throw std::invalid_argument(who +
                                "the friction coefficient must be finite and >= 0, got " +
                                std::to_string(friction_coefficient));
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument(who + error);

  // E: row dim c + a holds e_c,a = (-n_c, t1_c[, t2_c])_a on the free components of node
  // c.
  const Eigen::Index num_contacts = static_cast<Eigen::Index>(nodes_.size());
  std::vector<Eigen::Triplet<double>> e;
  for (Eigen::Index c = 0; c < num_contacts; ++c) {
    const ContactNode& node = nodes_[static_cast<size_t>(c)];
    for (int b = 0; b < dim; ++b) {
      const int unknown = node.dofs[b];
      if (unknown < 0) continue;
      if (unknown >= num_unknowns)
        throw std::invalid_argument(who + "node " + std::to_string(node.node) +
                                    " has contact unknown " + std::to_string(unknown) +
                                    ", W has " + std::to_string(num_unknowns));
      e.emplace_back(dim * c, unknown, -node.normal(b));
      e.emplace_back(dim * c + 1, unknown, node.tangent1(b));
      if (dim == 3) e.emplace_back(dim * c + 2, unknown, node.tangent2(b));
    }
  }
  E_.resize(dim * num_contacts, num_unknowns);
  E_.setFromTriplets(e.begin(), e.end());
  transmits_.assign(static_cast<size_t>(E_.rows()), false);
  for (Eigen::Index col = 0; col < E_.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(E_, col); it; ++it)
      if (it.value() != 0.0) transmits_[static_cast<size_t>(it.row())] = true;
  for (Eigen::Index c = 0; c < num_contacts; ++c)
    transmits_[static_cast<size_t>(dim * c)] = true;

  problem_.dimension = dim;
  problem_.num_contacts = static_cast<int>(num_contacts);
  problem_.mu = Eigen::VectorXd::Constant(num_contacts, friction_coefficient);
  problem_.name = "contact step";
}

void CoulombStep::SolveScaled(const Eigen::VectorXd& q_fc, double F, double D,
                              double asked, double required, Eigen::VectorXd* r,
                              ncp::fc::Summary* summary) {
  const Eigen::Index num_contacts = problem_.num_contacts;
  q_ = q_fc / D;
  const Eigen::VectorXd& q = q_;
  // ncp::fc's measure is relative to 1 + ||q'||_2. Asked: the margin; required: the
  // tolerance - below it Newton stops where its steps no longer halve the error (the
  // round-off of W' r' + q', which grows with the contact set: at 484 nodes ~2e-16
  // relative, above the margin's 1e-15, and every step ran ~100 Newton steps through all
  // of the hybrid's attempts before this).
  const double q_norm = Norm(q);
  ncp::fc::Options& options = solve_options_;
  options = options_;
  options.tolerance = asked / (1.0 + q_norm);
  options.acceptable_tolerance = required / (1.0 + q_norm);
  if (matrix_free_) {
    operator_problem_.q = q;
    operator_problem_.diagonal = (F / D) * diagonal_fc_;
    operator_scale_ = F / D;
    operator_solver_.Solve(options, operator_problem_, r, summary);
  } else {
    solver_->ScaleW(F / D);
    solver_->SetQ(q);
    solver_->Solve(options, r, summary);
  }
  // A local tangent along a constrained axis (empty row of E) transmits no force to the
  // body: its component of r is arbitrary in the problem and set to 0. Then r_c onto C_mu
  // (moves r by at most the error reached): the forces applied are admissible, lambda >=
  // 0.
  for (Eigen::Index i = 0; i < r->size(); ++i)
    if (!transmits_[static_cast<size_t>(i)]) (*r)(i) = 0.0;
  for (Eigen::Index c = 0; c < num_contacts; ++c)
    ncp::fc::ProjectOnCone(problem_.mu(c), dim_, r->data() + dim_ * c);
}

double CoulombStep::Motion(const Eigen::VectorXd& r, const Eigen::VectorXd& x_free,
                           const Eigen::VectorXd& gap0, double F, double D,
                           Outcome* out) {
  out->force.noalias() = E_.transpose() * r;
  apply_W_(out->force, &out->contact.x);
  out->contact.x += x_free;
  local_.noalias() = E_ * out->contact.x;
  u_ = local_;
  for (Eigen::Index c = 0; c < problem_.num_contacts; ++c) u_(dim_ * c) += gap0(c);
  u_ /= D;
  r_scaled_ = r / F;
  return std::sqrt(operator_problem_.reduction.Sum(
      ncp::fc::NaturalMapSquaredResidual(dim_, problem_.mu, r_scaled_, u_)));
}

bool CoulombStep::Solve(const Eigen::VectorXd& x_free, const Eigen::VectorXd& gap0,
                        double force_scale, double displacement_scale, double tolerance,
                        Outcome* out) {
  const Eigen::Index num_contacts = problem_.num_contacts;
  const char* who = "contact::CoulombStep::Solve: ";
  if (x_free.size() != E_.cols() || gap0.size() != num_contacts)
    throw std::invalid_argument(
        who + std::string("x_free has " + std::to_string(x_free.size()) +
                          " entries (expected " + std::to_string(E_.cols()) + "), gap0 " +
                          std::to_string(gap0.size()) + " (expected " +
                          std::to_string(num_contacts) + ")"));
  if (!(force_scale > 0.0) || !(displacement_scale > 0.0) || !(tolerance > 0.0))
    throw std::invalid_argument(
        who + std::string("the scales F, D and the tolerance must be > 0"));
  const double F = force_scale, D = displacement_scale;

  Eigen::VectorXd& q_fc = q_fc_;
  q_fc.noalias() = E_ * x_free;
  for (Eigen::Index c = 0; c < num_contacts; ++c) q_fc(dim_ * c) += gap0(c);
  // Asked: ||e'||_2 <= kNaturalMapMargin tolerance, required: <= tolerance (each + the
  // round-off of u', 16 ulp of its terms, as ContactSystem). The margin is best effort
  // (round-off of W' r' can stop Newton short of it): the step is solved when the
  // required bound holds at the returned (projected) r, recomputed.
  const double roundoff =
      ContactSystem::kRoundoffUlps * std::numeric_limits<double>::epsilon() *
      operator_problem_.reduction.Max(q_fc.size() ? q_fc.lpNorm<Eigen::Infinity>()
                                                  : 0.0) /
      D;
  const double asked = kNaturalMapMargin * tolerance + roundoff,
               required = tolerance + roundoff;
  Eigen::VectorXd& r = r_;  // system units
  double residual = std::numeric_limits<double>::infinity();
  // The start: the previous step's forces. One product with W gives the motion and the
  // residual at them; a step they already solve (no contact change) is done - the
  // solver's own check of its start point, without its per-solve set-up (W's scale, q).
  // (Distributed: only if every part has them - a part without contacts always has.)
  if (operator_problem_.reduction.Max(r_previous_.size() == q_fc.size() ? 0.0 : 1.0) ==
      0.0) {
    r = r_previous_;
    residual = Motion(r, x_free, gap0, F, D, out);
  } else {
    r.setZero(q_fc.size());
  }
  if (residual <= asked) {
    SolvedAtStart(residual / (1.0 + Norm(q_fc) / D), &out->summary);
  } else {
    r /= F;  // the solver's unknowns r' = r / F
    SolveScaled(q_fc, F, D, asked, required, &r, &out->summary);
    r *= F;
    residual = Motion(r, x_free, gap0, F, D, out);
  }
  out->natural_map_residual = residual;
  const bool converged = residual <= required;
  if (converged) r_previous_ = r;

  // The contact forces, gaps and slips: r, u = E x_c + (gap0, 0, 0) (Motion).
  ContactSystem::Result& contact = out->contact;
  const Eigen::VectorXd& local = local_;
  contact.normal_force.resize(num_contacts);
  contact.gap.resize(num_contacts);
  contact.tangent_force.resize(dim_ - 1, num_contacts);
  contact.slip.resize(dim_ - 1, num_contacts);
  for (Eigen::Index c = 0; c < num_contacts; ++c) {
    contact.normal_force(c) = r(dim_ * c);
    contact.gap(c) = gap0(c) + local(dim_ * c);
    for (int a = 1; a < dim_; ++a) {
      contact.tangent_force(a - 1, c) = r(dim_ * c + a);
      contact.slip(a - 1, c) = local(dim_ * c + a);
    }
  }
  return converged;
}

void CoulombStep::SolvedAtStart(double error, ncp::fc::Summary* summary) const {
  summary->termination = ncp::fc::Termination::kConverged;
  summary->message = "start point";  // (short: no allocation)
  summary->iterations = summary->attempts = summary->backtracks = 0;
  summary->gauss_seidel_sweeps = summary->fallback_sweeps = 0;
  summary->linear_solver_failures = summary->levenberg_marquardt_steps = 0;
  summary->symbolic_factorizations = 0;
  summary->krylov_iterations = matrix_free_ ? 0 : -1;
  summary->operator_applications = matrix_free_ ? 0 : -1;
  summary->initial_error = summary->final_error = error;
  summary->total_time_s = 0.0;
  summary->trace.clear();
}

void CoulombStep::RestorePreviousForces(const Eigen::VectorXd& r) {
  if (r.size() != 0 && r.size() != E_.rows())
    throw std::invalid_argument("the warm start (previous contact forces) has " +
                                std::to_string(r.size()) + " entries, this run has " +
                                std::to_string(E_.rows()) + " local components");
  r_previous_ = r;
}

double CoulombStep::Norm(const Eigen::VectorXd& v) const {
  return std::sqrt(operator_problem_.reduction.Sum(v.squaredNorm()));
}

}  // namespace contact::internal
