#include "contact/static_contact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "cholmod_factor.hpp"
#include "contact/convex_qp.hpp"
#include "ncp/blas_threads.hpp"

namespace contact {
namespace {

double MaxDiagonal(const Eigen::SparseMatrix<double>& K) {
  double k = 0.0;
  for (Eigen::Index i = 0; i < K.rows(); ++i) k = std::max(k, std::abs(K.coeff(i, i)));
  if (!(k > 0.0))
    throw std::invalid_argument("contact: the stiffness matrix has a zero diagonal");
  return k;
}

/// Throws std::invalid_argument on a Tresca bound of the wrong size, negative or not
/// finite, or a negative Coulomb coefficient.
void CheckFrictionOptions(Eigen::Index num_nodes, const StaticContactOptions& options) {
  if (options.friction == FrictionLaw::kTresca &&
      options.tresca_bound.size() != num_nodes)
    throw std::invalid_argument(
        "SolveStaticContact: tresca_bound needs one value per contact node (" +
        std::to_string(num_nodes) + "), got " +
        std::to_string(options.tresca_bound.size()));
  if (options.friction == FrictionLaw::kTresca)
    for (Eigen::Index c = 0; c < num_nodes; ++c)
      if (!(options.tresca_bound(c) >= 0.0) || !std::isfinite(options.tresca_bound(c)))
        throw std::invalid_argument("SolveStaticContact: tresca_bound[" +
                                    std::to_string(c) +
                                    "] must be finite and >= 0 N, got " +
                                    std::to_string(options.tresca_bound(c)));
  if (options.friction == FrictionLaw::kCoulomb && !(options.friction_coefficient >= 0.0))
    throw std::invalid_argument(
        "SolveStaticContact: friction_coefficient must be >= 0, got " +
        std::to_string(options.friction_coefficient));
}

/// Scales in system units (forces / k, displacements): the largest nodal load or Tresca
/// bound (bound in system units), and at least the displacement it causes at the stiffest
/// dof or the largest initial penetration - every row is solved to ncp.tolerance of them
/// (plus round-off).
struct StaticScales {
  double force, displacement;
};
StaticScales ComputeScales(const Eigen::VectorXd& f, const Eigen::VectorXd& bound,
                           double k, const std::vector<ContactNode>& nodes) {
  double force = std::max(f.lpNorm<Eigen::Infinity>(),
                          bound.size() ? k * bound.lpNorm<Eigen::Infinity>() : 0.0) /
                 k;
  double displacement = force;
  for (const ContactNode& node : nodes) displacement = std::max(displacement, -node.gap);
  if (force == 0.0) force = displacement;
  if (force == 0.0) force = displacement = 1.0;  // no load, no penetration: u = 0
  return {force, displacement};
}

/// The solution of one solve in newtons and metres (k: the stiffness scale of S = K / k).
void StoreSolution(const ContactSystem::Result& r, double k,
                   StaticContactResult* result) {
  result->u = r.x;
  result->normal_force = k * r.normal_force;
  result->tangent_force = k * r.tangent_force;
  result->gap = r.gap;
}

/// The closed start (StaticStart::kClosed): u minimizing 1/2 u'Ku - f'u subject to
/// n_c . u_c = s_c at every node. In the local components y = R u (MakeRestrictionMaps)
/// the constraints fix the normal ones, Y y = s; the others, w = P y (P: the rows of the
/// identity at the non-normal local dofs), solve
///     (P R K R' P') w = P R (f - K R' Y' s),     u = R' (Y' s + P' w).
/// Empty when that matrix is not positive definite.
Eigen::VectorXd ClosedStart(int dim, const Eigen::SparseMatrix<double>& K,
                            const Eigen::VectorXd& f,
                            const std::vector<ContactNode>& nodes, int blas_threads) {
  const ncp::ScopedBlasThreads threads(blas_threads);
  const auto n = K.rows();
  const RestrictionMaps maps = MakeRestrictionMaps(dim, static_cast<int>(n), nodes);
  Eigen::VectorXd s(static_cast<Eigen::Index>(nodes.size()));
  for (size_t c = 0; c < nodes.size(); ++c)
    s(static_cast<Eigen::Index>(c)) = nodes[c].gap;
  std::vector<bool> normal(static_cast<size_t>(n), false);
  for (int k = 0; k < maps.Y.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(maps.Y, k); it; ++it)
      normal[static_cast<size_t>(it.col())] = true;
  std::vector<Eigen::Triplet<double>> rows;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!normal[static_cast<size_t>(i)])
      rows.emplace_back(static_cast<int>(rows.size()), static_cast<int>(i), 1.0);
  Eigen::SparseMatrix<double> P(static_cast<Eigen::Index>(rows.size()), n);
  P.setFromTriplets(rows.begin(), rows.end());

  const Eigen::SparseMatrix<double> PR = P * maps.R;
  const Eigen::SparseMatrix<double> A =
      PR * K * Eigen::SparseMatrix<double>(PR.transpose());
  const Eigen::VectorXd u_held = maps.R.transpose() * (maps.Y.transpose() * s);
  const Eigen::VectorXd rhs = PR * (f - K * u_held);
  internal::CholmodFactor factor(A);
  if (!factor.ok()) return {};
  Eigen::VectorXd w;
  factor.Solve(rhs, &w);
  Eigen::VectorXd u = u_held + PR.transpose() * w;
  if (!u.allFinite()) return {};
  return u;
}

}  // namespace

const char* ToString(StaticStart start) {
  switch (start) {
    case StaticStart::kZero:
      return "zero";
    case StaticStart::kClosed:
      return "closed";
  }
  return "unknown";
}

ncp::Options StaticContactNcpOptions() {
  ncp::Options options = ContactNcpOptions();
  options.ncp_function = ncp::NcpFunction::kMin;
  return options;
}

StaticContactResult SolveStaticContact(int dim, const Eigen::SparseMatrix<double>& K,
                                       const Eigen::VectorXd& f,
                                       const std::vector<ContactNode>& nodes,
                                       const StaticContactOptions& options) {
  const auto num_nodes = static_cast<Eigen::Index>(nodes.size());
  CheckFrictionOptions(num_nodes, options);
  const double k = MaxDiagonal(K);
  const Eigen::SparseMatrix<double> S = K / k;
  const Eigen::VectorXd q = -f / k;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(K.rows());

  StaticContactResult result;
  ncp::Solver solver(options.ncp);
  Eigen::VectorXd bound = options.friction == FrictionLaw::kTresca
                              ? Eigen::VectorXd(options.tresca_bound / k)
                              : Eigen::VectorXd::Zero(num_nodes);
  Eigen::VectorXd guess = zero;
  if (options.start == StaticStart::kClosed && num_nodes > 0) {
    Eigen::VectorXd closed = ClosedStart(dim, K, f, nodes, options.ncp.blas_threads);
    result.closed_start = closed.size() == K.rows();
    if (result.closed_start) guess = std::move(closed);
  }
  Eigen::VectorXd lambda_previous = Eigen::VectorXd::Zero(num_nodes);
  const int rounds =
      options.friction == FrictionLaw::kCoulomb ? options.max_fixed_point_iterations : 1;
  ContactSystem system(dim, S, nodes);
  const StaticScales scales = ComputeScales(f, bound, k, nodes);
  for (int round = 0; round < rounds; ++round) {
    system.Update(
        q, zero,
        options.friction == FrictionLaw::kFrictionless ? Eigen::VectorXd() : bound);
    system.SetResidualScales(scales.force, scales.displacement);
    ncp::Vector z = system.StartPoint(guess);
    solver.Solve(system, &z, &result.last_summary);
    result.newton_iterations += result.last_summary.iterations;
    result.fixed_point_iterations = round + 1;
    const ContactSystem::Result r = system.Extract(z);
    StoreSolution(r, k, &result);
    if (!result.last_summary.IsSolutionUsable()) {
      result.converged = false;
      result.message = "complementarity solve failed: " + result.last_summary.message;
      return result;
    }
    if (options.friction != FrictionLaw::kCoulomb) {
      result.converged = true;
      result.message = result.last_summary.message;
      return result;
    }
    // Coulomb by fixed point: g_c = f_c lambda_c of the previous iterate.
    const double change =
        (result.normal_force - lambda_previous).lpNorm<Eigen::Infinity>();
    const double scale = std::max(result.normal_force.lpNorm<Eigen::Infinity>(), 1e-300);
    if (round > 0 && change <= options.fixed_point_tolerance * scale) {
      result.converged = true;
      result.message = "Coulomb fixed point converged after " +
                       std::to_string(round + 1) + " Tresca solves";
      return result;
    }
    lambda_previous = result.normal_force;
    bound = options.friction_coefficient * r.normal_force.cwiseMax(0.0);
    guess = r.x;
  }
  result.converged = false;
  result.message = "Coulomb fixed point did not converge in " +
                   std::to_string(options.max_fixed_point_iterations) + " Tresca solves";
  return result;
}

StaticContactResult SolveStaticContactIpopt(int dim, const Eigen::SparseMatrix<double>& K,
                                            const Eigen::VectorXd& f,
                                            const std::vector<ContactNode>& nodes,
                                            double tolerance) {
  // Rows of G: n_c . u_c <= s_c (the linearized non-penetration condition); G = Y R.
  const RestrictionMaps maps =
      MakeRestrictionMaps(dim, static_cast<int>(K.cols()), nodes);
  const Eigen::SparseMatrix<double> G = maps.Y * maps.R;
  Eigen::VectorXd h(static_cast<Eigen::Index>(nodes.size()));
  for (size_t c = 0; c < nodes.size(); ++c)
    h(static_cast<Eigen::Index>(c)) = nodes[c].gap;
  ConvexQpOptions qp_options;
  qp_options.tolerance = tolerance;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(K.cols());
  const ConvexQpResult qp = SolveConvexQpIpopt(K, -f, G, h, x0, qp_options);

  StaticContactResult result;
  result.converged = qp.status == ConvexQpStatus::kSolved;
  result.message = qp.message;
  result.u = qp.x;
  result.normal_force = qp.multipliers;
  result.tangent_force.setZero(dim - 1, static_cast<Eigen::Index>(nodes.size()));
  result.gap = h - G * qp.x;
  result.newton_iterations = qp.iterations;
  result.fixed_point_iterations = 1;
  return result;
}

}  // namespace contact
