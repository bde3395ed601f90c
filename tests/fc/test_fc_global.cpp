// Global-form problems M v = q + H r, u = H' v + b (Siconos GFC3D text files): read,
// reduced to the Delassus form, solved, and checked on the global problem itself - the
// equation of motion and the Coulomb law at u = H' v + b, recomputed here from M, H, q, b
// without W.
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "ncp/fc/global.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/solver.hpp"

using namespace ncp::fc;

namespace {

const std::string kGlobalData = std::string(NCP_FC_DATA_DIR) + "/../gfc3d";

/// Largest violation of r in C_mu, u_hat in C*_mu and r . u_hat = 0 per contact, relative
/// to 1 + |r| (resp. 1 + |u_hat|), with u_hat = (u_N + mu |u_T|, u_T).
double CoulombViolation(int d, const ncp::Vector& mu, const ncp::Vector& r,
                        const ncp::Vector& u) {
  double worst = 0.0;
  for (int a = 0; a < mu.size(); ++a) {
    const ncp::Vector ra = r.segment(d * a, d), ua = u.segment(d * a, d);
    const double rt = ra.tail(d - 1).norm(), ut = ua.tail(d - 1).norm();
    const double uhat_n = ua[0] + mu[a] * ut;
    const double scale_r = 1.0 + ra.norm(), scale_u = 1.0 + std::hypot(uhat_n, ut);
    worst = std::max({worst, std::max(0.0, rt - mu[a] * ra[0]) / scale_r,
                      std::max(0.0, mu[a] * ut - uhat_n) / scale_u,
                      std::abs(ra[0] * uhat_n + ra.tail(d - 1).dot(ua.tail(d - 1))) /
                          (scale_r * scale_u)});
  }
  return worst;
}

}  // namespace

TEST_CASE("GFC3D_Example1 as printed: M, H = I, q = 0, b, mu", "[fc][global]") {
  const GlobalFrictionProblem g =
      ReadSiconosGlobalDat(kGlobalData + "/GFC3D_Example1.dat");
  CHECK(g.dimension == 3);
  CHECK(g.num_contacts == 1);
  Eigen::Matrix3d M;
  M << 106.5, 81, 126.5, 81, 91.5, 110, 126.5, 110, 163.5;
  CHECK(Eigen::MatrixXd(g.M) == Eigen::MatrixXd(M));
  CHECK(Eigen::MatrixXd(g.H) == Eigen::MatrixXd(Eigen::Matrix3d::Identity()));
  CHECK(g.q == Eigen::Vector3d::Zero());
  CHECK(g.b == Eigen::Vector3d(-2.5, -10.0, -5.5));
  CHECK(g.mu[0] == 0.5);
  // W = H' M^-1 H = M^-1 here, q_local = H' M^-1 q + b = b.
  const FrictionProblem p = ReduceToLocal(g);
  CHECK((Eigen::MatrixXd(p.W) - Eigen::MatrixXd(M.inverse())).cwiseAbs().maxCoeff() <=
        1e-14);
  CHECK(p.q == g.b);
  // Read as a local problem it is something else; the reader names the mismatch.
  CHECK_THROWS_WITH(ReadSiconosDat(kGlobalData + "/GFC3D_Example1.dat"),
                    Catch::Contains("global"));
}

TEST_CASE("every global problem: solved through W, checked on M v = q + H r and the law",
          "[fc][global]") {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kGlobalData)) {
    if (entry.path().extension() != ".dat") continue;
    ++files;
    const GlobalFrictionProblem g = ReadGlobalProblem(entry.path().string());
    INFO(g.name << ": " << g.num_dofs() << " dofs, " << g.num_contacts << " contacts");
    const FrictionProblem p = ReduceToLocal(g);
    ncp::Vector r;
    Summary summary;
    Solve(Options(), p, &r, &summary);
    INFO(summary.BriefReport());
    REQUIRE(summary.IsSolutionUsable());
    const ncp::Vector v = GlobalVelocity(g, r);
    // Independent of W: the equation of motion and the law at u = H' v + b.
    const double motion =
        (g.M * v - g.q - g.H * r).norm() / (1.0 + g.q.norm() + (g.H * r).norm());
    CHECK(motion <= 1e-12);
    const ncp::Vector u = g.H.transpose() * v + g.b;
    CHECK(CoulombViolation(g.dimension, g.mu, r, u) <= 1e-7);
    const GlobalResidual residual = ComputeGlobalResidual(g, v, r);
    CHECK(residual.motion <= 1e-12 * (1.0 + (g.H * r).norm()));
    CHECK(residual.contact <= 1e-7);
  }
  CHECK(files >= 5);  // data/gfc3d: five GFC3D files of Siconos
}

TEST_CASE("a global problem with a singular M is refused with the reason",
          "[fc][global]") {
  GlobalFrictionProblem g;
  g.dimension = 3;
  g.num_contacts = 1;
  g.M = ncp::SparseMatrix(3, 3);  // zero
  g.H = Eigen::MatrixXd(Eigen::Matrix3d::Identity()).sparseView();
  g.q = ncp::Vector::Zero(3);
  g.b = ncp::Vector::Ones(3);
  g.mu = ncp::Vector::Constant(1, 0.3);
  g.name = "singular";
  CHECK_THROWS_WITH(ReduceToLocal(g), Catch::Contains("singular"));
  g.b = ncp::Vector::Ones(2);
  CHECK_THROWS_WITH(ReduceToLocal(g), Catch::Contains("the size of b"));
}
