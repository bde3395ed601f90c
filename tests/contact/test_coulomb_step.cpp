// CoulombStep (contact/src/step/coulomb_step.hpp): the condensed step's frictional
// contact problem solved by ncp::fc. Checked against the closed form of one node with W =
// w I, against the thesis's eq.-94 ContactSystem (Tresca with the bound f_c lambda of the
// Coulomb solution: a Coulomb solution is the unique Tresca solution for its own bound),
// by the Coulomb law recomputed here from x_c, and on bad input.
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <random>

#include "contact/contact_system.hpp"
#include "ncp/solver.hpp"
#include "step/coulomb_step.hpp"
#include "step_accuracy.hpp"

using Catch::Matchers::WithinAbs;
using contact::CompleteContactFrame;
using contact::ContactNode;
using contact::ContactSystem;
using contact::internal::CoulombStep;

namespace {

// Largest violation of Signorini-Coulomb at x_c = W F + x_free, F = sum_c (-lambda n +
// tau), recomputed from the returned forces: gap >= 0, lambda >= 0, lambda gap = 0
// (scaled by the largest gap/force), |tau| <= mu lambda, and tau = -mu lambda slip /
// |slip| where it slips.
double CoulombViolation(int dim, const Eigen::MatrixXd& W,
                        const std::vector<ContactNode>& nodes,
                        const Eigen::VectorXd& x_free, const Eigen::VectorXd& gap0,
                        double mu, const ContactSystem::Result& res) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(W.rows());
  for (size_t c = 0; c < nodes.size(); ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    Eigen::Vector3d fc = -res.normal_force(i) * nodes[c].normal +
                         res.tangent_force(0, i) * nodes[c].tangent1;
    if (dim == 3) fc += res.tangent_force(1, i) * nodes[c].tangent2;
    for (int a = 0; a < dim; ++a)
      if (nodes[c].dofs[a] >= 0) force(nodes[c].dofs[a]) += fc(a);
  }
  const Eigen::VectorXd x = W * force + x_free;
  double worst = (x - res.x).lpNorm<Eigen::Infinity>();
  for (size_t c = 0; c < nodes.size(); ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    Eigen::Vector3d xc = Eigen::Vector3d::Zero();
    for (int a = 0; a < dim; ++a) xc(a) = x(nodes[c].dofs[a]);
    const double gap = gap0(i) - nodes[c].normal.dot(xc), lambda = res.normal_force(i);
    Eigen::Vector3d slip = xc - nodes[c].normal.dot(xc) * nodes[c].normal;
    Eigen::Vector3d tau = res.tangent_force(0, i) * nodes[c].tangent1;
    if (dim == 3) tau += res.tangent_force(1, i) * nodes[c].tangent2;
    worst = std::max({worst, -gap, -lambda, std::abs(std::min(gap, lambda)),
                      tau.norm() - mu * lambda});
    if (slip.norm() > 1e-9)
      worst = std::max(worst, (tau + mu * lambda * slip.normalized()).norm());
  }
  return worst;
}

}  // namespace

TEST_CASE("CoulombStep: one node with W = w I, stick and slip in closed form",
          "[coulomb_step]") {
  const double w = 2.0, mu = 0.5, g0 = 0.1, p = 0.3;  // approaches by p against a gap g0
  ContactNode node;
  node.dofs[0] = 0, node.dofs[1] = 1, node.dofs[2] = 2;
  node.normal = Eigen::Vector3d(0, 0, -1);
  CompleteContactFrame(3, &node);
  node.gap = g0;
  CoulombStep step(3, w * Eigen::MatrixXd::Identity(3, 3), {node}, mu,
                   ncp::fc::Options());
  const double lambda = (p - g0) / w;  // closes the gap exactly
  const double s =
      GENERATE(0.05, 0.5);  // trial slip: inside (0.1) or outside the cone bound
  const Eigen::VectorXd x_free = Eigen::Vector3d(0.6 * s, 0.8 * s, -p);
  CoulombStep::Outcome out;
  REQUIRE(step.Solve(x_free, Eigen::VectorXd::Constant(1, g0), 1.0, 1.0, 1e-12, &out));
  CHECK_THAT(out.contact.normal_force(0), WithinAbs(lambda, 1e-10));
  CHECK_THAT(out.contact.gap(0), WithinAbs(0.0, 1e-10));
  CHECK_THAT(out.contact.x(2), WithinAbs(-g0, 1e-10));
  // Stick: the tangential motion is cancelled; slip: it is reduced by w mu lambda.
  const double slip = s <= mu * (p - g0) ? 0.0 : s - w * mu * lambda;
  CHECK_THAT(out.contact.x(0), WithinAbs(0.6 * slip, 1e-10));
  CHECK_THAT(out.contact.x(1), WithinAbs(0.8 * slip, 1e-10));
  CHECK_THAT(out.contact.tangent_force.col(0).norm(),
             WithinAbs(std::min(s / w, mu * lambda), 1e-10));
  CHECK(out.natural_map_residual <= 1e-12);
}

TEST_CASE("CoulombStep: same step as the eq.-94 ContactSystem with the Coulomb bound",
          "[coulomb_step]") {
  const int dim = GENERATE(2, 3);
  const unsigned seed = GENERATE(1u, 2u, 3u);
  const double mu = GENERATE(0.1, 0.4, 1.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int num_nodes = 5, m = dim * num_nodes;
  // W: the Delassus operator of a random SPD mass restricted to all node components.
  Eigen::MatrixXd B(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) B(i, j) = U(rng);
  const Eigen::MatrixXd Winv = B * B.transpose() + m * Eigen::MatrixXd::Identity(m, m);
  const Eigen::MatrixXd W = Winv.inverse();
  std::vector<ContactNode> nodes;
  Eigen::VectorXd gap0(num_nodes);
  for (int c = 0; c < num_nodes; ++c) {
    ContactNode node;
    node.node = c;
    for (int a = 0; a < dim; ++a) node.dofs[a] = dim * c + a;
    node.normal = Eigen::Vector3d(0.3 * U(rng), dim == 3 ? 0.3 * U(rng) : -1.0,
                                  dim == 3 ? -1.0 : 0.0)
                      .normalized();
    CompleteContactFrame(dim, &node);
    node.gap = gap0(c) = 0.02 * (1.0 + U(rng));
    nodes.push_back(node);
  }
  // Pressed towards the obstacle (along the outward normal n) and dragged sideways.
  Eigen::VectorXd x_free(m);
  for (int c = 0; c < num_nodes; ++c) {
    const Eigen::Vector3d motion =
        0.05 * nodes[c].normal + 0.03 * Eigen::Vector3d(U(rng), U(rng), U(rng));
    for (int a = 0; a < dim; ++a) x_free(dim * c + a) = motion(a);
  }
  CoulombStep step(dim, W, nodes, mu, ncp::fc::Options());
  CoulombStep::Outcome out;
  REQUIRE(step.Solve(x_free, gap0, 1.0, 0.01, 1e-10, &out));
  INFO(out.summary.BriefReport());
  CHECK(CoulombViolation(dim, W, nodes, x_free, gap0, mu, out.contact) <= 1e-9);
  CHECK(out.contact.normal_force.maxCoeff() > 0.0);
  int sliding = 0, sticking = 0;
  for (int c = 0; c < num_nodes; ++c)
    if (out.contact.normal_force(c) > 0.0)
      (out.contact.slip.col(c).norm() > 1e-9 ? sliding : sticking)++;
  INFO("dim " << dim << " seed " << seed << " mu " << mu << ": " << sliding
              << " sliding, " << sticking << " sticking");

  // The same step again starts at its solution: solved by the start-point check, no
  // Newton step, the same result; a changed step (pushed further) needs Newton steps and
  // is solved too.
  {
    CoulombStep::Outcome again;
    REQUIRE(step.Solve(x_free, gap0, 1.0, 0.01, 1e-10, &again));
    CHECK(again.summary.iterations == 0);
    CHECK(again.summary.message == "start point");
    CHECK(again.natural_map_residual <= out.natural_map_residual * (1.0 + 1e-12) + 1e-20);
    CHECK((again.contact.x - out.contact.x).lpNorm<Eigen::Infinity>() <=
          1e-14 * x_free.lpNorm<Eigen::Infinity>());
    CHECK(again.contact.normal_force == out.contact.normal_force);
    CoulombStep::Outcome pushed;
    const Eigen::VectorXd x_pushed = 1.5 * x_free;
    REQUIRE(step.Solve(x_pushed, gap0, 1.0, 0.01, 1e-10, &pushed));
    CHECK(pushed.summary.iterations > 0);
    ContactSystem::Result pushed_contact = pushed.contact;
    CHECK(CoulombViolation(dim, W, nodes, x_pushed, gap0, mu, pushed_contact) <= 1e-9);
    // (back to this test's step for the comparison below)
    REQUIRE(step.Solve(x_free, gap0, 1.0, 0.01, 1e-10, &out));
  }

  // eq. 94 on S_c = W^-1, q_c = -W^-1 x_free, Tresca bound g_c = mu lambda_c (Coulomb's).
  ContactSystem system(dim, Winv.sparseView(), nodes);
  system.Update(-Winv * x_free, Eigen::VectorXd::Zero(m), mu * out.contact.normal_force);
  ncp::Vector z = system.StartPoint(Eigen::VectorXd::Zero(m));
  ncp::Options options = contact::ContactNcpOptions();
  options.tolerance = 1e-12;
  ncp::Solver solver(options);
  ncp::Summary summary;
  solver.Solve(system, &z, &summary);
  REQUIRE(summary.IsSolutionUsable());
  const ContactSystem::Result tresca = system.Extract(z);
  CHECK((tresca.x - out.contact.x).lpNorm<Eigen::Infinity>() <=
        1e-8 * x_free.lpNorm<Eigen::Infinity>());
  CHECK((tresca.normal_force - out.contact.normal_force).lpNorm<Eigen::Infinity>() <=
        1e-8 * out.contact.normal_force.lpNorm<Eigen::Infinity>());
}

TEST_CASE("CoulombStep: the stopping test is in the step's scales", "[coulomb_step]") {
  // The same one-node step in metres and in millimetres (W [m/N] and x [m] x 1e3, forces
  // unchanged): same forces, positions scaled, same iterations.
  ContactNode node;
  node.dofs[0] = 0, node.dofs[1] = 1;
  node.normal = Eigen::Vector3d(0, -1, 0);
  CompleteContactFrame(2, &node);
  CoulombStep::Outcome metres, millimetres;
  for (double unit : {1.0, 1e3}) {
    Eigen::Matrix2d W;
    W << 2.0, 0.5, 0.5, 1.0;
    CoulombStep step(2, unit * 1e-6 * W, {node}, 0.3, ncp::fc::Options());
    const Eigen::VectorXd x_free = unit * Eigen::Vector2d(2e-6, -3e-6);
    REQUIRE(step.Solve(x_free, Eigen::VectorXd::Constant(1, unit * 1e-6), 1.0,
                       unit * 1e-6, 1e-10, unit == 1.0 ? &metres : &millimetres));
  }
  CHECK_THAT(millimetres.contact.normal_force(0),
             WithinAbs(metres.contact.normal_force(0), 1e-9));
  CHECK_THAT(millimetres.contact.x(0), WithinAbs(1e3 * metres.contact.x(0), 1e-9));
  CHECK(millimetres.summary.iterations == metres.summary.iterations);
  CHECK(metres.contact.normal_force(0) > 0.0);
}

TEST_CASE("CoulombStep: bad input throws", "[coulomb_step]") {
  ContactNode node;
  node.dofs[0] = 0, node.dofs[1] = 1;
  node.normal = Eigen::Vector3d(0, -1, 0);
  CompleteContactFrame(2, &node);
  CHECK_THROWS_AS(
      CoulombStep(2, Eigen::MatrixXd::Identity(2, 2), {node}, -0.1, ncp::fc::Options()),
      std::invalid_argument);
  CHECK_THROWS_AS(
      CoulombStep(2, Eigen::MatrixXd::Identity(1, 1), {node}, 0.1, ncp::fc::Options()),
      std::invalid_argument);
  CoulombStep step(2, Eigen::MatrixXd::Identity(2, 2), {node}, 0.1, ncp::fc::Options());
  CoulombStep::Outcome out;
  CHECK_THROWS_AS(
      step.Solve(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(1), 1, 1, 1e-8, &out),
      std::invalid_argument);
  CHECK_THROWS_AS(
      step.Solve(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(1), 0, 1, 1e-8, &out),
      std::invalid_argument);
}

// The independent friction check of every dynamic step (step_accuracy.cpp): at a slipping
// node tau must reach g along -slip; across the slip it may lean by g times the angle
// that the slip's own accuracy (kAccuracySlack displacement accuracies) leaves
// undetermined.
TEST_CASE("Step accuracy: friction direction judged to the accuracy of the slip",
          "[coulomb_step]") {
  ContactNode node;
  node.dofs[0] = 0, node.dofs[1] = 1, node.dofs[2] = 2;
  node.normal = Eigen::Vector3d(0, 0, -1);
  CompleteContactFrame(3, &node);
  const double g = 2.0, d = 1e-12;  // bound [N], displacement accuracy [m]
  auto friction_residual = [&](const Eigen::Vector2d& slip, const Eigen::Vector2d& tau) {
    ContactSystem::Result contact;
    contact.normal_force = Eigen::VectorXd::Constant(1, g / 0.5);
    contact.tangent_force = tau;
    contact.slip = slip;
    contact.gap = Eigen::VectorXd::Zero(1);
    contact::StepRecord rec;
    rec.force_accuracy = 1e-9;
    rec.displacement_accuracy = d;
    // r: the nodal force that the contact forces balance exactly.
    Eigen::VectorXd r = -contact.normal_force(0) * node.normal + tau(0) * node.tangent1 +
                        tau(1) * node.tangent2;
    Eigen::VectorXd residual;
    contact::internal::MeasureStepAccuracy(
        3, {node}, r, contact, 1.0, Eigen::VectorXd::Zero(3),
        Eigen::VectorXd::Constant(1, g), &residual, &rec);
    CHECK(rec.equilibrium_residual < 1e-14);
    return rec.friction_residual;
  };
  const double angle = 1e-3;  // tau leaning off -slip by 1 mrad
  const Eigen::Vector2d leaning = -g * Eigen::Vector2d(std::cos(angle), std::sin(angle));
  // A slip of 1 mm is known to 1e-8 rad: the lean is a violation of g angle.
  CHECK_THAT(friction_residual(Eigen::Vector2d(1e-3, 0), leaning),
             WithinAbs(g * angle, 1e-6 * g));
  // A slip of 100 x 10 d is known to 10 mrad only: the same lean is no violation (what
  // remains is the shortfall along the slip, g (1 - cos angle)).
  CHECK_THAT(friction_residual(Eigen::Vector2d(1000 * d, 0), leaning),
             WithinAbs(g * (1 - std::cos(angle)), 1e-12));
  // ... but a friction force short of g is, whatever the slip.
  CHECK_THAT(
      friction_residual(Eigen::Vector2d(1000 * d, 0), Eigen::Vector2d(-0.9 * g, 0)),
      WithinAbs(0.1 * g, 1e-12));
  // A slip within the accuracy is a stick: only |tau| <= g counts.
  CHECK(friction_residual(Eigen::Vector2d(5 * d, 0), Eigen::Vector2d(0, 0.5 * g)) == 0.0);
}
