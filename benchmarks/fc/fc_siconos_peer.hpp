// Siconos Numerics' fc3d_driver as the peer of fc-bench. Each solve runs in a forked
// child (Siconos can neither be interrupted nor always be trusted not to exit()): the
// parent kills it at the time limit and the row becomes time_limit.
#pragma once

#include <string>
#include <vector>

#include "ncp/fc/problem.hpp"

namespace fc_bench {

struct PeerRun {
  std::string status = "not_run";  ///< converged, not_converged (Siconos' info != 0),
                                   ///< time_limit, crashed, unavailable
  int iterations = -1;
  double time_s = -1.0;         ///< best of the repetitions, per solve
  double siconos_error = -1.0;  ///< dparam[SICONOS_DPARAM_RESIDU] as Siconos reports it
  ncp::Vector r;                ///< the returned reactions (for the recomputed error)
};

bool PeerAvailable();
std::string PeerDescription();
/// The solvers for a problem dimension: 3D (fc3d_driver) NSN_AC, NSN_FB, NSN_NM, NSGS,
/// ADMM as siconos-nsn-ac, ...; 2D (fc2d_driver) NSGS and Lemke as siconos-nsgs,
/// siconos-lemke.
std::vector<std::string> PeerSolvers(int dimension);

/// Solves with Siconos: a .dat file through Siconos' own reader, anything else (HDF5)
/// from the problem as ncp::fc read it, written to a temporary sparse-block .dat.
/// max_iterations: Siconos' iparam MAX_ITER.
PeerRun RunPeer(const std::string& solver, const std::string& path,
                const ncp::fc::FrictionProblem& problem, double tolerance,
                int max_iterations, double time_limit_s, double min_timing_s);

}  // namespace fc_bench
