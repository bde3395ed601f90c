// ContactSystem: Jacobians against finite differences in the four variants (2D/3D, with
// and without friction), hand-computed one-node solutions, and bad input.
#include <catch2/catch.hpp>
#include <random>

#include "contact/contact_system.hpp"
#include "ncp/solver.hpp"

using contact::CompleteContactFrame;
using contact::ContactNode;
using contact::ContactSystem;

namespace {

struct RandomSetup {
  Eigen::SparseMatrix<double> S;
  Eigen::VectorXd q, u0;
  std::vector<ContactNode> nodes;
};

RandomSetup MakeRandom(int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int num_nodes = 4, n = dim * num_nodes;
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = U(rng);
  RandomSetup s;
  s.S = (B * B.transpose() + n * Eigen::MatrixXd::Identity(n, n)).sparseView();
  s.q = Eigen::VectorXd::NullaryExpr(n, [&] { return U(rng); });
  s.u0 = 0.1 * Eigen::VectorXd::NullaryExpr(n, [&] { return U(rng); });
  for (int c = 0; c < 2; ++c) {
    ContactNode node;
    node.node = c;
    for (int a = 0; a < dim; ++a) node.dofs[a] = dim * (c + 1) + a;
    node.normal = Eigen::Vector3d(U(rng), U(rng), dim == 3 ? U(rng) : 0.0).normalized();
    CompleteContactFrame(dim, &node);
    node.gap = 0.05;
    s.nodes.push_back(node);
  }
  return s;
}

// Max |analytic - central difference| over all entries of [JE; JA; JB].
double JacobianError(ContactSystem& system, const ncp::Vector& z) {
  const int N = system.NumVariables(), m = system.NumEquations(), p = N - m;
  ncp::SparseMatrix JE, JA, JB;
  REQUIRE(system.Jacobian(z, &JE, &JA, &JB));
  Eigen::MatrixXd analytic(m + 2 * p, N);
  analytic << Eigen::MatrixXd(JE), Eigen::MatrixXd(JA), Eigen::MatrixXd(JB);
  double error = 0.0;
  for (int j = 0; j < N; ++j) {
    const double h = 1e-6;
    ncp::Vector zp = z, zm = z;
    zp(j) += h;
    zm(j) -= h;
    ncp::Vector Ep(m), Ap(p), Bp(p), Em(m), Am(p), Bm(p);
    system.Evaluate(zp, &Ep, &Ap, &Bp);
    system.Evaluate(zm, &Em, &Am, &Bm);
    Eigen::VectorXd fd(m + 2 * p);
    fd << (Ep - Em), (Ap - Am), (Bp - Bm);
    error = std::max(error, (fd / (2 * h) - analytic.col(j)).cwiseAbs().maxCoeff());
  }
  return error;
}

}  // namespace

TEST_CASE("ContactSystem Jacobian matches finite differences", "[contact][jacobian]") {
  const int dim = GENERATE(2, 3);
  const bool friction = GENERATE(false, true);
  const unsigned seed = GENERATE(1u, 2u, 3u);
  RandomSetup s = MakeRandom(dim, seed);
  ContactSystem system(dim, s.S, s.nodes);
  system.Update(s.q, s.u0,
                friction ? Eigen::VectorXd::Constant(2, 0.3) : Eigen::VectorXd());
  CAPTURE(dim, friction, seed);
  CHECK(system.num_friction_nodes() == (friction ? 2 : 0));
  // Rows = unknowns: n + (2D: 2, 3D: 3) per friction node.
  CHECK(system.NumVariables() == dim * 4 + (friction ? (dim == 2 ? 4 : 6) : 0));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  ncp::Vector z = ncp::Vector::NullaryExpr(system.NumVariables(), [&] { return U(rng); });
  CHECK(JacobianError(system, z) < 1e-7);
  // Near a kink: a node exactly at zero slip and the start point of a step.
  z = system.StartPoint(Eigen::VectorXd::Zero(dim * 4));
  CHECK(JacobianError(system, z) < 1e-7);
}

TEST_CASE("One contact node pressed and pulled sideways: stick and slip by hand",
          "[contact]") {
  // k u = f + F with k = 100 N/m, f = (10, 3) N pushing into the wall x <= 0 (n = e_x).
  // Normal reaction lambda = 10 N; friction bound g = f_c * 10 N: stick if 3 <= g, else
  // the node slides by (3 - g) / k with tau = -g.
  const double g = GENERATE(0.0, 2.0, 5.0);
  Eigen::SparseMatrix<double> S(2, 2);
  S.insert(0, 0) = 100.0;
  S.insert(1, 1) = 100.0;
  ContactNode node;
  node.dofs[0] = 0;
  node.dofs[1] = 1;
  node.normal = Eigen::Vector3d::UnitX();
  CompleteContactFrame(2, &node);
  ContactSystem system(2, S, {node});
  const Eigen::Vector2d f(10.0, 3.0);
  system.Update(-f, Eigen::VectorXd::Zero(2),
                g > 0 ? Eigen::VectorXd::Constant(1, g) : Eigen::VectorXd());
  ncp::Vector z = system.StartPoint(Eigen::VectorXd::Zero(2));
  ncp::Summary summary;
  ncp::Solve(ncp::Options(), system, &z, &summary);
  REQUIRE(summary.IsSolutionUsable());
  const ContactSystem::Result r = system.Extract(z);
  CAPTURE(g);
  CHECK_THAT(r.x(0), Catch::Matchers::WithinAbs(0.0, 1e-12));
  CHECK_THAT(r.normal_force(0), Catch::Matchers::WithinAbs(10.0, 1e-9));
  const double slip = g >= 3.0 ? 0.0 : (3.0 - g) / 100.0;
  const double tau = g >= 3.0 ? -3.0 : -g;
  CHECK_THAT(r.x(1), Catch::Matchers::WithinAbs(slip, 1e-12));
  CHECK_THAT(r.tangent_force(0, 0), Catch::Matchers::WithinAbs(tau, 1e-9));
}

TEST_CASE("3D node slides along the direction of the tangential load", "[contact]") {
  // k = 10 N/m, f = (-5, 3, 4) N into the floor z >= 0... here n = -e_z is the outward
  // normal of the body (obstacle below). Tangential load |(3, 4)| = 5 N, bound g = 2 N:
  // slip (5 - 2)/k = 0.3 m along (0.6, 0.8); friction force -2 N along it.
  Eigen::SparseMatrix<double> S(3, 3);
  for (int i = 0; i < 3; ++i) S.insert(i, i) = 10.0;
  ContactNode node;
  node.dofs[0] = 0;
  node.dofs[1] = 1;
  node.dofs[2] = 2;
  node.normal = -Eigen::Vector3d::UnitZ();
  CompleteContactFrame(3, &node);
  ContactSystem system(3, S, {node});
  // Dof order (x, y, z) = (0, 1, 2).
  const Eigen::Vector3d f(3.0, 4.0, -5.0);
  system.Update(-f, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Constant(1, 2.0));
  ncp::Vector z = system.StartPoint(Eigen::VectorXd::Zero(3));
  ncp::Summary summary;
  ncp::Solve(ncp::Options(), system, &z, &summary);
  REQUIRE(summary.IsSolutionUsable());
  const ContactSystem::Result r = system.Extract(z);
  CHECK_THAT(r.x(0), Catch::Matchers::WithinAbs(0.3 * 0.6, 1e-10));
  CHECK_THAT(r.x(1), Catch::Matchers::WithinAbs(0.3 * 0.8, 1e-10));
  CHECK_THAT(r.x(2), Catch::Matchers::WithinAbs(0.0, 1e-12));
  CHECK_THAT(r.normal_force(0), Catch::Matchers::WithinAbs(5.0, 1e-9));
  CHECK_THAT(r.tangent_force.col(0).norm(), Catch::Matchers::WithinAbs(2.0, 1e-9));
}

TEST_CASE("Nodes with constrained components: Jacobian and a hand solution",
          "[contact]") {
  // Three 3D nodes on 7 free dofs: node 0 all free (two tangents), node 1 with z fixed
  // (one tangent, 2D-like), node 2 with x and z fixed (normal only, no friction).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int n = 9;
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = U(rng);
  const Eigen::SparseMatrix<double> S =
      (B * B.transpose() + n * Eigen::MatrixXd::Identity(n, n)).sparseView();
  std::vector<ContactNode> nodes(3);
  nodes[0].dofs[0] = 0, nodes[0].dofs[1] = 1, nodes[0].dofs[2] = 2;
  nodes[0].normal = Eigen::Vector3d(0.3, -0.9, 0.2).normalized();
  nodes[1].dofs[0] = 3, nodes[1].dofs[1] = 4, nodes[1].dofs[2] = -1;
  nodes[1].normal = Eigen::Vector3d(0.6, -0.8, 0.0);
  nodes[2].dofs[0] = -1, nodes[2].dofs[1] = 5, nodes[2].dofs[2] = -1;
  nodes[2].normal = -Eigen::Vector3d::UnitY();
  for (ContactNode& node : nodes) CompleteContactFrame(3, &node);
  CHECK(std::abs(nodes[1].tangent1.z()) <
        1e-15);  // the used tangent avoids the fixed axis
  ContactSystem system(3, S, nodes);
  system.Update(Eigen::VectorXd::NullaryExpr(n, [&] { return U(rng); }),
                Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(3, 0.4));
  CHECK(system.num_friction_nodes() == 2);    // node 2 has no free tangent
  CHECK(system.NumVariables() == n + 3 + 2);  // (g, t1, t2) + (du-, tau)
  ncp::Vector z = ncp::Vector::NullaryExpr(system.NumVariables(), [&] { return U(rng); });
  CHECK(JacobianError(system, z) < 1e-7);

  // Hand solution: node with z fixed pressed on the floor y >= 0 with f = (3, -10, *):
  // lambda = 10, with g = 2 it slides (3 - 2) / k along x.
  Eigen::SparseMatrix<double> K(2, 2);
  K.insert(0, 0) = 100.0;
  K.insert(1, 1) = 100.0;
  ContactNode node;
  node.dofs[0] = 0, node.dofs[1] = 1, node.dofs[2] = -1;
  node.normal = -Eigen::Vector3d::UnitY();
  CompleteContactFrame(3, &node);
  ContactSystem single(3, K, {node});
  single.Update(-Eigen::Vector2d(3.0, -10.0), Eigen::VectorXd::Zero(2),
                Eigen::VectorXd::Constant(1, 2.0));
  z = single.StartPoint(Eigen::VectorXd::Zero(2));
  ncp::Summary summary;
  ncp::Solve(ncp::Options(), single, &z, &summary);
  REQUIRE(summary.IsSolutionUsable());
  const ContactSystem::Result r = single.Extract(z);
  CHECK_THAT(r.x(0), Catch::Matchers::WithinAbs(0.01, 1e-12));
  CHECK_THAT(r.x(1), Catch::Matchers::WithinAbs(0.0, 1e-12));
  CHECK_THAT(r.normal_force(0), Catch::Matchers::WithinAbs(10.0, 1e-9));
  CHECK_THAT(r.tangent_force.col(0).norm(), Catch::Matchers::WithinAbs(2.0, 1e-9));
}

TEST_CASE("Restriction maps X, Y, Z and the rotation R (eq. 55)", "[contact]") {
  // 3D: node 0 all free, node 1 with z constrained, 9 free dofs of which 5 are contact
  // dofs.
  std::vector<ContactNode> nodes(2);
  nodes[0].dofs[0] = 1, nodes[0].dofs[1] = 2, nodes[0].dofs[2] = 3;
  nodes[0].normal = Eigen::Vector3d(0.3, -0.9, 0.2).normalized();
  nodes[1].dofs[0] = 6, nodes[1].dofs[1] = 7, nodes[1].dofs[2] = -1;
  nodes[1].normal = Eigen::Vector3d(0.6, -0.8, 0.0);
  for (ContactNode& node : nodes) CompleteContactFrame(3, &node);
  const contact::RestrictionMaps m = contact::MakeRestrictionMaps(3, 9, nodes);
  CHECK(m.X.rows() == 4);
  CHECK(m.Y.rows() == 2);
  CHECK(m.Z.rows() == 3);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(9, 9);
  CHECK((Eigen::MatrixXd(m.R * Eigen::SparseMatrix<double>(m.R.transpose())) - I)
            .cwiseAbs()
            .maxCoeff() < 1e-14);
  const Eigen::MatrixXd partition =
      Eigen::MatrixXd(Eigen::SparseMatrix<double>(m.X.transpose()) * m.X) +
      Eigen::MatrixXd(Eigen::SparseMatrix<double>(m.Y.transpose()) * m.Y) +
      Eigen::MatrixXd(Eigen::SparseMatrix<double>(m.Z.transpose()) * m.Z);
  CHECK((partition - I).cwiseAbs().maxCoeff() == 0.0);
  // Y R x is the normal displacement n . x_c of each node.
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(9, 0.1, 0.9);
  const Eigen::VectorXd normal_part = m.Y * (m.R * x);
  CHECK_THAT(normal_part(0),
             Catch::Matchers::WithinAbs(
                 nodes[0].normal.dot(Eigen::Vector3d(x(1), x(2), x(3))), 1e-15));
  CHECK_THAT(normal_part(1),
             Catch::Matchers::WithinAbs(
                 nodes[1].normal.dot(Eigen::Vector3d(x(6), x(7), 0.0)), 1e-15));
  // The free tangent of node 1 avoids the constrained axis: Z picks t1 . x_c.
  const Eigen::VectorXd tangential = m.Z * (m.R * x);
  CHECK_THAT(tangential(2),
             Catch::Matchers::WithinAbs(
                 nodes[1].tangent1.dot(Eigen::Vector3d(x(6), x(7), 0.0)), 1e-15));
}

TEST_CASE("ContactSystem rejects bad input with a message", "[contact][errors]") {
  Eigen::SparseMatrix<double> S(2, 2);
  S.insert(0, 0) = 1.0;
  S.insert(1, 1) = 1.0;
  ContactNode node;
  node.dofs[0] = 0;
  node.dofs[1] = 1;
  node.normal = Eigen::Vector3d(2.0, 0.0, 0.0);  // not unit
  CompleteContactFrame(2, &node);
  CHECK_THROWS_WITH(ContactSystem(2, S, {node}), Catch::Contains("not a unit vector"));
  node.normal = Eigen::Vector3d::UnitX();
  CompleteContactFrame(2, &node);
  node.dofs[1] = 5;
  CHECK_THROWS_WITH(ContactSystem(2, S, {node}),
                    Catch::Contains("is neither a free dof"));
  node.dofs[1] = 1;
  CHECK_THROWS_WITH(ContactSystem(4, S, {node}),
                    Catch::Contains("dimension must be 2 or 3"));
  ContactNode tilted = node;  // x constrained but the normal has an x component
  tilted.dofs[0] = -1;
  CHECK_THROWS_WITH(ContactSystem(2, S, {tilted}),
                    Catch::Contains("which is constrained"));
  ContactSystem system(2, S, {node});
  CHECK_THROWS_WITH(system.Update(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(2),
                                  Eigen::VectorXd()),
                    Catch::Contains("must have size 2"));
  CHECK_THROWS_WITH(system.Update(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2),
                                  Eigen::VectorXd::Constant(1, -1.0)),
                    Catch::Contains("Tresca bound must be finite and >= 0"));
}
