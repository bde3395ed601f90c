#include "contact/bodies_contact.hpp"

#include <algorithm>
#include <cfloat>
#include <memory>
#include <stdexcept>

#include "mortar/mortar_friction.hpp"
#include "mortar/mortar_problem.hpp"

namespace contact {
namespace {

void CheckSizes(const BodySystem& system, const MortarConstraints& constraints,
                const Vector& f, const char* where) {
  if (constraints.B.cols() != system.NumDofs() || f.size() != system.NumDofs())
    throw std::invalid_argument(
        std::string(where) + ": the system has " + std::to_string(system.NumDofs()) +
        " dofs, B has " + std::to_string(constraints.B.cols()) +
        " columns and the load " + std::to_string(f.size()) + " entries");
}

double MaxDiagonal(const SparseMatrix& A) {
  double largest = 0.0;
  for (int i = 0; i < A.rows(); ++i) largest = std::max(largest, std::abs(A.coeff(i, i)));
  return largest;
}

/// max of the infinity norms, or the smallest positive double if all are 0: the scale
/// of the rows of one solve [units of x].
double DisplacementScale(std::initializer_list<double> norms) {
  double scale = DBL_MIN;
  for (double v : norms) scale = std::max(scale, v);
  return scale;
}

/// Sum of the forces of the constraints of each interface [N].
std::vector<double> InterfaceForces(const MortarConstraints& constraints,
                                    const Vector& force) {
  int interfaces = 0;
  for (int i : constraints.interface) interfaces = std::max(interfaces, i + 1);
  std::vector<double> sum(static_cast<size_t>(interfaces), 0.0);
  for (int j = 0; j < constraints.NumConstraints(); ++j)
    sum[static_cast<size_t>(constraints.interface[static_cast<size_t>(j)])] += force(j);
  return sum;
}

bool HasFriction(const MortarConstraints& constraints) {
  return constraints.friction.size() > 0 && constraints.friction.maxCoeff() > 0.0;
}

/// The contact solve of one step: frictionless by ncp (mortar_problem.hpp), with
/// friction by ncp::fc (mortar_friction.hpp); the slip rows measure the increment.
class StepContactSolve {
 public:
  StepContactSolve(const SparseMatrix& S, const SparseMatrix& B, const SparseMatrix& T,
                   const Vector& mu, bool friction)
      : problem_(S, B),
        z_(ncp::Vector::Zero(problem_.NumVariables())),
        no_slip_(Vector::Zero(B.rows())) {
    if (friction)
      friction_ = std::make_unique<internal::MortarFrictionSolve>(S, B, T, mu);
  }

  /// Solves from the previous step's forces (and increment x0, frictionless); out: x,
  /// lambda, tau; report and iterations of the solve. Returns whether it converged.
  bool Solve(const Vector& q, const Vector& gap_base, const Vector& x0, double scale,
             const ncp::Options& ncp, internal::MortarFrictionSolve::Outcome* out,
             std::string* report, int* iterations) {
    if (friction_) {
      const bool solved =
          friction_->Solve(q, gap_base, no_slip_, scale, ncp.tolerance, out);
      *report = out->summary.BriefReport();
      *iterations = out->summary.iterations;
      return solved;
    }
    const Eigen::Index n = x0.size();
    problem_.Update(q, gap_base, scale);
    z_.head(n) = x0;
    ncp::Summary solve;
    ncp::Solve(ncp, problem_, &z_, &solve);
    *report = solve.BriefReport();
    *iterations = solve.iterations;
    out->x = z_.head(n);
    out->lambda = z_.tail(no_slip_.size());
    out->tau = no_slip_;
    return solve.IsSolutionUsable();
  }

 private:
  internal::MortarContactProblem problem_;
  ncp::Vector z_;
  Vector no_slip_;
  std::unique_ptr<internal::MortarFrictionSolve> friction_;
};

}  // namespace

BodiesStaticResult SolveBodiesStatic(const BodySystem& system,
                                     const MortarConstraints& constraints,
                                     const Vector& f, const ncp::Options& ncp) {
  CheckSizes(system, constraints, f, "contact::SolveBodiesStatic");
  const DofMap& dofs = system.dofs;
  const SparseMatrix K = dofs.RestrictMatrix(system.stiffness);
  const double k = MaxDiagonal(K);
  const SparseMatrix B = constraints.B * dofs.RestrictionMatrix().transpose();
  const Vector q = -dofs.RestrictLoad(system.stiffness, f) / k;
  const Vector gap_base =
      constraints.initial_gap + constraints.B * dofs.PrescribedValues();
  const double scale = DisplacementScale(
      {q.lpNorm<Eigen::Infinity>(), dofs.PrescribedValues().lpNorm<Eigen::Infinity>()});
  BodiesStaticResult result;
  result.tangential_force = Vector::Zero(B.rows());
  if (HasFriction(constraints)) {
    const SparseMatrix T = constraints.T * dofs.RestrictionMatrix().transpose();
    internal::MortarFrictionSolve solve(K / k, B, T, constraints.friction);
    internal::MortarFrictionSolve::Outcome out;
    result.converged = solve.Solve(q, gap_base, constraints.T * dofs.PrescribedValues(),
                                   scale, ncp.tolerance, &out);
    result.message = out.summary.BriefReport();
    result.newton_iterations = out.summary.iterations;
    result.u = dofs.Expand(out.x);
    result.normal_force = out.lambda * k;
    result.tangential_force = out.tau * k;
  } else {
    internal::MortarContactProblem problem(K / k, B);
    problem.Update(q, gap_base, scale);
    ncp::Vector z = ncp::Vector::Zero(problem.NumVariables());
    ncp::Solve(ncp, problem, &z, &result.summary);
    result.converged = result.summary.IsSolutionUsable();
    result.message = result.summary.BriefReport();
    result.newton_iterations = result.summary.iterations;
    result.u = dofs.Expand(z.head(K.rows()));
    result.normal_force = z.tail(B.rows()) * k;
  }
  result.pressure = result.normal_force.cwiseQuotient(constraints.weight);
  result.slip = constraints.T * result.u;
  result.gap = constraints.initial_gap + constraints.B * result.u;
  return result;
}

const char* ToString(BodiesDynamicStatus status) {
  switch (status) {
    case BodiesDynamicStatus::kNotRun:
      return "not-run";
    case BodiesDynamicStatus::kCompleted:
      return "completed";
    case BodiesDynamicStatus::kSolverFailure:
      return "solver-failure";
  }
  return "unknown";
}

BodiesDynamicSummary RunBodiesDynamics(const BodySystem& system,
                                       const MortarConstraints& constraints,
                                       const Vector& f, const Vector& u0,
                                       const Vector& v0,
                                       const BodiesDynamicOptions& options) {
  CheckSizes(system, constraints, f, "contact::RunBodiesDynamics");
  if (u0.size() != system.NumDofs() || v0.size() != system.NumDofs())
    throw std::invalid_argument("contact::RunBodiesDynamics: u0 and v0 need " +
                                std::to_string(system.NumDofs()) + " entries");
  if (!(options.time_step > 0.0) || options.steps < 1)
    throw std::invalid_argument(
        "contact::RunBodiesDynamics: time_step = " + std::to_string(options.time_step) +
        " (need > 0), steps = " + std::to_string(options.steps) + " (need >= 1)");
  const DofMap& dofs = system.dofs;
  const double dt = options.time_step;
  const SparseMatrix M_full =
      options.lumped_mass ? SparseMatrix(system.lumped_mass.asDiagonal()) : system.mass;
  const SparseMatrix M = dofs.RestrictMatrix(M_full);
  const double m = MaxDiagonal(M);
  const SparseMatrix P = dofs.RestrictionMatrix();
  const SparseMatrix B = constraints.B * P.transpose();
  StepContactSolve contact(M / m, B, constraints.T * P.transpose(), constraints.friction,
                           HasFriction(constraints));

  Vector u = dofs.Expand(dofs.RestrictVector(u0));
  Vector u_prev = u - dt * dofs.ExpandHomogeneous(dofs.RestrictVector(v0));
  internal::MortarFrictionSolve::Outcome out;
  BodiesDynamicSummary summary;
  summary.records.reserve(static_cast<size_t>(options.steps));
  for (int step = 0; step < options.steps; ++step) {
    const Vector Ku = system.stiffness * u;
    const Vector increment = u - u_prev;
    const Vector q = -P * (M_full * increment + dt * dt * (f - Ku)) / m;
    const Vector gap_base = constraints.initial_gap + constraints.B * u;
    const double scale = DisplacementScale(
        {q.lpNorm<Eigen::Infinity>(), increment.lpNorm<Eigen::Infinity>()});
    std::string report;
    int iterations = 0;
    // start: the previous increment and forces
    const bool solved = contact.Solve(q, gap_base, P * increment, scale, options.ncp,
                                      &out, &report, &iterations);
    if (!solved) {
      summary.status = BodiesDynamicStatus::kSolverFailure;
      summary.message = "step " + std::to_string(step + 1) + ": " + report;
      break;
    }
    const Vector u_next = u + P.transpose() * out.x;
    const Vector force = out.lambda * (m / (dt * dt));
    const Vector gap = gap_base + B * out.x;
    if (gap.size() > 0)
      summary.max_penetration = std::max(summary.max_penetration, -gap.minCoeff());
    BodiesStepRecord record;
    record.time = (step + 1) * dt;
    record.interface_force = InterfaceForces(constraints, force);
    record.interface_tangential_force =
        InterfaceForces(constraints, out.tau * (m / (dt * dt)));
    const Vector v = (u_next - u) / dt;
    record.energy = 0.5 * v.dot(M_full * v) + 0.5 * u.dot(system.stiffness * u_next);
    record.newton_iterations = iterations;
    summary.records.push_back(record);
    if (options.on_step) options.on_step(step + 1, u_next, force);
    u_prev = u;
    u = u_next;
  }
  if (summary.status == BodiesDynamicStatus::kNotRun) {
    summary.status = BodiesDynamicStatus::kCompleted;
    summary.message =
        std::to_string(options.steps) + " steps, every contact solve converged";
  }
  summary.u = u;
  summary.velocity = (u - u_prev) / dt;
  return summary;
}

}  // namespace contact
