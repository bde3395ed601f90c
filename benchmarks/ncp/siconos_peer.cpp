// The Siconos Numerics peer of ncp-bench; see siconos_peer.hpp for the mapping.
#include "siconos_peer.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "ncp_bench_config.hpp"

#if NCP_BENCH_HAVE_SICONOS
#include "LCP_Solvers.h"
#include "LinearComplementarityProblem.h"
#include "MCP_cst.h"
#include "MixedComplementarityProblem.h"
#include "NonSmoothDrivers.h"
#include "NumericsMatrix.h"
#include "NumericsVerbose.h"
#include "SolverOptions.h"
#include "lcp_cst.h"
#endif

namespace ncp_bench {

const char* PeerName(PeerMethod method) {
  switch (method) {
    case PeerMethod::kMcpNewtonFb:
      return "siconos-mcp-fb";
    case PeerMethod::kMcpNewtonMin:
      return "siconos-mcp-min";
    case PeerMethod::kLcpLemke:
      return "siconos-lcp-lemke";
    case PeerMethod::kLcpNewtonFb:
      return "siconos-lcp-fb";
    case PeerMethod::kLcpNewtonMin:
      return "siconos-lcp-min";
  }
  return "siconos-unknown";
}

bool PeerAvailable() { return NCP_BENCH_HAVE_SICONOS != 0; }

std::string PeerDescription() {
  return PeerAvailable() ? std::string("Siconos Numerics ") + NCP_BENCH_SICONOS_VERSION
                         : std::string("none");
}

#if !NCP_BENCH_HAVE_SICONOS

PeerResult RunPeer(PeerMethod, const PeerProblem&, const ncp::Vector&, double, int, int,
                   double) {
  PeerResult result;
  result.reason = "built without Siconos Numerics";
  return result;
}

#else

namespace {

/// How Siconos' unknown z_k relates to the original x_i = offset_k + sign_k z_k, and the
/// row k of Siconos' function is sign_k F_i (see siconos_peer.hpp).
struct VariableMap {
  int num_equations = 0;       ///< n1: free variables, ordered first
  std::vector<int> original;   ///< i for every Siconos index k
  std::vector<double> sign;    ///< +1 (lower bound or free) or -1 (upper bound)
  std::vector<double> offset;  ///< l_i, u_i or 0
};

/// Builds the map; false when a variable has two finite bounds.
bool MakeVariableMap(const ncp::Vector& l, const ncp::Vector& u, VariableMap* map) {
  const int n = static_cast<int>(l.size());
  std::vector<int> free_vars, bounded;
  for (int i = 0; i < n; ++i) {
    const bool has_l = std::isfinite(l[i]), has_u = std::isfinite(u[i]);
    if (has_l && has_u) return false;
    (has_l || has_u ? bounded : free_vars).push_back(i);
  }
  map->num_equations = static_cast<int>(free_vars.size());
  map->original = free_vars;
  map->original.insert(map->original.end(), bounded.begin(), bounded.end());
  map->sign.assign(n, 1.0);
  map->offset.assign(n, 0.0);
  for (int k = 0; k < n; ++k) {
    const int i = map->original[k];
    if (std::isfinite(l[i])) {
      map->offset[k] = l[i];
    } else if (std::isfinite(u[i])) {
      map->offset[k] = u[i];
      map->sign[k] = -1.0;
    }
  }
  return true;
}

/// x_i = offset_k + sign_k z_k into *x (sized n).
void ToOriginal(const VariableMap& map, const double* z, ncp::Vector* x) {
  for (size_t k = 0; k < map.original.size(); ++k)
    (*x)[map.original[k]] = map.offset[k] + map.sign[k] * z[k];
}

ncp::Vector ToOriginal(const VariableMap& map, const double* z) {
  ncp::Vector x(map.original.size());
  ToOriginal(map, z, &x);
  return x;
}

/// The environment handed to Siconos' MCP callbacks. Sized once per run, so that the
/// callbacks allocate nothing (the peer is timed per iteration on small problems).
struct McpEnvironment {
  ncp::SquareFunction* F = nullptr;
  const VariableMap* map = nullptr;
  int residual_evaluations = 0;
  int jacobian_evaluations = 0;
  ncp::Vector x, Fx;
  ncp::SparseMatrix J;
  std::vector<int> position;  ///< k for every original index i
  /// Siconos cannot be interrupted; past this deadline the callbacks return NaN, which
  /// ends its Newton iteration within a few evaluations (the run is then a time_limit).
  /// time_point::max(): no limit (the clock is then not read).
  std::chrono::steady_clock::time_point deadline =
      std::chrono::steady_clock::time_point::max();

  bool PastDeadline() const {
    return deadline != std::chrono::steady_clock::time_point::max() &&
           std::chrono::steady_clock::now() > deadline;
  }
};

void ComputeMcpFunction(void* env, int n, double* z, double* w) {
  auto* e = static_cast<McpEnvironment*>(env);
  ++e->residual_evaluations;
  ToOriginal(*e->map, z, &e->x);
  // Siconos' callbacks cannot report failure: a non-evaluable point becomes NaN.
  if (e->PastDeadline() || !e->F->Evaluate(e->x, &e->Fx))
    e->Fx.setConstant(std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < n; ++k) w[k] = e->map->sign[k] * e->Fx[e->map->original[k]];
}

void ComputeMcpJacobian(void* env, int n, double* z, NumericsMatrix* nabla) {
  auto* e = static_cast<McpEnvironment*>(env);
  ++e->jacobian_evaluations;
  ToOriginal(*e->map, z, &e->x);
  double* dense = nabla->matrix0;  // column-major n x n
  std::fill(dense, dense + static_cast<size_t>(n) * n, 0.0);
  if (e->PastDeadline() || !e->F->Jacobian(e->x, &e->J)) {
    std::fill(dense, dense + static_cast<size_t>(n) * n,
              std::numeric_limits<double>::quiet_NaN());
    return;
  }
  // d(sign_k F_i)/dz_k' = sign_k J_{i i'} sign_k'.
  const std::vector<int>& position = e->position;
  for (int col = 0; col < e->J.outerSize(); ++col) {
    for (ncp::SparseMatrix::InnerIterator it(e->J, col); it; ++it) {
      const int kr = position[it.row()], kc = position[it.col()];
      dense[kr + static_cast<size_t>(kc) * n] =
          e->map->sign[kr] * e->map->sign[kc] * it.value();
    }
  }
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

PeerResult RunPeer(PeerMethod method, const PeerProblem& problem, const ncp::Vector& x0,
                   double tolerance, int max_iterations, int max_n, double time_limit_s) {
  PeerResult result;
  const int n = static_cast<int>(x0.size());
  if (n > max_n) {
    result.reason = "n above the dense limit of the peer";
    return result;
  }
  VariableMap map;
  if (!MakeVariableMap(problem.lower, problem.upper, &map)) {
    result.reason = "two-sided bounds have no Siconos MCP/LCP form";
    return result;
  }
  const bool lcp_method = method == PeerMethod::kLcpLemke ||
                          method == PeerMethod::kLcpNewtonFb ||
                          method == PeerMethod::kLcpNewtonMin;
  if (lcp_method) {
    if (!problem.affine) {
      result.reason = "F is not affine";
      return result;
    }
    if (map.num_equations > 0 || (problem.upper.array().isFinite()).any()) {
      result.reason = "not an LCP after shifting by the lower bound";
      return result;
    }
  }
  result.applicable = true;
  numerics_set_verbose(0);

  std::vector<double> z(n), w(n, 0.0);
  for (int k = 0; k < n; ++k) {
    // Start point in Siconos' variables; a start outside the bounds is projected.
    z[k] = std::max(0.0, map.sign[k] * (x0[map.original[k]] - map.offset[k]));
    if (k < map.num_equations) z[k] = x0[map.original[k]];
  }

  int solver_id = 0;
  switch (method) {
    case PeerMethod::kMcpNewtonFb:
      solver_id = SICONOS_MCP_NEWTON_FB_FBLSA;
      break;
    case PeerMethod::kMcpNewtonMin:
      solver_id = SICONOS_MCP_NEWTON_MIN_FBLSA;
      break;
    case PeerMethod::kLcpLemke:
      solver_id = SICONOS_LCP_LEMKE;
      break;
    case PeerMethod::kLcpNewtonFb:
      solver_id = SICONOS_LCP_NEWTON_FB_FBLSA;
      break;
    case PeerMethod::kLcpNewtonMin:
      solver_id = SICONOS_LCP_NEWTON_MIN_FBLSA;
      break;
  }
  SolverOptions* options = solver_options_create(solver_id);
  // Lemke counts pivots, and a solution may need up to ~n of them: give it 10 n.
  options->iparam[SICONOS_IPARAM_MAX_ITER] =
      method == PeerMethod::kLcpLemke ? std::max(max_iterations, 10 * n) : max_iterations;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;

  int info = -1;
  const auto start = std::chrono::steady_clock::now();
  if (!lcp_method) {
    McpEnvironment env;
    env.F = problem.F;
    env.map = &map;
    env.x.resize(n);
    env.Fx.resize(n);
    env.position.resize(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k)
      env.position[static_cast<size_t>(map.original[static_cast<size_t>(k)])] = k;
    if (std::isfinite(time_limit_s))
      env.deadline =
          start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(time_limit_s));
    MixedComplementarityProblem mcp{};
    mcp.n1 = map.num_equations;
    mcp.n2 = n - map.num_equations;
    mcp.compute_Fmcp = &ComputeMcpFunction;
    mcp.compute_nabla_Fmcp = &ComputeMcpJacobian;
    mcp.nabla_Fmcp = NM_create(NM_DENSE, n, n);
    mcp.env = &env;
    info = mcp_driver(&mcp, z.data(), w.data(), options);
    result.time_s = Seconds(start);
    NM_free(mcp.nabla_Fmcp);
    result.residual_evaluations = env.residual_evaluations;
    result.jacobian_evaluations = env.jacobian_evaluations;
  } else {
    // w = F(l + z) = M z + F(l): q = F(l), M permuted like the variables (here the
    // identity permutation, since every variable is lower bounded).
    ncp::Vector q(n);
    ncp::Vector lower = problem.lower;
    problem.F->Evaluate(lower, &q);
    LinearComplementarityProblem lcp{};
    lcp.size = n;
    lcp.M = NM_create(NM_DENSE, n, n);
    Eigen::Map<Eigen::MatrixXd>(lcp.M->matrix0, n, n) = Eigen::MatrixXd(problem.M);
    lcp.q = q.data();
    info = linearComplementarity_driver(&lcp, z.data(), w.data(), options);
    result.time_s = Seconds(start);
    NM_free(lcp.M);
  }
  result.iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  result.iteration_limit = options->iparam[SICONOS_IPARAM_MAX_ITER];
  result.native_status = "info=" + std::to_string(info);
  result.claimed_success = info == 0;
  result.x = ToOriginal(map, z.data());
  solver_options_delete(options);
  return result;
}

#endif  // NCP_BENCH_HAVE_SICONOS

}  // namespace ncp_bench
