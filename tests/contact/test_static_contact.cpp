// Static contact of an elastic body with a rigid obstacle against answers known in closed
// form: the contact patch test (uniform pressure on a flat frictionless obstacle), the 2D
// Hertz contact of a cylinder on a rigid plane, agreement of the semismooth Newton solver
// (Fischer-Burmeister and min) with the Ipopt QP reference, Tresca and Coulomb friction,
// and bad input. Every solution is checked with residuals recomputed here from K, f and
// the contact frames, never from the solver's summary.

#include <Eigen/QR>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/contact_boundary.hpp"
#include "contact/contact_frames.hpp"
#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/obstacle.hpp"
#include "contact/static_contact.hpp"
#include "fem_test_support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using namespace contact;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Steel; lengths in m, stresses in Pa, 2D quantities per metre of depth (thickness 1 m).
const IsotropicMaterial kSteel{210e9, 0.3, 7850.0};

// ---------------------------------------------------------------------------------------
// The discrete problem and independent checks of a solution.
// ---------------------------------------------------------------------------------------

// K u = f + sum_c F_c on the free dofs, with the contact nodes of the "contact" group
// against `obstacle` (normals and gaps from the obstacle: exact for a flat one) and a
// constant traction on the "load" group. All Dirichlet conditions here are homogeneous,
// so a constrained component of a contact node has zero displacement.
struct StaticProblem {
  StaticProblem(ElasticBody body_in, DofMap dofs_in, const RigidObstacle& obstacle,
                const Eigen::VectorXd& traction)
      : body(std::move(body_in)),
        dofs(std::move(dofs_in)),
        boundary(MakeContactBoundary(body)),
        frames(MakeContactFrames(body.mesh(), boundary, dofs, obstacle,
                                 NormalSource::kObstacle)),
        K_full(body.StiffnessMatrix()),
        f_full(body.TractionLoad(traction)),
        K(dofs.RestrictMatrix(K_full)),
        f(dofs.RestrictLoad(K_full, f_full)) {}

  int dim() const { return body.dim(); }
  const std::vector<ContactNode>& nodes() const { return frames.nodes; }
  // Mesh coordinates of contact node c [m].
  Eigen::VectorXd Position(size_t c) const {
    return body.mesh().nodes.col(frames.nodes[c].node);
  }

  ElasticBody body;
  DofMap dofs;
  ContactBoundary boundary;
  ContactFrames frames;
  SparseMatrix K_full;
  Vector f_full;
  SparseMatrix K;  // K_FF [N/m]
  Vector f;        // f_F [N]
};

// Displacement of contact node c (global frame, 3 components, 0 where constrained) [m].
Eigen::Vector3d NodeDisplacement(const ContactNode& node, int dim, const Vector& u) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int a = 0; a < dim; ++a)
    if (node.dofs[a] >= 0) v(a) = u(node.dofs[a]);
  return v;
}

// Residuals of a static contact solution recomputed from the problem data:
//   equilibrium  ||K u - f - sum_c F_c||_inf / max(||f||_inf, max_c lambda_c), with the
//                force of the obstacle F_c = -lambda_c n_c + tau_c1 t_c1 (+ tau_c2 t_c2)
//                (contact_system.hpp),
//   signorini    max_c |min(lambda_c / max lambda, gap_c / ||u||_inf)| with the gap
//                recomputed as gap_c = s_c - n_c . u_c: zero iff lambda_c >= 0,
//                gap_c >= 0 and lambda_c gap_c = 0 at every node.
struct ContactResiduals {
  double equilibrium = -1.0;
  double signorini = -1.0;
};

ContactResiduals Recompute(const StaticProblem& problem, const StaticContactResult& r) {
  const int dim = problem.dim();
  const auto& nodes = problem.nodes();
  REQUIRE(r.u.size() == problem.K.rows());
  REQUIRE(r.normal_force.size() == static_cast<Eigen::Index>(nodes.size()));
  Vector residual = problem.K * r.u - problem.f;
  const double force_scale =
      std::max(problem.f.lpNorm<Eigen::Infinity>(), r.normal_force.maxCoeff());
  const double lambda_scale = std::max(r.normal_force.maxCoeff(), 1e-300);
  const double u_scale = std::max(r.u.lpNorm<Eigen::Infinity>(), 1e-300);
  ContactResiduals out;
  out.signorini = 0.0;
  for (size_t c = 0; c < nodes.size(); ++c) {
    const ContactNode& node = nodes[c];
    const auto k = static_cast<Eigen::Index>(c);
    Eigen::Vector3d F = -r.normal_force(k) * node.normal;
    if (r.tangent_force.size() > 0) {
      F += r.tangent_force(0, k) * node.tangent1;
      if (dim == 3) F += r.tangent_force(1, k) * node.tangent2;
    }
    for (int a = 0; a < dim; ++a)
      if (node.dofs[a] >= 0) residual(node.dofs[a]) -= F(a);
    const double gap = node.gap - node.normal.dot(NodeDisplacement(node, dim, r.u));
    out.signorini =
        std::max(out.signorini,
                 std::abs(std::min(r.normal_force(k) / lambda_scale, gap / u_scale)));
  }
  out.equilibrium = residual.lpNorm<Eigen::Infinity>() / force_scale;
  return out;
}

// Semismooth Newton settings. The solver's tolerance is absolute on the system scaled by
// k = max K_ii, whose rows are in metres (S u + q = (K u - f) / k, gaps in m): it must be
// set relative to the expected displacement, e.g. 1e-10 m would be only ~1e-5 relative
// for steel under 10 MPa (u ~ 1e-5 m).
// The default tolerance: relative to the problem's own force and displacement scales, so
// no test picks one by the size of its displacements.
StaticContactOptions SolverOptions(
    ncp::NcpFunction function = ncp::NcpFunction::kFischerBurmeister) {
  StaticContactOptions options;
  options.ncp.ncp_function = function;
  return options;
}

// ||a - b||_inf / ||b||_inf.
double RelativeDifference(const Vector& a, const Vector& b) {
  REQUIRE(a.size() == b.size());
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

// ---------------------------------------------------------------------------------------
// Contact patch test
// ---------------------------------------------------------------------------------------

// Moves the nodes of the bottom face (coordinate dim-1 = 0) that are not on any other
// side of the bounding box along the face by up to `fraction` h (fixed seed), so that the
// tributary areas of the contact nodes differ.
void PerturbBottomNodes(Mesh* mesh, double h, double fraction) {
  std::mt19937 generator(11);
  std::uniform_real_distribution<double> offset(-fraction * h, fraction * h);
  const int dim = mesh->dim;
  const Eigen::VectorXd lower = mesh->nodes.rowwise().minCoeff();
  const Eigen::VectorXd upper = mesh->nodes.rowwise().maxCoeff();
  const double tolerance = 1e-9 * (upper - lower).norm();
  for (int i = 0; i < mesh->NumNodes(); ++i) {
    if (std::abs(mesh->nodes(dim - 1, i) - lower(dim - 1)) > tolerance) continue;
    bool on_edge = false;
    for (int k = 0; k + 1 < dim; ++k)
      on_edge |= std::abs(mesh->nodes(k, i) - lower(k)) <= tolerance ||
                 std::abs(mesh->nodes(k, i) - upper(k)) <= tolerance;
    if (on_edge) continue;
    for (int k = 0; k + 1 < dim; ++k) mesh->nodes(k, i) += offset(generator);
  }
}

struct PatchCase {
  const char* name;
  ElementType element;
  MeshTopology topology;
};

// A block [0, 2] x [0, 1] (2D, plane strain) or [0, 2] x [0, 1] x [0, 1] m (3D) on the
// frictionless floor {y <= 0} (3D: {z <= 0}), gap 0, pressed by a pressure p on the top.
// Rigid tangential motions are removed by rollers: u_x = 0 on x = 0 (3D also u_y = 0 on
// y = 0). The exact solution is the uniform uniaxial stress sigma_vertical = -p:
//   2D plane strain: u_x = nu (1 + nu) p / E x,  u_y = -(1 - nu^2) p / E y,
//   3D:              u_x = nu p / E x,  u_y = nu p / E y,  u_z = -p / E z,
// which linear elements reproduce exactly; every contact node carries p times its
// tributary area (consistent nodal force of a uniform traction).
struct PatchSetup {
  StaticProblem problem;
  double p = 10e6;          // applied pressure [Pa]
  double contact_area = 0;  // [m^2] (2D: length x thickness 1 m)
  Vector u_exact;           // free dofs [m]
};

PatchSetup MakePatch(const PatchCase& c) {
  const int dim = Dimension(c.element);
  const double p = 10e6;
  Mesh mesh;
  double h = 0;
  if (dim == 2) {
    RectangleMeshOptions o;
    o.size = {2.0, 1.0};
    o.cells = {8, 4};
    o.element_type = c.element;
    o.topology = c.topology;
    o.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                    {Side::kYMin, BoundaryRole::kContact},
                    {Side::kYMax, BoundaryRole::kLoad}};
    mesh = MakeRectangleMesh(o);
    h = 0.25;
  } else {
    BoxMeshOptions o;
    o.size = {2.0, 1.0, 1.0};
    o.cells = {6, 3, 3};
    o.element_type = c.element;
    o.side_roles = {{Side::kZMin, BoundaryRole::kContact},
                    {Side::kZMax, BoundaryRole::kLoad}};
    mesh = MakeBoxMesh(o);
    h = 1.0 / 3.0;
  }
  const double fraction = c.topology == MeshTopology::kStructured ? 0.2 : 0.05;
  testing::PerturbInteriorNodes(&mesh, h, fraction);
  PerturbBottomNodes(&mesh, h, 0.2);

  // Rollers: x on x = 0 (the 'fixed' group in 2D), and y on y = 0 in 3D.
  DofMap dofs;
  if (dim == 2) {
    dofs = MakeDofMap(mesh, {DirichletCondition{kFixedGroup, {0}, {}}});
  } else {
    std::vector<int> constrained;
    for (int i = 0; i < mesh.NumNodes(); ++i)
      for (int a = 0; a < 2; ++a)
        if (std::abs(mesh.nodes(a, i)) < 1e-12) constrained.push_back(3 * i + a);
    dofs = DofMap(mesh.NumDofs(), constrained);
  }
  Eigen::VectorXd strain(dim);  // diagonal of the exact (constant) strain
  const double E = kSteel.youngs_modulus, nu = kSteel.poisson_ratio;
  if (dim == 2)
    strain << nu * (1 + nu) * p / E, -(1 - nu * nu) * p / E;
  else
    strain << nu * p / E, nu * p / E, -p / E;
  const Vector u_exact_full = testing::LinearField(mesh, Eigen::VectorXd::Zero(dim),
                                                   strain.asDiagonal().toDenseMatrix());
  Eigen::VectorXd traction = Eigen::VectorXd::Zero(dim);
  traction(dim - 1) = -p;
  const double contact_area = dim == 2 ? 2.0 : 2.0 * 1.0;
  ElasticBody body(std::move(mesh), kSteel);
  PatchSetup setup{StaticProblem(std::move(body), std::move(dofs),
                                 HalfSpace::ObstacleBelow(dim, dim - 1, 0.0), traction),
                   p, contact_area, Vector()};
  setup.u_exact = setup.problem.dofs.RestrictVector(u_exact_full);
  return setup;
}

// Ipopt at tolerance 1e-14 often ends with Search_Direction_Becomes_Too_Small at a point
// it cannot improve further (convex_qp.hpp); such a result is accepted here and judged by
// the residuals recomputed from the problem data, like every other.
bool UsableIpoptResult(const StaticContactResult& r) {
  return r.converged ||
         r.message.find("Search_Direction_Becomes_Too_Small") != std::string::npos;
}

// The checks of the patch test on one solution; returns max_c |sigma_c / p - 1|.
double CheckPatchSolution(const PatchSetup& s, const StaticContactResult& r) {
  const ContactResiduals res = Recompute(s.problem, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  // Contact stress per node: normal force / tributary area = p.
  double stress_error = 0.0;
  for (size_t c = 0; c < s.problem.nodes().size(); ++c) {
    const double sigma =
        r.normal_force(static_cast<Eigen::Index>(c)) / s.problem.nodes()[c].area;
    stress_error = std::max(stress_error, std::abs(sigma / s.p - 1.0));
  }
  CHECK(stress_error < 1e-8);
  CHECK_THAT(r.normal_force.sum(), WithinRel(s.p * s.contact_area, 1e-10));
  // The exact linear displacement field.
  CHECK(RelativeDifference(r.u, s.u_exact) < 1e-8);
  return stress_error;
}

}  // namespace

TEST_CASE("Contact patch test: uniform pressure on a flat frictionless obstacle",
          "[static][patch]") {
  const PatchCase c = GENERATE(
      PatchCase{"Q4 structured", ElementType::kQuadrilateral4, MeshTopology::kStructured},
      PatchCase{"T3 unstructured", ElementType::kTriangle3, MeshTopology::kUnstructured},
      PatchCase{"Hex8 structured", ElementType::kHexahedron8, MeshTopology::kStructured});
  CAPTURE(c.name);
  const PatchSetup s = MakePatch(c);
  const int dim = s.problem.dim();
  // Every bottom node is a contact node, the corner ones on the rollers included (their
  // constrained components are orthogonal to the normal).
  CHECK(s.problem.frames.excluded_mesh_nodes.empty());
  REQUIRE(s.problem.nodes().size() == s.problem.boundary.nodes.size());
  // The perturbed mesh has unequal tributary areas: the test is not trivially uniform.
  Vector areas(static_cast<Eigen::Index>(s.problem.nodes().size()));
  for (size_t c2 = 0; c2 < s.problem.nodes().size(); ++c2)
    areas(static_cast<Eigen::Index>(c2)) = s.problem.nodes()[c2].area;
  CHECK(areas.maxCoeff() > 1.2 * areas.minCoeff());
  CHECK_THAT(areas.sum(), WithinRel(s.contact_area, 1e-12));

  const ncp::NcpFunction function =
      GENERATE(ncp::NcpFunction::kFischerBurmeister, ncp::NcpFunction::kMin);
  const ncp::LinearSolverType linear_solver =
      GENERATE(ncp::LinearSolverType::kSparseLU, ncp::LinearSolverType::kUmfpack,
               ncp::LinearSolverType::kKlu);
  CAPTURE(ncp::ToString(function), ncp::ToString(linear_solver));
  StaticContactOptions options = SolverOptions(function);
  options.ncp.linear_solver = linear_solver;
  const StaticContactResult newton =
      SolveStaticContact(dim, s.problem.K, s.problem.f, s.problem.nodes(), options);
  INFO(newton.message);
  REQUIRE(newton.converged);
  const double newton_stress_error = CheckPatchSolution(s, newton);

  const StaticContactResult ipopt =
      SolveStaticContactIpopt(dim, s.problem.K, s.problem.f, s.problem.nodes(), 1e-14);
  INFO(ipopt.message);
  REQUIRE(UsableIpoptResult(ipopt));
  const double ipopt_stress_error = CheckPatchSolution(s, ipopt);
  const double du = RelativeDifference(ipopt.u, newton.u);
  const double dlambda = RelativeDifference(ipopt.normal_force, newton.normal_force);
  CHECK(du < 1e-8);
  CHECK(dlambda < 1e-8);
  std::printf(
      "patch %-16s %-18s %-9s: newton its %2d (%d gradient steps), stress error %.1e; "
      "ipopt "
      "its %2d, stress error %.1e; |du|/|u| %.1e, |dlambda|/|lambda| %.1e\n",
      c.name, ncp::ToString(function), ncp::ToString(linear_solver),
      newton.newton_iterations, newton.last_summary.gradient_steps, newton_stress_error,
      ipopt.newton_iterations, ipopt_stress_error, du, dlambda);
}

// ---------------------------------------------------------------------------------------
// Hertz: a cylinder pressed onto a rigid plane (plane strain)
// ---------------------------------------------------------------------------------------

namespace {

// Hertz contact of a cylinder of radius R on a rigid flat (Johnson, Contact Mechanics,
// 1985, section 4.3, eq. 4.43-4.45; the plane is rigid, so E* = E / (1 - nu^2)): for a
// load P per unit length the contact half-width and the pressure are
//     a = sqrt(4 P R / (pi E*)),   p(x) = p0 sqrt(1 - x^2 / a^2),   p0 = 2 P / (pi a).
// The model is the quarter x >= 0 of the cylinder's lower half (axis through (0, R),
// touching the floor y <= 0 at the origin) with the symmetry condition u_x = 0 on x = 0
// and a uniform pressure q on the cut y = R: the quarter carries P / 2 = q R.
// Small load, a = 0.02 R: the gap of the model, the exact R - sqrt(R^2 - x^2) measured
// vertically to the floor, differs from the parabola x^2 / (2R) of Hertz theory by a
// relative x^2 / (4 R^2) <= 1e-4 in the contact zone, and the finite disk is close to the
// half-space of the theory (measured: with a = 0.05 R the peak pressure levels off at
// 0.3% below p0 as the mesh is refined; with a = 0.02 R below 0.1%).
struct HertzData {
  double R = 0.05;  // [m]
  double E_star =
      kSteel.youngs_modulus / (1.0 - kSteel.poisson_ratio * kSteel.poisson_ratio);
  double a = 0.02 * R;                          // exact half-width [m]
  double P = kPi * E_star * a * a / (4.0 * R);  // load per metre of length [N/m]
  double p0 = 2.0 * P / (kPi * a);              // exact peak pressure [Pa]
  double q = P / (2.0 * R);                     // pressure on the cut of the quarter [Pa]

  double Pressure(double x) const {
    return std::abs(x) >= a ? 0.0 : p0 * std::sqrt(1.0 - x * x / (a * a));
  }
};

StaticProblem MakeHertzProblem(const HertzData& d, double h_contact, int order = 1) {
  QuarterDiskMeshOptions disk;
  disk.order = order;
  disk.radius = d.R;
  disk.contact_size = h_contact;
  disk.refined_radius = 1.5 * d.a;
  disk.contact_extent = 3.0 * d.a;
  disk.max_size = d.R / 8.0;
  Mesh mesh = MakeQuarterDiskMesh(disk);
  DofMap dofs = MakeDofMap(mesh, {DirichletCondition{kFixedGroup, {0}, {}}});
  return StaticProblem(ElasticBody(std::move(mesh), kSteel), std::move(dofs),
                       HalfSpace::ObstacleBelow(2, 1, 0.0), Eigen::Vector2d(0.0, -d.q));
}

// What the computed contact tells about the Hertz quantities. The contact pressure of
// node c is p_c = lambda_c / tributary_area_c (thickness 1 m); node c is loaded when
// lambda_c > 1e-9 max lambda.
struct HertzMeasurement {
  double h_contact = 0;  // element size at the contact [m]
  int num_dofs = 0;
  int nodes_in_contact = 0;   // loaded nodes
  double x_last = 0;          // x of the last loaded node [m]
  double x_next = 0;          // x of the first unloaded node [m]
  double a_extrapolated = 0;  // [m], see below
  double a_fit = 0;           // [m], see below
  double p0_node = 0;         // p at the node x = 0 [Pa]
  double p0_fit = 0;          // [Pa], see below
  double max_error = 0;       // max_c |p_c - p(x_c)| / p0_exact over all contact nodes
  double l2_error = 0;        // sqrt(sum_c A_c (p_c - p(x_c))^2 / a) / p0_exact
  double force = 0;           // sum_c lambda_c [N/m] (= q R by equilibrium)
};

// Half-width: near the edge p^2 = p0^2 (1 - x^2 / a^2) is linear in x^2, so
//  - a_extrapolated is the zero of the line through (x^2, p^2) of the last two loaded
//    nodes;
//  - (a_fit, p0_fit) come from the least-squares line p^2 = A - B x^2 through all loaded
//    nodes but the last (whose tributary segment straddles the edge of contact):
//    p0_fit = sqrt(A), a_fit = sqrt(A / B).
HertzMeasurement MeasureHertz(const StaticProblem& problem, const StaticContactResult& r,
                              const HertzData& d, double h_contact) {
  struct Sample {
    double x, p, area;
    bool loaded;
  };
  std::vector<Sample> profile;
  const double threshold = 1e-9 * r.normal_force.maxCoeff();
  for (size_t c = 0; c < problem.nodes().size(); ++c) {
    const double lambda = r.normal_force(static_cast<Eigen::Index>(c));
    const double area = problem.nodes()[c].area;
    profile.push_back({problem.Position(c)(0), lambda / area, area, lambda > threshold});
  }
  std::sort(profile.begin(), profile.end(),
            [](const Sample& s, const Sample& t) { return s.x < t.x; });
  HertzMeasurement m;
  m.h_contact = h_contact;
  m.num_dofs = static_cast<int>(problem.K.rows());
  m.force = r.normal_force.sum();
  REQUIRE(profile.front().x == 0.0);
  m.p0_node = profile.front().p;
  double l2 = 0.0;
  for (const Sample& s : profile) {
    const double e = (s.p - d.Pressure(s.x)) / d.p0;
    m.max_error = std::max(m.max_error, std::abs(e));
    l2 += s.area * e * e;
    m.nodes_in_contact += s.loaded ? 1 : 0;
  }
  m.l2_error = std::sqrt(l2 / d.a);
  // The loaded nodes are the prefix 0 .. last of the sorted profile.
  size_t last = 0;
  while (last + 1 < profile.size() && profile[last + 1].loaded) ++last;
  CHECK(static_cast<int>(last) + 1 == m.nodes_in_contact);
  REQUIRE(last >= 3);
  REQUIRE(last + 1 < profile.size());
  m.x_last = profile[last].x;
  m.x_next = profile[last + 1].x;
  const double x1 = profile[last - 1].x, p1 = profile[last - 1].p;
  const double x2 = profile[last].x, p2 = profile[last].p;
  m.a_extrapolated =
      std::sqrt(x2 * x2 + p2 * p2 * (x2 * x2 - x1 * x1) / (p1 * p1 - p2 * p2));
  // Least squares for p^2 = A - B x^2 over nodes 0 .. last-1.
  Eigen::MatrixXd M(static_cast<Eigen::Index>(last), 2);
  Eigen::VectorXd y(static_cast<Eigen::Index>(last));
  for (size_t c = 0; c < last; ++c) {
    M(static_cast<Eigen::Index>(c), 0) = 1.0;
    M(static_cast<Eigen::Index>(c), 1) = -profile[c].x * profile[c].x / (d.a * d.a);
    y(static_cast<Eigen::Index>(c)) = profile[c].p * profile[c].p / (d.p0 * d.p0);
  }
  const Eigen::Vector2d AB = M.colPivHouseholderQr().solve(y);  // A / p0^2, B a^2 / p0^2
  m.p0_fit = d.p0 * std::sqrt(AB(0));
  m.a_fit = d.a * std::sqrt(AB(0) / AB(1));
  return m;
}

}  // namespace

TEST_CASE("Hertz: cylinder on a rigid plane, half-width, peak and profile converge",
          "[static][hertz]") {
  const HertzData d;
  std::printf(
      "\nHertz, plane strain cylinder on a rigid plane: R = %g m, E = %g Pa, nu = %g,"
      " P = %.6g N/m, a = %.6g m, p0 = %.6g Pa\n",
      d.R, kSteel.youngs_modulus, kSteel.poisson_ratio, d.P, d.a, d.p0);
  std::printf(
      "relative errors of a and p0 (node: extrapolated / nodal value; fit: least "
      "squares of p^2 = A - B x^2); bracket = [last loaded, first free node] / a;\n"
      "max and L2 errors of the nodal pressure relative to p0\n");
  std::printf("%9s %5s %6s %6s | %9s %9s %9s | %9s %9s | %8s %8s\n", "h [m]", "a/h",
              "dofs", "loaded", "a_extr", "a_fit", "bracket", "p0_node", "p0_fit",
              "max err", "L2 err");
  std::vector<HertzMeasurement> runs;
  for (const int elements_per_a : {10, 20, 40}) {
    const double h = d.a / elements_per_a;
    const StaticProblem problem = MakeHertzProblem(d, h);
    const StaticContactResult r =
        SolveStaticContact(2, problem.K, problem.f, problem.nodes(), SolverOptions());
    INFO(r.message);
    REQUIRE(r.converged);
    const ContactResiduals res = Recompute(problem, r);
    CHECK(res.equilibrium < 1e-10);
    CHECK(res.signorini < 1e-10);
    const HertzMeasurement m = MeasureHertz(problem, r, d, h);
    std::printf(
        "%9.2e %5d %6d %6d | %+9.2e %+9.2e %4.2f-%4.2f | %+9.2e %+9.2e | %8.2e %8.2e\n",
        h, elements_per_a, m.num_dofs, m.nodes_in_contact, m.a_extrapolated / d.a - 1,
        m.a_fit / d.a - 1, m.x_last / d.a, m.x_next / d.a, m.p0_node / d.p0 - 1,
        m.p0_fit / d.p0 - 1, m.max_error, m.l2_error);
    CAPTURE(elements_per_a);
    // Equilibrium of the quarter in y: the contact carries the load q R.
    CHECK_THAT(m.force, WithinRel(d.q * d.R, 1e-10));
    // The exact edge of contact lies between the last loaded and the first free node.
    CHECK(m.x_last <= d.a);
    CHECK(d.a <= m.x_next);
    // Accuracy on every mesh, a >= 10 elements across the half-width (measured on the
    // gmsh 4.8 meshes: a within 1.2%, p0 within 0.3%, max error 4.2% at the edge node,
    // fits within 0.06%).
    CHECK_THAT(m.a_extrapolated, WithinRel(d.a, 0.02));
    CHECK_THAT(m.p0_node, WithinRel(d.p0, 0.01));
    CHECK(m.max_error < 0.05);
    CHECK(m.l2_error < 0.02);
    CHECK_THAT(m.a_fit, WithinRel(d.a, 0.002));
    CHECK_THAT(m.p0_fit, WithinRel(d.p0, 0.002));
    runs.push_back(m);
  }
  // Convergence: the pressure error falls with h (the max error, which sits at the node
  // straddling the edge of contact where p ~ sqrt(a - x), falls slowly), and so do the
  // errors of the half-width and of the peak pressure from the coarse to the fine mesh.
  REQUIRE(runs.size() == 3);
  CHECK(runs[1].l2_error < 0.7 * runs[0].l2_error);
  CHECK(runs[2].l2_error < 0.7 * runs[1].l2_error);
  CHECK(runs[2].max_error < runs[0].max_error);
  CHECK(std::abs(runs[2].a_extrapolated / d.a - 1) <
        0.5 * std::abs(runs[0].a_extrapolated / d.a - 1));
  CHECK(std::abs(runs[2].p0_node / d.p0 - 1) <
        0.5 * std::abs(runs[0].p0_node / d.p0 - 1));
}

// Quadratic triangles with the mid-side nodes of the arc on the circle, h = a / 5 at the
// contact: the half-width (least-squares fit) and the peak pressure (node x = 0) within
// 0.2 % where T3 on the same mesh size has p0 1.6 % off.
TEST_CASE("Hertz with curved T6 at h = a/5: a and p0 within 0.2 %", "[static][hertz]") {
  const HertzData d;
  for (const int order : {1, 2}) {
    const double h = d.a / 5;
    const StaticProblem problem = MakeHertzProblem(d, h, order);
    const StaticContactResult r =
        SolveStaticContact(2, problem.K, problem.f, problem.nodes(), SolverOptions());
    INFO(r.message);
    REQUIRE(r.converged);
    const ContactResiduals res = Recompute(problem, r);
    CHECK(res.equilibrium < 1e-10);
    CHECK(res.signorini < 1e-10);
    const HertzMeasurement m = MeasureHertz(problem, r, d, h);
    std::printf(
        "Hertz a/h = 5, %s: %d dofs, a_extr %+.3f %%, a_fit %+.3f %%, p0_node %+.3f %%, "
        "p0_fit %+.3f %%\n",
        order == 2 ? "T6 (curved)" : "T3", m.num_dofs, 100 * (m.a_extrapolated / d.a - 1),
        100 * (m.a_fit / d.a - 1), 100 * (m.p0_node / d.p0 - 1),
        100 * (m.p0_fit / d.p0 - 1));
    CHECK_THAT(m.force, WithinRel(d.q * d.R, 1e-10));
    if (order == 2) {
      // (a_extrapolated leans on the node straddling the edge of contact, measured
      // -0.76 %; the fit through the loaded nodes is the half-width of the profile.)
      CHECK_THAT(m.a_fit, WithinRel(d.a, 0.002));
      CHECK_THAT(m.p0_node, WithinRel(d.p0, 0.002));
    } else {
      CHECK(std::abs(m.p0_node / d.p0 - 1) > 0.01);
    }
  }
}

TEST_CASE("Semismooth Newton (FB and min) and Ipopt agree on the Hertz problem",
          "[static][hertz][ipopt]") {
  const HertzData d;
  const StaticProblem problem = MakeHertzProblem(d, d.a / 10);
  StaticContactResult fb =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(),
                         SolverOptions(ncp::NcpFunction::kFischerBurmeister));
  StaticContactResult min = SolveStaticContact(2, problem.K, problem.f, problem.nodes(),
                                               SolverOptions(ncp::NcpFunction::kMin));
  StaticContactResult ipopt =
      SolveStaticContactIpopt(2, problem.K, problem.f, problem.nodes(), 1e-14);
  INFO(fb.message << " | " << min.message << " | " << ipopt.message);
  REQUIRE(fb.converged);
  REQUIRE(min.converged);
  REQUIRE(UsableIpoptResult(ipopt));
  for (const StaticContactResult* r : {&fb, &min, &ipopt}) {
    const ContactResiduals res = Recompute(problem, *r);
    CHECK(res.equilibrium < 1e-10);
    CHECK(res.signorini < 1e-10);
  }
  const double du_min = RelativeDifference(min.u, fb.u);
  const double dl_min = RelativeDifference(min.normal_force, fb.normal_force);
  const double du_ipopt = RelativeDifference(ipopt.u, fb.u);
  const double dl_ipopt = RelativeDifference(ipopt.normal_force, fb.normal_force);
  std::printf(
      "Hertz a/h = 10 (%d dofs, %zu contact nodes): FB %d its, min %d its, Ipopt %d its;"
      " min vs FB |du|/|u| %.1e |dlambda|/|lambda| %.1e; Ipopt vs FB %.1e %.1e\n",
      static_cast<int>(problem.K.rows()), problem.nodes().size(), fb.newton_iterations,
      min.newton_iterations, ipopt.newton_iterations, du_min, dl_min, du_ipopt, dl_ipopt);
  CHECK(du_min < 1e-8);
  CHECK(dl_min < 1e-8);
  CHECK(du_ipopt < 1e-8);
  CHECK(dl_ipopt < 1e-8);
}

TEST_CASE("Default static solve of Hertz: closed start, few Newton iterations",
          "[static][hertz]") {
  // The defaults (StaticContactOptions: closed start, min function) against the closed
  // form, and the Newton iteration count against the u = 0 start with Fischer-Burmeister
  // (the earlier defaults, which cut their first steps back to ~2e-3 while the body,
  // held only by the contact, moves onto the floor).
  const HertzData d;
  const double h = d.a / 10;
  const StaticProblem problem = MakeHertzProblem(d, h);
  const StaticContactResult r = SolveStaticContact(
      2, problem.K, problem.f, problem.nodes(), StaticContactOptions());
  StaticContactOptions earlier;
  earlier.start = StaticStart::kZero;
  earlier.ncp.ncp_function = ncp::NcpFunction::kFischerBurmeister;
  const StaticContactResult e =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), earlier);
  INFO(r.message << " | " << e.message);
  REQUIRE(r.converged);
  REQUIRE(e.converged);
  CHECK(r.closed_start);
  CHECK_FALSE(e.closed_start);
  const ContactResiduals res = Recompute(problem, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  const HertzMeasurement m = MeasureHertz(problem, r, d, h);
  CHECK_THAT(m.a_extrapolated, WithinRel(d.a, 0.02));
  CHECK_THAT(m.p0_node, WithinRel(d.p0, 0.01));
  CHECK_THAT(m.force, WithinRel(d.q * d.R, 1e-10));
  CHECK(RelativeDifference(r.normal_force, e.normal_force) < 1e-8);
  std::printf("Hertz a/h = 10, Newton iterations: default %d, u = 0 start with FB %d\n",
              r.newton_iterations, e.newton_iterations);
  constexpr int kDefaultHertzIterations = 8;
  CHECK(r.newton_iterations <= kDefaultHertzIterations);
  CHECK(e.newton_iterations > kDefaultHertzIterations);
}

// ---------------------------------------------------------------------------------------
// Friction: Tresca and Coulomb
// ---------------------------------------------------------------------------------------

namespace {

// A block [0, 2] x [0, 1] m (plane strain, 16 x 8 Q4) on the floor {y <= 0}, gap 0,
// loaded on the top by the traction (s, -p): pressed down and pulled along +x.
constexpr double kBlockPressure = 10e6;  // p [Pa]
constexpr double kBlockShear = 2e6;      // s [Pa]
constexpr double kBlockLength = 2.0;     // [m]

Mesh BlockMesh() {
  RectangleMeshOptions o;
  o.size = {kBlockLength, 1.0};
  o.cells = {16, 8};
  o.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                  {Side::kYMin, BoundaryRole::kContact},
                  {Side::kYMax, BoundaryRole::kLoad}};
  return MakeRectangleMesh(o);
}

StaticProblem BlockProblem(const std::vector<DirichletCondition>& conditions) {
  Mesh mesh = BlockMesh();
  DofMap dofs = MakeDofMap(mesh, conditions);
  return StaticProblem(ElasticBody(std::move(mesh), kSteel), std::move(dofs),
                       HalfSpace::ObstacleBelow(2, 1, 0.0),
                       Eigen::Vector2d(kBlockShear, -kBlockPressure));
}

// u ~ p L / E for the block [m].
constexpr double kBlockDisplacement = kBlockPressure / 210e9;

// A node of the floor has a free tangent when its x component is free.
bool HasFreeTangent(const ContactNode& node) { return node.dofs[0] >= 0; }

// Tresca's law recomputed at every contact node from u and the returned forces (2D):
// with slip_c = t_c . u_c (the static slip, contact_system.hpp),
//   |tau_c| <= g_c,   and   slip_c != 0  =>  tau_c = -g_c sign(slip_c);
// a node whose x is constrained carries no friction (tau_c = 0). A node slips when
// |slip_c| > 1e-9 ||u||_inf (the solves are accurate to ~1e-13 ||u||).
struct FrictionCheck {
  double bound_excess =
      -std::numeric_limits<double>::infinity();  // max_c (|tau_c| - g_c) / max g
  double slip_law = 0;  // max over slipping nodes of |tau_c + g_c sign(slip_c)| / max g
  double constrained_tau = 0;  // max |tau_c| at nodes without a free tangent [N]
  int sticking = 0;
  int slipping = 0;
};

FrictionCheck CheckTresca(const StaticProblem& problem, const StaticContactResult& r,
                          const Vector& g) {
  REQUIRE(r.tangent_force.rows() == 1);
  const double g_scale = std::max(g.maxCoeff(), 1e-300);
  const double slip_threshold = 1e-9 * r.u.lpNorm<Eigen::Infinity>();
  FrictionCheck out;
  for (size_t c = 0; c < problem.nodes().size(); ++c) {
    const ContactNode& node = problem.nodes()[c];
    const auto k = static_cast<Eigen::Index>(c);
    const double tau = r.tangent_force(0, k);
    if (!HasFreeTangent(node)) {
      out.constrained_tau = std::max(out.constrained_tau, std::abs(tau));
      continue;
    }
    const double slip = node.tangent1.dot(NodeDisplacement(node, 2, r.u));
    out.bound_excess = std::max(out.bound_excess, (std::abs(tau) - g(k)) / g_scale);
    if (std::abs(slip) > slip_threshold) {
      ++out.slipping;
      out.slip_law = std::max(out.slip_law,
                              std::abs(tau + g(k) * (slip > 0 ? 1.0 : -1.0)) / g_scale);
    } else {
      ++out.sticking;
    }
  }
  return out;
}

// Full displacement vector (all Dirichlet conditions here are homogeneous).
Vector FullDisplacement(const StaticProblem& problem, const Vector& u_free) {
  return problem.dofs.ExpandHomogeneous(u_free);
}

// The reference for sticking: every contact node's x fixed (a Dirichlet condition on the
// "contact" group), frictionless in y. Returns the full u and, per contact node of
// `problem`, the x reaction R = (K u - f)_x, which is the friction force on the body.
struct StuckReference {
  Vector u_full;
  Vector tangent_reaction;  // per contact node of the frictional problem [N]
};

StuckReference SolveStuck(const StaticProblem& frictional,
                          std::vector<DirichletCondition> conditions) {
  conditions.push_back(DirichletCondition{kContactGroup, {0}, {}});
  const StaticProblem stuck = BlockProblem(conditions);
  REQUIRE(stuck.nodes().size() == frictional.nodes().size());
  const StaticContactResult r =
      SolveStaticContact(2, stuck.K, stuck.f, stuck.nodes(), SolverOptions());
  INFO(r.message);
  REQUIRE(r.converged);
  const ContactResiduals res = Recompute(stuck, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  StuckReference out;
  out.u_full = FullDisplacement(stuck, r.u);
  const Vector reaction = stuck.K_full * out.u_full - stuck.f_full;
  out.tangent_reaction.resize(static_cast<Eigen::Index>(frictional.nodes().size()));
  for (size_t c = 0; c < frictional.nodes().size(); ++c)
    out.tangent_reaction(static_cast<Eigen::Index>(c)) =
        frictional.nodes()[c].tangent1.x() * reaction(2 * frictional.nodes()[c].node);
  return out;
}

}  // namespace

TEST_CASE("Tresca, bound above every stuck nodal force: the block sticks",
          "[static][friction]") {
  // No Dirichlet condition at all: friction alone holds the block against the pull s L.
  const StaticProblem problem = BlockProblem({});
  const StuckReference stuck = SolveStuck(problem, {});
  const double max_reaction = stuck.tangent_reaction.cwiseAbs().maxCoeff();
  // Friction balances the pull: sum_c tau_c = -s L.
  CHECK_THAT(stuck.tangent_reaction.sum(), WithinRel(-kBlockShear * kBlockLength, 1e-10));

  StaticContactOptions options = SolverOptions();
  options.friction = FrictionLaw::kTresca;
  options.tresca_bound = Vector::Constant(
      static_cast<Eigen::Index>(problem.nodes().size()), 1.5 * max_reaction);
  const StaticContactResult r =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options);
  INFO(r.message);
  REQUIRE(r.converged);
  const ContactResiduals res = Recompute(problem, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  const FrictionCheck fc = CheckTresca(problem, r, options.tresca_bound);
  CHECK(fc.slipping == 0);
  CHECK(fc.sticking == static_cast<int>(problem.nodes().size()));
  CHECK(fc.bound_excess < -0.3);  // g = 1.5 max |tau|: |tau_c| - g <= -g / 3
  // Same displacement and friction forces as with the contact nodes' x fixed.
  const double du = RelativeDifference(FullDisplacement(problem, r.u), stuck.u_full);
  const double dtau =
      RelativeDifference(r.tangent_force.row(0).transpose(), stuck.tangent_reaction);
  std::printf(
      "Tresca all-stick: %d Newton its; vs x-fixed reference |du|/|u| %.1e, "
      "|dtau|/|tau| %.1e\n",
      r.newton_iterations, du, dtau);
  CHECK(du < 1e-8);
  CHECK(dtau < 1e-8);
}

TEST_CASE("Tresca with a zero bound is frictionless", "[static][friction]") {
  // Roller u_x = 0 on x = 0 takes the pull.
  const StaticProblem problem = BlockProblem({DirichletCondition{kFixedGroup, {0}, {}}});
  const StaticContactResult frictionless =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), SolverOptions());
  StaticContactOptions options = SolverOptions();
  options.friction = FrictionLaw::kTresca;
  options.tresca_bound = Vector::Zero(static_cast<Eigen::Index>(problem.nodes().size()));
  const StaticContactResult tresca =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options);
  INFO(frictionless.message << " | " << tresca.message);
  REQUIRE(frictionless.converged);
  REQUIRE(tresca.converged);
  CHECK(Recompute(problem, tresca).equilibrium < 1e-10);
  CHECK(Recompute(problem, tresca).signorini < 1e-10);
  CHECK(RelativeDifference(tresca.u, frictionless.u) < 1e-10);
  CHECK(RelativeDifference(tresca.normal_force, frictionless.normal_force) < 1e-10);
  CHECK(tresca.tangent_force.cwiseAbs().maxCoeff() <
        1e-12 * frictionless.normal_force.maxCoeff());
  // The floor nodes slide along +x: the block stretches under the pull.
  CHECK(CheckTresca(problem, tresca, options.tresca_bound).slipping ==
        static_cast<int>(problem.nodes().size()) - 1);
}

TEST_CASE("Tresca below the stuck forces: stick and slip zones obey the law",
          "[static][friction]") {
  // Roller u_x = 0 on x = 0; bound a fraction of the largest stuck nodal force: some
  // nodes stick near the roller, the others slip (fraction 0.3), or all slip (fraction
  // 0.01).
  const double fraction = GENERATE(0.3, 0.01);
  CAPTURE(fraction);
  const std::vector<DirichletCondition> roller{DirichletCondition{kFixedGroup, {0}, {}}};
  const StaticProblem problem = BlockProblem(roller);
  const StuckReference stuck = SolveStuck(problem, roller);
  StaticContactOptions options = SolverOptions();
  options.friction = FrictionLaw::kTresca;
  options.tresca_bound =
      Vector::Constant(static_cast<Eigen::Index>(problem.nodes().size()),
                       fraction * stuck.tangent_reaction.cwiseAbs().maxCoeff());
  const StaticContactResult r =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options);
  INFO(r.message);
  REQUIRE(r.converged);
  const ContactResiduals res = Recompute(problem, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  const FrictionCheck fc = CheckTresca(problem, r, options.tresca_bound);
  std::printf(
      "Tresca bound %.2f x max stuck force: %d Newton its, %d stick, %d slip, bound "
      "excess %.1e, slip law %.1e\n",
      fraction, r.newton_iterations, fc.sticking, fc.slipping, fc.bound_excess,
      fc.slip_law);
  CHECK(fc.bound_excess < 1e-10);
  CHECK(fc.slip_law < 1e-10);
  CHECK(fc.constrained_tau == 0.0);
  CHECK(fc.slipping > 0);
  if (fraction > 0.1)
    CHECK(fc.sticking > 0);
  else
    CHECK(fc.sticking == 0);
}

TEST_CASE("Coulomb by fixed point: converges and |tau| <= f lambda, = where slipping",
          "[static][friction][coulomb]") {
  const double friction_coefficient = 0.2;
  const StaticProblem problem = BlockProblem({DirichletCondition{kFixedGroup, {0}, {}}});
  StaticContactOptions options = SolverOptions();
  options.friction = FrictionLaw::kCoulomb;
  options.friction_coefficient = friction_coefficient;
  const StaticContactResult r =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options);
  INFO(r.message);
  REQUIRE(r.converged);
  const ContactResiduals res = Recompute(problem, r);
  CHECK(res.equilibrium < 1e-10);
  CHECK(res.signorini < 1e-10);
  // Coulomb's law is Tresca's with g_c = f lambda_c of the solution itself.
  const Vector g = friction_coefficient * r.normal_force;
  const FrictionCheck fc = CheckTresca(problem, r, g);
  std::printf(
      "Coulomb f = %.2f: %d fixed-point iterations, %d Newton its, %d stick, %d slip, "
      "bound excess %.1e, slip law %.1e\n",
      friction_coefficient, r.fixed_point_iterations, r.newton_iterations, fc.sticking,
      fc.slipping, fc.bound_excess, fc.slip_law);
  CHECK(r.fixed_point_iterations > 1);
  CHECK(r.fixed_point_iterations <= options.max_fixed_point_iterations);
  CHECK(fc.bound_excess < 1e-8);
  CHECK(fc.slip_law < 1e-8);
  CHECK(fc.sticking > 0);
  CHECK(fc.slipping > 0);
  // A fixed point: the Tresca problem with g = f lambda gives the same solution back.
  StaticContactOptions tresca = SolverOptions();
  tresca.friction = FrictionLaw::kTresca;
  tresca.tresca_bound = g;
  const StaticContactResult again =
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), tresca);
  REQUIRE(again.converged);
  CHECK(RelativeDifference(again.u, r.u) < 1e-8);
  CHECK(RelativeDifference(again.normal_force, r.normal_force) < 1e-8);
}

TEST_CASE("Static contact rejects bad friction input with a message",
          "[static][errors]") {
  const StaticProblem problem = BlockProblem({DirichletCondition{kFixedGroup, {0}, {}}});
  const auto num_nodes = static_cast<Eigen::Index>(problem.nodes().size());
  StaticContactOptions options;
  options.friction = FrictionLaw::kTresca;
  options.tresca_bound = Vector::Constant(num_nodes - 1, 1.0);
  CHECK_THROWS_AS(SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
                  std::invalid_argument);
  CHECK_THROWS_WITH(
      SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
      Contains("tresca_bound needs one value per contact node (" +
               std::to_string(num_nodes) + "), got " + std::to_string(num_nodes - 1)));
  options.tresca_bound = Vector::Constant(num_nodes, 1.0);
  options.tresca_bound(3) = -5.0;
  CHECK_THROWS_AS(SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
                  std::invalid_argument);
  CHECK_THROWS_WITH(SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
                    Contains("tresca_bound[3] must be finite and >= 0 N, got -5"));
  // (The value after "got" is the bound divided by the scaling k = max K_ii and printed
  // with 6 decimals, "-0.000000" here: not checked.)

  options = StaticContactOptions();
  options.friction = FrictionLaw::kCoulomb;
  for (const double f : {-0.1, std::numeric_limits<double>::quiet_NaN()}) {
    options.friction_coefficient = f;
    CAPTURE(f);
    CHECK_THROWS_AS(SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
                    std::invalid_argument);
    CHECK_THROWS_WITH(
        SolveStaticContact(2, problem.K, problem.f, problem.nodes(), options),
        Contains("friction_coefficient must be >= 0"));
  }
}

TEST_CASE("min function on the Hex8 patch from the tied start point", "[static][patch]") {
  // SolveStaticContact starts from u = 0, where lambda_c = gap_c = 0 at every node. With
  // the min rule's tie taking grad lambda_c, the first Newton matrix was the stiffness
  // itself, singular because only the contact holds the block vertically (500 gradient
  // steps, ||Phi|| stuck at 1.5e-6). The contact module's default takes grad gap_c at a
  // tie (ContactNcpOptions: the node counts as closed): Newton from the first step.
  const PatchSetup s = MakePatch(
      {"Hex8 structured", ElementType::kHexahedron8, MeshTopology::kStructured});
  const double u_scale = s.p / kSteel.youngs_modulus;
  const StaticContactOptions options = SolverOptions(ncp::NcpFunction::kMin);

  // The same system started from a point pressing every node 1e-3 u_scale into the floor
  // (gap_c < 0 = lambda_c: the gap branch) converges in a few Newton steps.
  const double k = [&] {
    double m = 0;
    for (Eigen::Index i = 0; i < s.problem.K.rows(); ++i)
      m = std::max(m, s.problem.K.coeff(i, i));
    return m;
  }();
  ContactSystem system(3, s.problem.K / k, s.problem.nodes());
  system.Update(-s.problem.f / k, Vector::Zero(s.problem.K.rows()), Vector());
  Vector guess = Vector::Zero(s.problem.K.rows());
  for (const ContactNode& node : s.problem.nodes()) guess(node.dofs[2]) = -1e-3 * u_scale;
  ncp::Vector z = system.StartPoint(guess);
  ncp::Summary summary;
  ncp::Solve(options.ncp, system, &z, &summary);
  INFO(summary.BriefReport());
  CHECK(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_failures == 0);
  CHECK(RelativeDifference(system.Extract(z).x, s.u_exact) < 1e-8);

  const StaticContactResult newton =
      SolveStaticContact(3, s.problem.K, s.problem.f, s.problem.nodes(), options);
  INFO(newton.message << "; linear solver failures "
                      << newton.last_summary.linear_solver_failures);
  CHECK(newton.converged);
  CHECK(newton.last_summary.linear_solver_failures == 0);
  CHECK(RelativeDifference(newton.u, s.u_exact) < 1e-8);
}
