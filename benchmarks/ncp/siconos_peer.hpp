/// \file siconos_peer.hpp
/// The Siconos Numerics peer of ncp-bench behind a Siconos-free interface, so that the
/// benchmark builds (and says so) without the peer.
///
/// Mapping of the box MCP  l <= x <= u  perp  F(x)  onto Siconos' MCP (n1 equations
/// G(z) = 0 with z free, then n2 pairs 0 <= z perp H(z) >= 0;
/// MixedComplementarityProblem.h):
///   free variable  (l = -inf, u = +inf):  x_i = z_k,        row  F_i     (an equation)
///   lower bound only (u = +inf):          x_i = l_i + z_k,  row  F_i     (a pair)
///   upper bound only (l = -inf):          x_i = u_i - z_k,  row -F_i     (a pair)
/// with the free variables ordered first. A variable with two finite bounds has no such
/// form, so two-sided problems are reported as not_applicable.
/// An LCP solver applies when, in addition, every variable has only a finite lower bound
/// and F is affine (checked numerically): w = F(l + z) = M z + F(l), M = F'.
#pragma once

#include <string>

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp_bench {

enum class PeerMethod {
  kMcpNewtonFb,   ///< SICONOS_MCP_NEWTON_FB_FBLSA through mcp_driver
  kMcpNewtonMin,  ///< SICONOS_MCP_NEWTON_MIN_FBLSA through mcp_driver
  kLcpLemke,      ///< SICONOS_LCP_LEMKE through linearComplementarity_driver
  kLcpNewtonFb,   ///< SICONOS_LCP_NEWTON_FB_FBLSA through linearComplementarity_driver
  kLcpNewtonMin,  ///< SICONOS_LCP_NEWTON_MIN_FBLSA through linearComplementarity_driver
};

const char* PeerName(PeerMethod method);

/// What a peer run produced, in the benchmark's own terms.
struct PeerResult {
  bool applicable = false;
  std::string reason;  ///< why not applicable
  bool claimed_success = false;
  std::string native_status;  ///< e.g. "info=0"
  int iterations = -1;
  int iteration_limit = -1;       ///< the limit Siconos was given
  int jacobian_evaluations = -1;  ///< counted by the benchmark's callbacks (-1: LCP)
  int residual_evaluations = -1;
  double time_s = 0.0;
  ncp::Vector x;  ///< the returned point in the original variables
};

/// True when the benchmark was built with Siconos Numerics.
bool PeerAvailable();
/// "Siconos Numerics <version>" or "none".
std::string PeerDescription();

/// Problem data the peer needs, computed once per problem.
struct PeerProblem {
  ncp::SquareFunction* F = nullptr;
  ncp::Vector lower, upper;
  bool affine = false;  ///< F(x) = M x + q verified at random points
  ncp::SparseMatrix M;  ///< F' when affine
};

/// Solves with the given Siconos method from x0 with Siconos' tolerance `tolerance` and
/// iteration limit `max_iterations`. Runs only for n <= max_n (the peer is given dense
/// matrices). The MCP methods are stopped after time_limit_s by returning NaN from the
/// callbacks; the LCP methods have no callback and stop at their iteration limit only.
PeerResult RunPeer(PeerMethod method, const PeerProblem& problem, const ncp::Vector& x0,
                   double tolerance, int max_iterations, int max_n, double time_limit_s);

}  // namespace ncp_bench
