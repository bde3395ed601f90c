/// \file small_timing.hpp
/// Time per iteration of ncp against Siconos' MCP Newton-FB (SICONOS_MCP_NEWTON_FB_FBLSA)
/// on the small problems of the collection (n <= 10), side by side in one run: for every
/// (problem, start) the two solvers are timed in alternating batches, so that both see
/// the same load of the shared machine, and the result is the ratio of their medians.
///
/// A call is one complete solve from the start point, set-up included, as a user makes
/// it: ncp::Solve(options, F, l, u, x, summary) with default options (a fresh Solver each
/// call, kAuto = dense LU here) and RunPeer (options, matrix and variable map created
/// each call). A third column times ncp::Solver::Solve on one Solver kept between calls.
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "ncp/square_function.hpp"
#include "siconos_peer.hpp"

namespace ncp_bench {

struct SmallTimingCase {
  std::string problem, start;
  const PeerProblem* peer = nullptr;  ///< F, bounds (and the affine data, unused here)
  ncp::Vector x0;
};

struct SmallTimingRow {
  std::string problem, start;
  int n = 0;
  bool ncp_converged = false, peer_converged = false;
  int ncp_iterations = 0, peer_iterations = 0;
  /// Median over the rounds of the time per call [us].
  double ncp_us = 0.0, ncp_reused_us = 0.0, peer_us = 0.0;
  /// Per iteration [us]: the per-call time divided by the solver's own iteration count.
  double ncp_us_per_iteration() const { return ncp_us / ncp_iterations; }
  double ncp_reused_us_per_iteration() const { return ncp_reused_us / ncp_iterations; }
  double peer_us_per_iteration() const { return peer_us / peer_iterations; }
};

/// Mixed MCPs with free variables (the collection's small problems have
/// none): F(x) = M x + q + x.^3 / 10, M = 2 I + (K - K') + B B' / n with K, B, q normal
/// (x'Mx >= 2 |x|^2 and F' = M + diag(0.3 x.^2): strongly monotone, one solution); the
/// first `free_variables` are free, the rest >= 0. Starts: zero and ones.
struct MixedFreeProblem {
  std::string name;
  std::unique_ptr<ncp::SquareFunction> F;
  PeerProblem peer;
  std::vector<std::pair<std::string, ncp::Vector>> starts;
};
MixedFreeProblem MakeMixedFreeProblem(int n, int free_variables, unsigned seed);

/// Times every case (problems with n <= 10 only are expected) at Siconos' and ncp's
/// tolerance `tolerance`; progress and a summary go to `log`. Cases where either solver
/// takes no iteration are skipped.
std::vector<SmallTimingRow> TimeSmallProblems(const std::vector<SmallTimingCase>& cases,
                                              double tolerance, std::ostream& log);

/// One CSV line per row, with a header.
void WriteSmallTimingCsv(const std::vector<SmallTimingRow>& rows, std::ostream& out);

}  // namespace ncp_bench
