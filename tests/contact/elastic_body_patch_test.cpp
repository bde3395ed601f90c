// Patch tests (Irons): linear elements reproduce any linear displacement field exactly,
// on distorted and unstructured meshes, for T3, Q4, Tet4 and Hex8.
//
//  1. Equilibrium: for u(x) = a + B x the stress sigma = C sym(B) is constant, so
//     K u equals the consistent nodal forces of the traction sigma n on the whole
//     boundary and vanishes at interior nodes.
//  2. Dirichlet patch: solving K_FF u_F = -K_FC u_C with u_C from the linear field on
//     the boundary reproduces the field at the interior nodes.
#include <Eigen/SparseCholesky>
#include <catch2/catch.hpp>
#include <contact/dof_map.hpp>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>
#include <cstdio>
#include <string>

#include "fem_test_support.hpp"

namespace contact {
namespace {

struct PatchMesh {
  std::string label;
  Mesh mesh;
};

std::map<Side, BoundaryRole> AllSides(int dim, BoundaryRole role) {
  std::map<Side, BoundaryRole> roles = {
      {Side::kXMin, role}, {Side::kXMax, role}, {Side::kYMin, role}, {Side::kYMax, role}};
  if (dim == 3) {
    roles[Side::kZMin] = role;
    roles[Side::kZMax] = role;
  }
  return roles;
}

// Distorted or unstructured meshes of [0.3, 1.5] x [-0.2, 0.7] (x [0.1, 0.9]) whose whole
// boundary is the group of `role`.
std::vector<PatchMesh> PatchMeshes(BoundaryRole role) {
  std::vector<PatchMesh> meshes;
  for (const ElementType type : {ElementType::kTriangle3, ElementType::kQuadrilateral4}) {
    RectangleMeshOptions options;
    options.origin = {0.3, -0.2};
    options.size = {1.2, 0.9};
    options.cells = {6, 5};
    options.element_type = type;
    options.side_roles = AllSides(2, role);
    Mesh structured = MakeRectangleMesh(options);
    testing::PerturbInteriorNodes(&structured, 0.18, 0.24);
    meshes.push_back({std::string(ToString(type)) + " distorted", structured});
    options.topology = MeshTopology::kUnstructured;
    meshes.push_back(
        {std::string(ToString(type)) + " unstructured", MakeRectangleMesh(options)});
  }
  BoxMeshOptions box;
  box.origin = {0.3, -0.2, 0.1};
  box.size = {1.2, 0.9, 0.8};
  box.cells = {5, 4, 4};
  box.side_roles = AllSides(3, role);
  box.element_type = ElementType::kHexahedron8;
  Mesh hexes = MakeBoxMesh(box);
  testing::PerturbInteriorNodes(&hexes, 0.2, 0.24);
  meshes.push_back({"Hexahedron8 distorted", hexes});
  box.element_type = ElementType::kTetrahedron4;
  box.topology = MeshTopology::kUnstructured;
  meshes.push_back({"Tetrahedron4 unstructured", MakeBoxMesh(box)});
  box.topology = MeshTopology::kStructured;
  Mesh tets = MakeBoxMesh(box);
  testing::PerturbInteriorNodes(&tets, 0.2, 0.15);
  meshes.push_back({"Tetrahedron4 distorted", tets});
  return meshes;
}

const IsotropicMaterial kSteel{210e9, 0.3, 7850};

// A general (non-symmetric) displacement gradient: strain plus rotation, in 1e-3.
Eigen::MatrixXd Gradient(int dim) {
  Eigen::MatrixXd B(3, 3);
  B << 1.0, 0.4, -0.7,  //
      -0.2, 2.0, 0.5,   //
      0.3, 0.9, -1.5;
  return 1e-3 * B.topLeftCorner(dim, dim);
}

// Constant Cauchy stress of u = a + B x: sigma = lambda tr(eps) I + 2 mu eps.
Eigen::MatrixXd Stress(const Eigen::MatrixXd& B, const IsotropicMaterial& material,
                       PlaneModel model) {
  const Eigen::MatrixXd eps = 0.5 * (B + B.transpose());
  const double lambda =
      ElasticityMatrix(material, static_cast<int>(B.rows()), model)(0, 1);
  return lambda * eps.trace() * Eigen::MatrixXd::Identity(B.rows(), B.cols()) +
         2 * material.ShearModulus() * eps;
}

TEST_CASE("patch test: K u of a linear field equals the boundary tractions", "[patch]") {
  for (const PlaneModel model : {PlaneModel::kPlaneStrain, PlaneModel::kPlaneStress}) {
    for (const PatchMesh& patch : PatchMeshes(BoundaryRole::kLoad)) {
      if (patch.mesh.dim == 3 && model == PlaneModel::kPlaneStress) continue;
      const ElasticBody body(patch.mesh, kSteel, {model, 0.35});
      const int dim = body.dim();
      const Eigen::MatrixXd B = Gradient(dim);
      const Eigen::VectorXd a = Eigen::VectorXd::LinSpaced(dim, 1e-3, 2e-3);
      const Eigen::MatrixXd sigma = Stress(B, kSteel, model);

      const Vector internal_forces =
          body.StiffnessMatrix() * testing::LinearField(body.mesh(), a, B);
      const Vector boundary_forces = body.TractionFieldLoad(
          [&](const Eigen::VectorXd&, const Eigen::VectorXd& n) -> Eigen::VectorXd {
            return sigma * n;
          });
      const double error = (internal_forces - boundary_forces).lpNorm<Eigen::Infinity>() /
                           boundary_forces.lpNorm<Eigen::Infinity>();
      std::printf("patch equilibrium %-26s %-12s  max|Ku - f_t| / max|f_t| = %.2e\n",
                  patch.label.c_str(),
                  model == PlaneModel::kPlaneStrain ? "plane strain" : "plane stress",
                  error);
      INFO(patch.label);
      CHECK(error < 1e-12);
      // Interior nodes are in equilibrium: boundary_forces vanish there by construction,
      // and it is not the zero vector overall.
      CHECK(boundary_forces.norm() > 1e3);
    }
  }
}

TEST_CASE("patch test: Dirichlet data of a linear field is reproduced inside",
          "[patch]") {
  for (const PatchMesh& patch : PatchMeshes(BoundaryRole::kFixed)) {
    const ElasticBody body(patch.mesh, kSteel, {PlaneModel::kPlaneStress, 0.35});
    const int dim = body.dim();
    const Eigen::MatrixXd B = Gradient(dim);
    const Eigen::VectorXd a = Eigen::VectorXd::LinSpaced(dim, -1e-3, 2e-3);
    const Vector exact = testing::LinearField(body.mesh(), a, B);

    DirichletCondition condition;
    condition.displacement = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return a + B * x;
    };
    const DofMap dofs = MakeDofMap(body.mesh(), {condition});
    REQUIRE(dofs.NumFreeDofs() > 0);
    const SparseMatrix K = body.StiffnessMatrix();
    Eigen::SimplicialLDLT<SparseMatrix> solver(dofs.RestrictMatrix(K));
    REQUIRE(solver.info() == Eigen::Success);
    const Vector u_free =
        solver.solve(dofs.RestrictLoad(K, Vector::Zero(body.NumDofs())));
    const Vector u = dofs.Expand(u_free);
    const double error = (dofs.RestrictVector(u - exact)).lpNorm<Eigen::Infinity>() /
                         exact.lpNorm<Eigen::Infinity>();
    std::printf(
        "patch Dirichlet   %-26s interior dofs %4d  max|u_h - u| / max|u| = %.2e\n",
        patch.label.c_str(), dofs.NumFreeDofs(), error);
    INFO(patch.label);
    CHECK(error < 1e-10);
  }
}

}  // namespace
}  // namespace contact
