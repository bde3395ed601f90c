// Quadratic elements (Triangle6, Quadrilateral8/9, Tetrahedron10, Hexahedron20/27):
//  - reference data: partition of unity, N_a(x_b) = delta_ab, derivatives against central
//    differences, quadrature exact for monomials of the stated degree;
//  - patch tests: linear and quadratic displacement fields u(x) = a + B x + x^T C x / 2
//    reproduced exactly (Dirichlet data on the whole boundary, body force b = -div sigma
//    of the field), rigid motions in the null space of K;
//  - lumped masses (HRZ) positive and summing to the body's mass;
//  - L2 convergence rates against a manufactured smooth solution;
//  - a 3D cantilever against Timoshenko beam theory (Tetrahedron10 vs Tetrahedron4);
//  - contact weights: refused where nonpositive (Tetrahedron10, Hexahedron20 faces).
#include "quadratic_element.hpp"

#include <gmsh.h>

#include <Eigen/SparseCholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/contact_boundary.hpp>
#include <contact/dof_map.hpp>
#include <contact/dynamics.hpp>
#include <contact/elastic_body.hpp>
#include <contact/gmsh_reader.hpp>
#include <contact/mesh_generation.hpp>
#include <contact/quadratic_mesh.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fem_test_support.hpp"
#include "gmsh_model.hpp"
#include "reference_element.hpp"

namespace contact {
namespace {

constexpr ElementType kQuadratic[] = {
    ElementType::kTriangle6,      ElementType::kQuadrilateral8,
    ElementType::kQuadrilateral9, ElementType::kTetrahedron10,
    ElementType::kHexahedron20,   ElementType::kHexahedron27};

std::map<Side, BoundaryRole> AllSides(int dim, BoundaryRole role) {
  std::map<Side, BoundaryRole> roles = {
      {Side::kXMin, role}, {Side::kXMax, role}, {Side::kYMin, role}, {Side::kYMax, role}};
  if (dim == 3) {
    roles[Side::kZMin] = role;
    roles[Side::kZMax] = role;
  }
  return roles;
}

// A mesh of [0.3, 0.3 + 1.2] x [-0.2, 0.7] (x [0.1, 0.9]) with n cells per direction
// (n/2 in z), every side in group "fixed"; with distort, interior corners are moved
// randomly by up to 0.2 h before the mid-side nodes are placed (edges stay straight).
Mesh BoxOrRectangle(ElementType type, int n, bool distort) {
  const ElementType linear = LinearElementOf(type);
  Mesh mesh;
  if (Dimension(type) == 2) {
    RectangleMeshOptions options;
    options.origin = {0.3, -0.2};
    options.size = {1.2, 0.9};
    options.cells = {n, n};
    options.element_type = linear;
    options.side_roles = AllSides(2, BoundaryRole::kFixed);
    mesh = MakeRectangleMesh(options);
  } else {
    BoxMeshOptions options;
    options.origin = {0.3, -0.2, 0.1};
    options.size = {1.2, 0.9, 0.8};
    options.cells = {n, n, std::max(1, n / 2)};
    options.element_type = linear;
    options.side_roles = AllSides(3, BoundaryRole::kFixed);
    mesh = MakeBoxMesh(options);
  }
  if (distort) testing::PerturbInteriorNodes(&mesh, 0.9 / n, 0.2);
  return type == linear ? mesh : MakeQuadraticMesh(mesh, type);
}

TEST_CASE("quadratic shape functions: unity, nodal values, derivatives", "[quadratic]") {
  for (const ElementType type : kQuadratic) {
    const int dim = Dimension(type), nodes = NodesPerElement(type);
    const std::vector<double> ref = internal::ReferenceNodes(dim, nodes);
    std::vector<double> N(nodes), dN(nodes * dim), Np(nodes), Nm(nodes),
        scratch(nodes * dim);
    // Nodal values.
    for (int b = 0; b < nodes; ++b) {
      internal::EvaluateShape(dim, nodes, &ref[dim * b], N.data(), dN.data());
      for (int a = 0; a < nodes; ++a) REQUIRE(std::abs(N[a] - (a == b)) < 1e-14);
    }
    // A generic interior point: sum N = 1, sum dN = 0, dN against central differences.
    const double xi[3] = {0.21, 0.17, 0.13};
    internal::EvaluateShape(dim, nodes, xi, N.data(), dN.data());
    double sum = 0;
    for (int a = 0; a < nodes; ++a) sum += N[a];
    CHECK(std::abs(sum - 1) < 1e-14);
    for (int k = 0; k < dim; ++k) {
      double xp[3] = {xi[0], xi[1], xi[2]}, xm[3] = {xi[0], xi[1], xi[2]};
      const double step = 1e-6;
      xp[k] += step;
      xm[k] -= step;
      internal::EvaluateShape(dim, nodes, xp, Np.data(), scratch.data());
      internal::EvaluateShape(dim, nodes, xm, Nm.data(), scratch.data());
      double derivative_sum = 0;
      for (int a = 0; a < nodes; ++a) {
        derivative_sum += dN[dim * a + k];
        CHECK(std::abs(dN[dim * a + k] - (Np[a] - Nm[a]) / (2 * step)) < 1e-8);
      }
      CHECK(std::abs(derivative_sum) < 1e-13);
    }
  }
}

// int x^p y^q (z^r) over the reference simplex: p! q! r! / (p + q + r + dim)!; over
// [-1, 1]^d: prod (1 + (-1)^p) / (p + 1).
double ExactMonomialIntegral(bool simplex, int dim, const int* power) {
  if (simplex) {
    double numerator = 1;
    int total = dim;
    for (int k = 0; k < dim; ++k) {
      numerator *= std::tgamma(power[k] + 1.0);
      total += power[k];
    }
    return numerator / std::tgamma(total + 1.0);
  }
  double value = 1;
  for (int k = 0; k < dim; ++k) value *= power[k] % 2 ? 0.0 : 2.0 / (power[k] + 1);
  return value;
}

TEST_CASE("quadratic element and facet rules are exact to their stated degree",
          "[quadratic]") {
  struct Case {
    const internal::QuadratureRule* rule;
    bool simplex;
    int dim, degree;  // total degree (simplex) or per direction (tensor)
  };
  const Case cases[] = {
      {&internal::ElementRule(ElementType::kTriangle6, internal::RulePurpose::kMass),
       true, 2, 4},
      {&internal::ElementRule(ElementType::kTetrahedron10, internal::RulePurpose::kMass),
       true, 3, 5},
      {&internal::ElementRule(ElementType::kQuadrilateral8, internal::RulePurpose::kMass),
       false, 2, 5},
      {&internal::ElementRule(ElementType::kHexahedron27, internal::RulePurpose::kMass),
       false, 3, 5},
      {&internal::FacetRule(FacetType::kLine3), false, 1, 5},
      {&internal::FacetRule(FacetType::kTriangle6), true, 2, 4}};
  for (const Case& c : cases) {
    int power[3] = {0, 0, 0};
    for (power[0] = 0; power[0] <= c.degree; ++power[0])
      for (power[1] = 0; power[1] <= (c.dim > 1 ? c.degree : 0); ++power[1])
        for (power[2] = 0; power[2] <= (c.dim > 2 ? c.degree : 0); ++power[2]) {
          if (c.simplex && power[0] + power[1] + power[2] > c.degree) continue;
          double integral = 0;
          for (int q = 0; q < c.rule->NumPoints(); ++q) {
            double value = c.rule->weights(q);
            for (int k = 0; k < c.dim; ++k)
              value *= std::pow(c.rule->points(k, q), power[k]);
            integral += value;
          }
          CHECK(std::abs(integral - ExactMonomialIntegral(c.simplex, c.dim, power)) <
                1e-14);
        }
  }
}

// u_i = a_i + B_ij x_j + C_ijk x_j x_k / 2 (C symmetric in j, k) and its body force
// b_i = -d_j sigma_ij = -(lambda sum_m C_mmi + mu sum_j (C_ijj + C_jij)).
struct QuadraticField {
  int dim;
  Eigen::VectorXd a;
  Eigen::MatrixXd B;
  double C[3][3][3] = {};

  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const {
    Eigen::VectorXd u = a + B * x;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        for (int k = 0; k < dim; ++k) u(i) += 0.5 * C[i][j][k] * x(j) * x(k);
    return u;
  }
  Eigen::VectorXd BodyForce(double lambda, double mu) const {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        b(i) -= lambda * C[j][j][i] + mu * (C[i][j][j] + C[j][i][j]);
    return b;
  }
};

QuadraticField MakeField(int dim, bool quadratic) {
  QuadraticField field{dim, Eigen::VectorXd::LinSpaced(dim, 0.01, 0.03),
                       Eigen::MatrixXd::Zero(dim, dim)};
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      field.B(i, j) = 1e-3 * (1 + i + 2 * j) * (i == j ? 1 : -0.5);
      for (int k = j; k < dim && quadratic; ++k)
        field.C[i][j][k] = field.C[i][k][j] = 2e-3 * (1 + i - j + 0.5 * k);
    }
  return field;
}

// Dirichlet data u(x) on the whole boundary, the body force of u inside: the solution.
Vector SolveDirichlet(const ElasticBody& body, const DirichletCondition& condition,
                      const BodyForceField& b) {
  const DofMap dofs = MakeDofMap(body.mesh(), {condition});
  const SparseMatrix K = body.StiffnessMatrix();
  const Vector f = body.BodyForceFieldLoad(b);
  Eigen::SimplicialLDLT<SparseMatrix> solver(dofs.RestrictMatrix(K));
  REQUIRE(solver.info() == Eigen::Success);
  return dofs.Expand(solver.solve(dofs.RestrictLoad(K, f)));
}

TEST_CASE("quadratic elements pass the linear and quadratic patch tests", "[quadratic]") {
  const IsotropicMaterial material{200e9, 0.3, 7800};
  for (const ElementType type : kQuadratic) {
    // Serendipity elements contain the quadratic fields only on affine elements.
    const bool serendipity =
        type == ElementType::kQuadrilateral8 || type == ElementType::kHexahedron20;
    const ElasticBody body(BoxOrRectangle(type, 3, !serendipity), material);
    const int dim = body.mesh().dim;
    const double mu = material.ShearModulus();
    const double lambda = ElasticityMatrix(material, dim, body.plane().model)(0, 1);
    for (const bool quadratic : {false, true}) {
      const QuadraticField field = MakeField(dim, quadratic);
      DirichletCondition condition;
      condition.displacement = [&](const Eigen::VectorXd& x) { return field(x); };
      const Eigen::VectorXd b = field.BodyForce(lambda, mu);
      const Vector u =
          SolveDirichlet(body, condition, [&](const Eigen::VectorXd&) { return b; });
      double error = 0, scale = 0;
      for (int i = 0; i < body.mesh().NumNodes(); ++i) {
        const Eigen::VectorXd exact = field(body.mesh().nodes.col(i));
        error = std::max(error, (u.segment(dim * i, dim) - exact).cwiseAbs().maxCoeff());
        scale = std::max(scale, exact.cwiseAbs().maxCoeff());
      }
      INFO(ToString(type) << (quadratic ? " quadratic" : " linear") << " field: error "
                          << error << " of " << scale);
      CHECK(error < 1e-9 * scale);
    }
    // Rigid motions: K r = 0 relative to |K| |r|.
    const SparseMatrix K = body.StiffnessMatrix();
    const DenseMatrix modes = testing::RigidBodyModes(body.mesh());
    for (int m = 0; m < modes.cols(); ++m)
      CHECK((K * modes.col(m)).norm() < 1e-12 * K.norm() * modes.col(m).norm());
  }
}

TEST_CASE("HRZ lumped masses are positive and sum to the body's mass", "[quadratic]") {
  const IsotropicMaterial material{200e9, 0.3, 7800};
  for (const ElementType type : kQuadratic) {
    const ElasticBody body(BoxOrRectangle(type, 3, true), material);
    const Vector m = body.LumpedMass();
    const double mass = material.density * DomainMeasure(body.mesh());
    INFO(ToString(type));
    CHECK(m.minCoeff() > 0);
    CHECK(std::abs(m.sum() / body.mesh().dim - mass) < 1e-12 * mass);
    // The consistent mass has the same total.
    const SparseMatrix M = body.ConsistentMassMatrix();
    CHECK(std::abs((M * Vector::Ones(M.rows())).sum() / body.mesh().dim - mass) <
          1e-12 * mass);
  }
}

// Central differences u_(n+1) = 2 u_n - u_(n-1) - dt^2 M^-1 K u_n with the HRZ mass on a
// free body at rest: bounded at 0.98 dt_crit (Lanczos estimate), growing at 1.05 dt_crit
// (the highest mode by |lambda| = 1.88 per step).
double CentralDifferenceGrowth(const SparseMatrix& K, const Vector& m, double dt) {
  Vector u(K.rows());
  for (Eigen::Index i = 0; i < u.size(); ++i) u(i) = std::sin(1.7 * i + 0.3);
  Vector u_old = u;  // at rest
  const double start = u.norm();
  for (int n = 0; n < 300; ++n) {
    const Vector next = 2 * u - u_old - dt * dt * (K * u).cwiseQuotient(m);
    u_old = u;
    u = next;
  }
  return u.norm() / start;
}

TEST_CASE("explicit steps with HRZ masses are stable at the estimated critical step",
          "[quadratic]") {
  const IsotropicMaterial material{200e9, 0.3, 7800};
  for (const ElementType type : kQuadratic) {
    const ElasticBody body(BoxOrRectangle(type, 2, true), material);
    const SparseMatrix K = body.StiffnessMatrix();
    const Vector m = body.LumpedMass();
    SparseMatrix M(m.size(), m.size());
    for (Eigen::Index i = 0; i < m.size(); ++i) M.insert(i, i) = m(i);
    const CriticalTimeStep estimate = EstimateCriticalTimeStep(K, M);
    INFO(ToString(type) << ": dt_crit " << estimate.dt_crit);
    REQUIRE(estimate.converged);
    CHECK(CentralDifferenceGrowth(K, m, 0.98 * estimate.dt_crit) < 10);
    CHECK(CentralDifferenceGrowth(K, m, 1.05 * estimate.dt_crit) > 1e6);
  }
}

// Manufactured solution u = sum_t c_t sin(k_t . x) with b = -div sigma =
// sum_t sin(k_t . x) ((lambda + mu) (c_t . k_t) k_t + mu |k_t|^2 c_t).
struct SmoothField {
  std::vector<Eigen::VectorXd> c, k;
  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(x.size());
    for (std::size_t t = 0; t < c.size(); ++t) u += c[t] * std::sin(k[t].dot(x));
    return u;
  }
  Eigen::VectorXd BodyForce(const Eigen::VectorXd& x, double lambda, double mu) const {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(x.size());
    for (std::size_t t = 0; t < c.size(); ++t)
      b += std::sin(k[t].dot(x)) *
           ((lambda + mu) * c[t].dot(k[t]) * k[t] + mu * k[t].squaredNorm() * c[t]);
    return b;
  }
};

// || u_h - u ||_L2 over the mesh, at the points of the mass rule.
double L2Error(const Mesh& mesh, const Vector& u, const SmoothField& exact) {
  const int dim = mesh.dim, nodes = NodesPerElement(mesh.element_type);
  const auto& rule =
      internal::ElementRule(mesh.element_type, internal::RulePurpose::kMass);
  Eigen::VectorXd N(nodes);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dN(nodes, dim);
  double sum = 0;
  for (int e = 0; e < mesh.NumElements(); ++e) {
    Eigen::MatrixXd X(dim, nodes), U(dim, nodes);
    for (int a = 0; a < nodes; ++a) {
      X.col(a) = mesh.nodes.col(mesh.elements(a, e));
      U.col(a) = u.segment(dim * mesh.elements(a, e), dim);
    }
    for (int q = 0; q < rule.NumPoints(); ++q) {
      internal::EvaluateShape(dim, nodes, rule.points.col(q).data(), N.data(), dN.data());
      const double det = (X * dN).determinant();
      sum += rule.weights(q) * det * (U * N - exact(X * N)).squaredNorm();
    }
  }
  return std::sqrt(sum);
}

double ConvergenceRate(ElementType type, int n) {
  const IsotropicMaterial material{1.0, 0.3, 1.0};
  const int dim = Dimension(type);
  SmoothField field;
  if (dim == 2) {
    field.c = {Eigen::Vector2d(1.0, 0.5), Eigen::Vector2d(-0.3, 0.8)};
    field.k = {Eigen::Vector2d(2.0, 1.0), Eigen::Vector2d(-1.0, 2.5)};
  } else {
    field.c = {Eigen::Vector3d(1.0, 0.5, -0.4), Eigen::Vector3d(-0.3, 0.8, 0.6)};
    field.k = {Eigen::Vector3d(2.0, 1.0, 1.5), Eigen::Vector3d(-1.0, 2.5, 1.0)};
  }
  double errors[2];
  for (int level = 0; level < 2; ++level) {
    const ElasticBody body(BoxOrRectangle(type, n << level, false), material);
    const double mu = material.ShearModulus();
    const double lambda = ElasticityMatrix(material, dim, body.plane().model)(0, 1);
    DirichletCondition condition;
    condition.displacement = [&](const Eigen::VectorXd& x) { return field(x); };
    const Vector u = SolveDirichlet(body, condition, [&](const Eigen::VectorXd& x) {
      return field.BodyForce(x, lambda, mu);
    });
    errors[level] = L2Error(body.mesh(), u, field);
  }
  const double rate = std::log2(errors[0] / errors[1]);
  std::printf("L2 convergence %-15s n = %2d -> %2d: error %.3e -> %.3e, rate %.3f\n",
              ToString(type), n, 2 * n, errors[0], errors[1], rate);
  return rate;
}

TEST_CASE("L2 displacement error converges at order 3 (quadratic) and 2 (linear)",
          "[quadratic]") {
  for (const ElementType type : {ElementType::kTriangle6, ElementType::kQuadrilateral8,
                                 ElementType::kQuadrilateral9}) {
    INFO(ToString(type));
    CHECK(ConvergenceRate(type, 6) >= 2.9);
  }
  for (const ElementType type : {ElementType::kTetrahedron10, ElementType::kHexahedron20,
                                 ElementType::kHexahedron27}) {
    INFO(ToString(type));
    CHECK(ConvergenceRate(type, 4) >= 2.9);
  }
  for (const ElementType type : {ElementType::kTriangle3, ElementType::kQuadrilateral4,
                                 ElementType::kHexahedron8}) {
    INFO(ToString(type));
    const double rate = ConvergenceRate(type, 8);
    CHECK(rate >= 1.9);
    CHECK(rate < 2.2);
  }
}

// Cantilever 0 <= x <= L, |y|, |z| <= c: clamped at x = L (all components), total shear
// force P in -y as a uniform traction on the end x = 0; nu = 0, so that the clamp does
// not restrain a Poisson contraction that beam theory leaves free. Timoshenko beam
// theory: tip deflection P L^3 / (3 E I) + P L / (kappa G A), kappa = 10 (1 + nu) / (12 +
// 11 nu).
double CantileverTipRatio(ElementType type) {
  const double L = 10.0, c = 0.5, P = 1.0e3;
  const IsotropicMaterial material{1.0e7, 0.0, 1.0};
  BoxMeshOptions options;
  options.origin = {0.0, -c, -c};
  options.size = {L, 2 * c, 2 * c};
  options.cells = {10, 2, 2};
  options.element_type = type;
  options.side_roles = {{Side::kXMin, BoundaryRole::kLoad},
                        {Side::kXMax, BoundaryRole::kFixed}};
  const ElasticBody body(MakeBoxMesh(options), material);
  const double area = 4 * c * c, I = std::pow(2 * c, 4) / 12.0;
  const double nu = material.poisson_ratio;
  const double kappa = 10 * (1 + nu) / (12 + 11 * nu);
  const double exact = P * L * L * L / (3 * material.youngs_modulus * I) +
                       P * L / (kappa * material.ShearModulus() * area);
  const DofMap dofs = MakeDofMap(body.mesh(), {DirichletCondition{}});
  const SparseMatrix K = body.StiffnessMatrix();
  const Vector f = body.TractionLoad(Eigen::Vector3d(0, -P / area, 0), kLoadGroup);
  Eigen::SimplicialLDLT<SparseMatrix> solver(dofs.RestrictMatrix(K));
  REQUIRE(solver.info() == Eigen::Success);
  const Vector u = dofs.Expand(solver.solve(dofs.RestrictLoad(K, f)));
  // Mean deflection of the loaded end.
  double sum = 0;
  int count = 0;
  for (int i = 0; i < body.mesh().NumNodes(); ++i)
    if (std::abs(body.mesh().nodes(0, i)) < 1e-12) {
      sum += -u(3 * i + 1);
      ++count;
    }
  const double ratio = sum / count / exact;
  std::printf("cantilever 10x2x2 %-14s tip deflection / Timoshenko = %.4f\n",
              ToString(type), ratio);
  return ratio;
}

TEST_CASE("Tetrahedron10 cantilever within 1 % of beam theory, Tetrahedron4 far off",
          "[quadratic]") {
  CHECK(std::abs(CantileverTipRatio(ElementType::kTetrahedron10) - 1) < 0.01);
  CHECK(std::abs(CantileverTipRatio(ElementType::kHexahedron20) - 1) < 0.01);
  CHECK(std::abs(CantileverTipRatio(ElementType::kTetrahedron4) - 1) > 0.2);
}

TEST_CASE("contact on quadratic faces: positive weights or a clear refusal",
          "[quadratic]") {
  const IsotropicMaterial material{200e9, 0.3, 7800};
  for (const ElementType type : kQuadratic) {
    Mesh mesh = BoxOrRectangle(type, 2, false);
    mesh.boundary_groups[kContactGroup] = mesh.boundary_groups[kFixedGroup];
    const ElasticBody body(mesh, material);
    INFO(ToString(type));
    if (type == ElementType::kTetrahedron10 || type == ElementType::kHexahedron20) {
      CHECK_THROWS_WITH(
          MakeContactBoundary(body, kContactGroup),
          Catch::Contains("is not supported") && Catch::Contains("nodal contact weight"));
      continue;
    }
    const ContactBoundary boundary = MakeContactBoundary(body, kContactGroup);
    CHECK(boundary.tributary_area.minCoeff() > 0);
    const double measure = BoundaryMeasure(body.mesh(), kContactGroup);
    CHECK(std::abs(boundary.tributary_area.sum() - measure) < 1e-12 * measure);
  }
}

// The quarter disk of radius 1 meshed by gmsh at order 2 and saved in MSH 2.2 and 4.1;
// read back, the curved mid-side nodes make the area pi/4 exact to O(h^4), the straight
// chords of the linear mesh only to O(h^2).
void WriteQuarterDisk(const std::string& path, double version, int gmsh_type,
                      bool recombine, bool incomplete) {
  internal::GmshSession session("quadratic_quarter_disk");
  namespace geo = gmsh::model::geo;
  const int o = geo::addPoint(0, 0, 0), a = geo::addPoint(1, 0, 0),
            b = geo::addPoint(0, 1, 0);
  const int arc = geo::addCircleArc(a, o, b), l1 = geo::addLine(o, a),
            l2 = geo::addLine(b, o);
  const int surface = geo::addPlaneSurface({geo::addCurveLoop({l1, arc, l2})});
  if (recombine) geo::mesh::setRecombine(2, surface);
  geo::synchronize();
  gmsh::model::setPhysicalName(1, gmsh::model::addPhysicalGroup(1, {arc}), "contact");
  gmsh::model::setPhysicalName(1, gmsh::model::addPhysicalGroup(1, {l1, l2}), "fixed");
  gmsh::model::addPhysicalGroup(2, {surface});
  gmsh::option::setNumber("Mesh.MeshSizeMax", 0.2);
  gmsh::option::setNumber("Mesh.SecondOrderIncomplete", incomplete ? 1 : 0);
  gmsh::model::mesh::generate(2);
  gmsh::model::mesh::setOrder(2);
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  gmsh::model::mesh::getElements(types, tags, nodes, 2);
  REQUIRE(types.size() == 1);
  REQUIRE(types[0] == gmsh_type);
  gmsh::option::setNumber("Mesh.MshFileVersion", version);
  gmsh::write(path);
}

TEST_CASE("gmsh order-2 meshes (MSH 2.2 and 4.1) are read with curved mid-side nodes",
          "[quadratic]") {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "contact_quadratic_gmsh_test";
  std::filesystem::create_directories(dir);
  struct Case {
    int gmsh_type;
    ElementType type;
    bool recombine, incomplete;
  };
  for (const Case c : {Case{9, ElementType::kTriangle6, false, false},
                       Case{10, ElementType::kQuadrilateral9, true, false},
                       Case{16, ElementType::kQuadrilateral8, true, true}}) {
    for (const double version : {2.2, 4.1}) {
      const std::string path =
          (dir / ("disk_" + std::to_string(c.gmsh_type) + "_" +
                  std::to_string(static_cast<int>(version * 10)) + ".msh"))
              .string();
      WriteQuarterDisk(path, version, c.gmsh_type, c.recombine, c.incomplete);
      const Mesh mesh = ReadGmshMesh(path);
      INFO(ToString(c.type) << " MSH " << version);
      CHECK(mesh.element_type == c.type);
      CHECK(mesh.boundary_groups.at("contact").type == FacetType::kLine3);
      // Area pi/4 and arc length pi/2 to the accuracy of a curved quadratic boundary.
      const double pi = std::acos(-1.0);
      CHECK(std::abs(DomainMeasure(mesh) - pi / 4) < 1e-4);
      CHECK(std::abs(BoundaryMeasure(mesh, "contact") - pi / 2) < 1e-4);
      // Every node of the contact arc lies on the circle.
      for (const int node : mesh.boundary_groups.at("contact").Nodes())
        CHECK(std::abs(mesh.nodes.col(node).norm() - 1) < 1e-12);
      const ElasticBody body(mesh, IsotropicMaterial{200e9, 0.3, 7800});
      CHECK(MakeContactBoundary(body, "contact").tributary_area.minCoeff() > 0);
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace contact
