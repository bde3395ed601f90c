// Mesh convergence of an end-loaded cantilever in plane stress against the exact
// elasticity solution (Timoshenko & Goodier, Theory of Elasticity, section 21).
//
// Beam 0 <= x <= L, -c <= y <= c, thickness h, I = h (2c)^3 / 12. A shear force P
// (upward) acts on the end x = 0 as the parabolic traction t = sigma n, n = (-1, 0); the
// end x = L carries the exact displacement as Dirichlet data (so the discrete problem
// converges to the exact solution itself, not to a beam-theory approximation). Exact
// fields:
//   sigma_xx = -P x y / I,  sigma_yy = 0,  tau_xy = -P (c^2 - y^2) / (2 I),
//   u = -P x^2 y / (2EI) - nu P y^3 / (6EI) + P y^3 / (6IG)
//       + (P L^2 / (2EI) - P c^2 / (2IG)) y,
//   v = nu P x y^2 / (2EI) + P x^3 / (6EI) - P L^2 x / (2EI) + P L^3 / (3EI),
// with u = v = dv/dx = 0 at (L, 0). The measured quantity is the tip deflection
// v(0, 0) = P L^3 / (3EI); with bilinear Q4 it converges as O(h^2) (the nodal
// displacement error of a second-order accurate energy-norm method).
#include <Eigen/SparseCholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/dof_map.hpp>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>
#include <cstdio>

namespace contact {
namespace {

struct Cantilever {
  double L = 8.0, c = 1.0, h = 0.5;  // [m]
  double P = 4.0e6;                  // [N]
  IsotropicMaterial material{200e9, 0.3, 7800};

  double I() const { return h * std::pow(2 * c, 3) / 12.0; }
  double E() const { return material.youngs_modulus; }
  double G() const { return material.ShearModulus(); }
  double nu() const { return material.poisson_ratio; }

  Eigen::VectorXd Displacement(const Eigen::VectorXd& p) const {
    const double x = p(0), y = p(1);
    const double EI = E() * I(), IG = I() * G();
    Eigen::VectorXd u(2);
    u(0) = -P * x * x * y / (2 * EI) - nu() * P * y * y * y / (6 * EI) +
           P * y * y * y / (6 * IG) + (P * L * L / (2 * EI) - P * c * c / (2 * IG)) * y;
    u(1) = nu() * P * x * y * y / (2 * EI) + P * x * x * x / (6 * EI) -
           P * L * L * x / (2 * EI) + P * L * L * L / (3 * EI);
    return u;
  }
  Eigen::Matrix2d Stress(const Eigen::VectorXd& p) const {
    const double x = p(0), y = p(1);
    const double tau = -P * (c * c - y * y) / (2 * I());
    Eigen::Matrix2d sigma;
    sigma << -P * x * y / I(), tau, tau, 0.0;
    return sigma;
  }
  double TipDeflection() const { return P * L * L * L / (3 * E() * I()); }
};

// Tip deflection with ny elements over the height and 4 ny along the length (square Q4).
double SolveTipDeflection(const Cantilever& beam, int ny) {
  RectangleMeshOptions options;
  options.origin = {0.0, -beam.c};
  options.size = {beam.L, 2 * beam.c};
  options.cells = {4 * ny, ny};
  options.element_type = ElementType::kQuadrilateral4;
  options.side_roles = {{Side::kXMin, BoundaryRole::kLoad},
                        {Side::kXMax, BoundaryRole::kFixed}};
  const ElasticBody body(MakeRectangleMesh(options), beam.material,
                         {PlaneModel::kPlaneStress, beam.h});

  DirichletCondition clamp;
  clamp.displacement = [&](const Eigen::VectorXd& x) { return beam.Displacement(x); };
  const DofMap dofs = MakeDofMap(body.mesh(), {clamp});
  const SparseMatrix K = body.StiffnessMatrix();
  const Vector f = body.TractionFieldLoad(
      [&](const Eigen::VectorXd& x, const Eigen::VectorXd& n) -> Eigen::VectorXd {
        return beam.Stress(x) * n;
      });
  Eigen::SimplicialLDLT<SparseMatrix> solver(dofs.RestrictMatrix(K));
  REQUIRE(solver.info() == Eigen::Success);
  const Vector u = dofs.Expand(solver.solve(dofs.RestrictLoad(K, f)));

  int tip = -1;
  for (int i = 0; i < body.mesh().NumNodes(); ++i)
    if (body.mesh().nodes.col(i).norm() < 1e-12) tip = i;
  REQUIRE(tip >= 0);
  return u(2 * tip + 1);
}

TEST_CASE("Q4 plane-stress cantilever converges to the exact tip deflection at order 2",
          "[convergence]") {
  const Cantilever beam;
  const double exact = beam.TipDeflection();
  std::printf("cantilever L = %g, 2c = %g, h = %g, P = %g: exact tip deflection %.9e m\n",
              beam.L, 2 * beam.c, beam.h, beam.P, exact);
  std::printf("%8s %10s %16s %12s %8s\n", "mesh", "dofs", "v_tip [m]", "rel. error",
              "order");
  std::vector<double> errors;
  for (const int ny : {2, 4, 8, 16, 32}) {
    const double v_tip = SolveTipDeflection(beam, ny);
    errors.push_back(std::abs(v_tip - exact) / exact);
    const double order = errors.size() > 1
                             ? std::log2(errors[errors.size() - 2] / errors.back())
                             : std::nan("");
    std::printf("%4dx%-3d %10d %16.9e %12.4e %8.3f\n", 4 * ny, ny,
                2 * (4 * ny + 1) * (ny + 1), v_tip, errors.back(), order);
  }
  for (std::size_t k = 1; k < errors.size(); ++k) CHECK(errors[k] < errors[k - 1]);
  const double final_order = std::log2(errors[errors.size() - 2] / errors.back());
  CHECK(final_order > 1.8);
  CHECK(final_order < 2.2);
  CHECK(errors.back() < 2e-3);
}

}  // namespace
}  // namespace contact
