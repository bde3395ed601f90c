#include "contact/dynamics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include "contact/convex_qp.hpp"
#include "contact/static_contact.hpp"

namespace contact {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
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

// Exact elimination of the non-contact dofs from one step (StepMethod::kCondensed).
// With H selecting the contact dofs (global components), the step equation
//     S du + q = H' F          (F: contact force components at the contact dofs)
// gives du = S^-1 (H' F - q) and, on the contact dofs, x_c = H du = W F - H S^-1 q with the
// Delassus operator W = H S^-1 H'. Hence F = W^-1 x_c + W^-1 H S^-1 q: a ContactSystem over
// the contact dofs with S_c = W^-1 and q_c = W^-1 H S^-1 q, whose solution is the same as
// that of the full system. W is formed once from n_c solves with the Cholesky factor of S.
class CondensedStep {
 public:
  CondensedStep(int dim, const Eigen::SparseMatrix<double>& S, const std::vector<ContactNode>& nodes)
      : n_(S.rows()) {
    factor_.compute(S);
    if (factor_.info() != Eigen::Success)
      throw std::invalid_argument("contact::RunDynamics: the mass matrix is not positive definite "
                                  "(Cholesky failed), the condensed step needs it");
    // Contact dofs, and the nodes renumbered onto them.
    std::vector<ContactNode> condensed = nodes;
    for (ContactNode& node : condensed)
      for (int a = 0; a < dim; ++a) {
        if (node.dofs[a] < 0) continue;
        const int position = static_cast<int>(contact_dofs_.size());
        contact_dofs_.push_back(node.dofs[a]);
        node.dofs[a] = position;
      }
    const auto nc = static_cast<Eigen::Index>(contact_dofs_.size());
    Eigen::MatrixXd W(nc, nc);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n_), column(n_);
    for (Eigen::Index j = 0; j < nc; ++j) {
      e(contact_dofs_[static_cast<size_t>(j)]) = 1.0;
      column = factor_.solve(e);
      e(contact_dofs_[static_cast<size_t>(j)]) = 0.0;
      for (Eigen::Index i = 0; i < nc; ++i) W(i, j) = column(contact_dofs_[static_cast<size_t>(i)]);
    }
    W = 0.5 * (W + W.transpose());
    const Eigen::LLT<Eigen::MatrixXd> llt(W);
    if (llt.info() != Eigen::Success)
      throw std::invalid_argument("contact::RunDynamics: the Delassus operator H M^-1 H' is not "
                                  "positive definite; use the full step");
    inverse_delassus_ = llt.solve(Eigen::MatrixXd::Identity(nc, nc));
    system_ = std::make_unique<ContactSystem>(dim, inverse_delassus_.sparseView(0.0, 0.0), condensed);
    rhs_.resize(n_);
  }

  ContactSystem& system() { return *system_; }

  /// x_c = H x.
  Eigen::VectorXd Restrict(const Eigen::VectorXd& x) const {
    Eigen::VectorXd out(static_cast<Eigen::Index>(contact_dofs_.size()));
    for (size_t i = 0; i < contact_dofs_.size(); ++i) out(static_cast<Eigen::Index>(i)) = x(contact_dofs_[i]);
    return out;
  }

  /// Data of one step: q and u0 on all free dofs.
  void Update(const Eigen::VectorXd& q, const Eigen::VectorXd& u0, const Eigen::VectorXd& bound) {
    q_c_ = inverse_delassus_ * Restrict(factor_.solve(q));  // W^-1 H S^-1 q
    system_->Update(q_c_, Restrict(u0), bound);
  }

  /// The full result from the condensed one: du = S^-1 (H' F - q), F = S_c x_c + q_c, with
  /// the q of the last Update().
  ContactSystem::Result Expand(ContactSystem::Result condensed, const Eigen::VectorXd& q) {
    const Eigen::VectorXd F = inverse_delassus_ * condensed.x + q_c_;
    rhs_ = -q;
    for (size_t i = 0; i < contact_dofs_.size(); ++i) rhs_(contact_dofs_[i]) += F(static_cast<Eigen::Index>(i));
    condensed.x = factor_.solve(rhs_);
    return condensed;
  }

 private:
  Eigen::Index n_;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>> factor_;
  std::vector<int> contact_dofs_;
  Eigen::MatrixXd inverse_delassus_;
  std::unique_ptr<ContactSystem> system_;
  Eigen::VectorXd rhs_, q_c_;
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
    bool diagonal = true;
    for (int col = 0; col < S.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(S, col); it; ++it)
        diagonal &= it.row() == it.col() || it.value() == 0.0;
    diagonal_ = S.diagonal();
    if (!diagonal || !(diagonal_.minCoeff() > 0.0))
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
  ContactSystem::Result Solve(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
                              const Eigen::VectorXd& bound) const {
    const auto N = static_cast<Eigen::Index>(nodes_.size());
    ContactSystem::Result out;
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
    return out;
  }

 private:
  int dim_;
  std::vector<ContactNode> nodes_;
  Eigen::VectorXd diagonal_;
};

}  // namespace

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
  }
  return "unknown";
}

CriticalTimeStep EstimateCriticalTimeStep(const Eigen::SparseMatrix<double>& K,
                                          const Eigen::SparseMatrix<double>& M,
                                          double relative_tolerance, int max_iterations) {
  if (K.rows() != M.rows() || K.cols() != M.cols() || K.rows() != K.cols())
    throw std::invalid_argument("EstimateCriticalTimeStep: K and M must be square of equal size");
  CriticalTimeStep out;
  if (K.rows() == 0) return out;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mass(M);
  if (mass.info() != Eigen::Success)
    throw std::invalid_argument("EstimateCriticalTimeStep: the mass matrix is not positive definite");
  // Power iteration on M^-1 K with Rayleigh quotient lambda = x'Kx / x'Mx. The start vector
  // alternates in sign node by node so it is rich in high-frequency modes.
  Eigen::VectorXd x(K.rows());
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = ((i / 2) % 2 == 0 ? 1.0 : -1.0) * (1.0 + 1e-3 * static_cast<double>(i % 7));
  double lambda = 0.0;
  int stable_count = 0;
  Eigen::VectorXd Kx = K * x, y(x.size()), Ky(x.size());
  for (int it = 1; it <= max_iterations; ++it) {
    y = mass.solve(Kx);
    Ky.noalias() = K * y;  // reused as K x of the next iterate
    const double num = y.dot(Ky), den = y.dot(M * y);
    if (!(den > 0.0)) {  // K x = 0: no elastic stiffness along the iterate (e.g. K = 0)
      lambda = 0.0;
      out.converged = true;
      break;
    }
    const double next = num / den;
    Kx = Ky / std::sqrt(den);  // x = y / sqrt(y'My) is only needed through K x
    out.iterations = it;
    if (std::abs(next - lambda) <= relative_tolerance * next) {
      if (++stable_count >= 5) {
        lambda = next;
        out.converged = true;
        break;
      }
    } else {
      stable_count = 0;
    }
    lambda = next;
  }
  out.omega_max = std::sqrt(lambda);
  out.dt_crit = lambda > 0.0 ? 2.0 / out.omega_max : std::numeric_limits<double>::infinity();
  return out;
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
  if (!(options.end_time >= options.start_time))
    throw std::invalid_argument(who + "end_time must be >= start_time");
  if (!(options.friction_coefficient >= 0.0))
    throw std::invalid_argument(who + "friction_coefficient must be >= 0, got " +
                                std::to_string(options.friction_coefficient));
  if ((options.solver == StepSolver::kIpopt || options.compare_with_ipopt) &&
      options.friction_coefficient > 0.0)
    throw std::invalid_argument(who + "the Ipopt step solver handles frictionless contact only "
                                      "(friction_coefficient = " +
                                std::to_string(options.friction_coefficient) + ")");
  if (options.initial_state == InitialState::kPrescribed &&
      (options.u0.size() != n || options.v0.size() != n))
    throw std::invalid_argument(who + "prescribed u0 and v0 must have size " + std::to_string(n));

  DynamicSummary summary;
  const double dt = options.dt;

  // Stability: central differences need dt <= 2 / omega_max.
  const CriticalTimeStep crit = EstimateCriticalTimeStep(model.K, model.M);
  summary.critical_time_step = crit.dt_crit;
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
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mass(model.M);
    const Eigen::VectorXd a0 = mass.solve(f - model.K * u);
    u_previous = u - dt * options.v0 + 0.5 * dt * dt * a0;
  }

  // The step system: S = M / Mmax is the same every step.
  const double m_max = MaxAbsEntry(model.M);
  const double force_scale = m_max / (dt * dt);  // system units -> newtons
  const Eigen::SparseMatrix<double> S = model.M / m_max;
  ContactSystem system(model.dim, S, model.contact_nodes);
  std::unique_ptr<CondensedStep> condensed;
  std::unique_ptr<ExplicitStep> explicit_step;
  if (options.solver != StepSolver::kIpopt) {
    if (options.step_method == StepMethod::kCondensed)
      condensed = std::make_unique<CondensedStep>(model.dim, S, model.contact_nodes);
    if (options.step_method == StepMethod::kExplicit)
      explicit_step = std::make_unique<ExplicitStep>(model.dim, S, model.contact_nodes);
  }
  ncp::Options ncp_options = options.ncp;
  ncp_options.ncp_function = FunctionOf(options.solver);
  ncp::Solver solver(ncp_options);

  // Ipopt reference: rows n_c . du_c <= s_c - n_c . u^k, i.e. G = Y R.
  Eigen::SparseMatrix<double> G;
  if (options.solver == StepSolver::kIpopt || options.compare_with_ipopt) {
    const RestrictionMaps maps = MakeRestrictionMaps(model.dim, static_cast<int>(n), model.contact_nodes);
    G = maps.Y * maps.R;
  }
  Eigen::VectorXd gap0(static_cast<Eigen::Index>(model.contact_nodes.size()));
  for (size_t c = 0; c < model.contact_nodes.size(); ++c) gap0(static_cast<Eigen::Index>(c)) = model.contact_nodes[c].gap;

  // Shadow energy of central differences at k = -1/2 (conserved exactly without forces):
  // E = 1/2 v' M v + 1/2 (u^k)' K u^{k+1}. It cannot reveal an instability (the cross term
  // turns negative), so the blow-up guard uses the positive 1/2 v' M v + 1/2 u' K u.
  auto shadow_energy = [&](const Eigen::VectorXd& u_k, const Eigen::VectorXd& u_next,
                           double* kinetic) {
    const Eigen::VectorXd v = (u_next - u_k) / dt;
    *kinetic = 0.5 * v.dot(model.M * v);
    return *kinetic + 0.5 * u_k.dot(model.K * u_next);
  };
  double kinetic0;
  const double energy0 = shadow_energy(u_previous, u, &kinetic0);
  const double strain0 = 0.5 * u.dot(model.K * u);
  double external_work = 0.0, normal_work = 0.0, friction_dissipation = 0.0, work_scale = 0.0;

  Eigen::VectorXd du = u - u_previous;  // start guess of the first step
  Eigen::MatrixXd friction_previous;     // local friction forces of the previous step
  Eigen::VectorXd Q(n), q(n), r(n), u_next(n), bound;
  const long num_steps = std::lround(std::ceil((options.end_time - options.start_time) / dt - 1e-3));
  double last_progress = 0.0;
  summary.records.reserve(static_cast<size_t>(std::max(0L, num_steps)));

  for (long k = 0; k < num_steps; ++k) {
    const auto step_start = Clock::now();
    const double t_k = options.start_time + static_cast<double>(k) * dt;
    model.load(t_k, &f);
    // Q^k = M (u^{k-1} - u^k) / dt^2 + K u^k - f^k   (eq. 73), scaled by dt^2 / Mmax (eq. 81).
    Q = model.M * (u_previous - u) / (dt * dt) + model.K * u - f;
    q = Q / force_scale;
    if (options.friction_coefficient > 0.0)
      bound = options.friction_coefficient * lambda_physical.cwiseMax(0.0) / force_scale;
    else
      bound.resize(0);
    if (condensed) condensed->Update(q, u, bound);
    else if (!explicit_step) system.Update(q, u, bound);

    StepRecord rec;
    rec.step = static_cast<int>(k + 1);
    rec.time = t_k + dt;
    // Frictionless reference: the step as the convex QP
    //   min 1/2 du' S du + q' du  s.t.  n_c . du_c <= s_c - n_c . u^k_c,
    // whose multipliers are the normal reactions (system units).
    auto solve_qp = [&]() {
      ConvexQpOptions qp_options;
      qp_options.tolerance = options.ipopt_tolerance;
      return SolveConvexQpIpopt(S, q, G, gap0 - G * u, du, qp_options);
    };
    ContactSystem::Result contact;
    bool ok;
    if (options.solver == StepSolver::kIpopt) {
      const ConvexQpResult qp = solve_qp();
      ok = qp.status == ConvexQpStatus::kSolved;
      rec.solver_status = ok ? "converged" : qp.message;
      rec.newton_iterations = qp.iterations;
      contact = system.Extract(system.StartPoint(qp.x));
      contact.normal_force = qp.multipliers;
    } else if (explicit_step) {
      contact = explicit_step->Solve(q, u, bound);
      ok = contact.x.allFinite();
      rec.solver_status = ok ? "converged" : "non-finite values in the explicit step";
    } else {
      ContactSystem& step_system = condensed ? condensed->system() : system;
      ncp::Vector z = step_system.StartPoint(condensed ? condensed->Restrict(du) : du, friction_previous);
      ncp::Summary s;
      solver.Solve(step_system, &z, &s);
      ok = s.IsSolutionUsable();
      rec.solver_status = ok ? "converged" : s.message;
      rec.newton_iterations = s.iterations;
      rec.jacobian_evaluations = s.jacobian_evaluations;
      rec.residual_evaluations = s.residual_evaluations;
      contact = condensed ? condensed->Expand(step_system.Extract(z), q) : step_system.Extract(z);
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
    friction_previous = contact.tangent_force;
    u_next = u + du;

    // Contact forces r^{k+1} = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k - f^k, in newtons,
    // and the work increments over (u^{k+1} - u^{k-1}) / 2.
    r = model.M * du / (dt * dt) + Q;
    const Eigen::VectorXd half_span = 0.5 * (u_next - u_previous);
    const double dw_ext = f.dot(half_span);
    external_work += dw_ext;
    work_scale += std::abs(dw_ext);
    double dw_normal = 0.0;
    for (size_t c = 0; c < model.contact_nodes.size(); ++c) {
      const ContactNode& node = model.contact_nodes[c];
      Eigen::Vector3d rc = Eigen::Vector3d::Zero(), sc = Eigen::Vector3d::Zero();
      for (int a = 0; a < model.dim; ++a) {
        if (node.dofs[a] < 0) continue;  // constrained component: no motion, no work
        rc(a) = r(node.dofs[a]);
        sc(a) = half_span(node.dofs[a]);
      }
      const double rn = rc.dot(node.normal), sn = sc.dot(node.normal);
      dw_normal += rn * sn;
      friction_dissipation -= rc.dot(sc) - rn * sn;
    }
    normal_work += dw_normal;

    // Bookkeeping of the record.
    const double shadow = shadow_energy(u, u_next, &rec.kinetic);
    rec.strain = 0.5 * u_next.dot(model.K * u_next);
    rec.external_work = external_work;
    rec.normal_contact_work = normal_work;
    rec.friction_dissipation = friction_dissipation;
    rec.energy_balance_error =
        shadow - energy0 - external_work - normal_work + friction_dissipation;
    const Eigen::VectorXd lambda_now = force_scale * contact.normal_force;
    rec.normal_force_sum = lambda_now.sum();
    for (Eigen::Index c = 0; c < contact.tangent_force.cols(); ++c)
      rec.tangent_force_sum += force_scale * contact.tangent_force.col(c).norm();
    rec.max_penetration = contact.gap.size() ? std::max(0.0, -contact.gap.minCoeff()) : 0.0;
    rec.active_nodes = static_cast<int>((lambda_now.array() > 0.0).count());
    rec.seconds = Seconds(step_start);
    summary.max_penetration = std::max(summary.max_penetration, rec.max_penetration);
    summary.energy_balance_error = std::max(summary.energy_balance_error, std::abs(rec.energy_balance_error));
    summary.steps = rec.step;
    summary.records.push_back(rec);
    if (options.on_step) options.on_step(rec, u_next, contact, force_scale);

    lambda_physical = lambda_now;
    u_previous = u;
    u = u_next;

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
  if (summary.status == DynamicStatus::kNotRun) {
    summary.status = DynamicStatus::kCompleted;
    summary.message = "completed " + std::to_string(summary.steps) + " steps";
  }
  summary.u = u;
  summary.seconds = Seconds(start);
  return summary;
}

}  // namespace contact
