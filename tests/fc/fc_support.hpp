// Shared by the fc tests: the problem with a published solution and an independent check
// of the Coulomb law that does not use ncp::fc's projection or error.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "ncp/fc/io.hpp"
#include "ncp/fc/problem.hpp"

namespace ncp::fc::test {

/// FrictionContact3D_1c of Siconos' test data (see data/fc3d/README.md).
inline FrictionProblem OneContactProblem() {
  FrictionProblem p;
  p.dimension = 3;
  p.num_contacts = 1;
  Eigen::Matrix3d W;
  W << 15, -1, -2, -1, 14, 1, -2, 1, 16;
  p.W = W.sparseView();
  p.q = Eigen::Vector3d(-1, 2, 3);
  p.mu = Eigen::VectorXd::Constant(1, 0.1);
  p.name = "FrictionContact3D_1c";
  return p;
}

/// Its published (sliding) solution, 10 significant digits.
inline Eigen::Vector3d OneContactSolution() {
  return Eigen::Vector3d(0.0656956829, -0.003678614907, -0.005443070814);
}

/// The Coulomb law checked term by term, without any projection: with u = W r + q and
/// u_hat = u + mu |u_T| e_N, the largest of
///   |r_T| - mu r_N  (r in C_mu),   mu |u_hat_T| - u_hat_N  (u_hat in C*_mu),
///   |r . u_hat| / (1 + |u_hat|)  (complementarity),
/// over the contacts, divided by 1 + ||q||. Zero exactly at a solution.
inline double CoulombViolation(const FrictionProblem& p, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = p.W * r + p.q;
  const int d = p.dimension;
  double worst = 0.0;
  for (int a = 0; a < p.num_contacts; ++a) {
    const Eigen::VectorXd ra = r.segment(a * d, d), ua = u.segment(a * d, d);
    const double mu = p.mu[a];
    Eigen::VectorXd uhat = ua;
    uhat[0] += mu * ua.tail(d - 1).norm();
    worst = std::max({worst, ra.tail(d - 1).norm() - mu * ra[0],
                      mu * uhat.tail(d - 1).norm() - uhat[0],
                      std::abs(ra.dot(uhat)) / (1.0 + uhat.norm())});
  }
  return worst / (1.0 + p.q.norm());
}

/// Calls f(problem) for every .dat and .hdf5 problem of NCP_FC_DATA_DIR; returns their
/// number.
template <class F>
int ForEachDataProblem(F f) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(NCP_FC_DATA_DIR)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".dat" && ext != ".hdf5") continue;
    ++files;
    f(ReadProblem(entry.path().string()));
  }
  return files;
}

}  // namespace ncp::fc::test
