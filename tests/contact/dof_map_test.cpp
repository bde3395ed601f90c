// DofMap: restriction and expansion against dense index arithmetic; MakeDofMap.
#include <catch2/catch.hpp>
#include <contact/dof_map.hpp>
#include <contact/mesh_generation.hpp>

namespace contact {
namespace {

SparseMatrix RandomSymmetric(int n, unsigned seed) {
  std::srand(seed);
  DenseMatrix A = DenseMatrix::Random(n, n);
  A = (A + A.transpose()).eval();
  A(1, 4) = A(4, 1) = 0.0;  // a structural hole
  return A.sparseView();
}

TEST_CASE("DofMap restricts and expands with prescribed values", "[dof_map]") {
  const int n = 7;
  const std::vector<int> constrained = {5, 1, 3, 1};  // unordered, duplicate
  Vector u_full = Vector::Zero(n);
  u_full(1) = 0.25;
  u_full(3) = -1.5;
  u_full(5) = 2.0;
  u_full(0) = 99.0;  // free: ignored
  const DofMap dofs(n, constrained, u_full);
  REQUIRE(dofs.NumFreeDofs() == 4);
  REQUIRE(dofs.NumConstrainedDofs() == 3);
  CHECK(dofs.FreeDofs() == std::vector<int>{0, 2, 4, 6});
  CHECK(dofs.ConstrainedDofs() == std::vector<int>{1, 3, 5});
  CHECK(dofs.FreeIndex(4) == 2);
  CHECK(dofs.FreeIndex(3) == -1);
  CHECK(dofs.PrescribedValues()(0) == 0.0);
  CHECK(dofs.PrescribedValues()(5) == 2.0);

  const SparseMatrix K = RandomSymmetric(n, 3);
  const DenseMatrix Kd = DenseMatrix(K);
  const Vector f = Vector::LinSpaced(n, 1.0, 7.0);
  const std::vector<int> F = {0, 2, 4, 6}, C = {1, 3, 5};

  const DenseMatrix K_FF = DenseMatrix(dofs.RestrictMatrix(K));
  Vector expected_load(4);
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) CHECK(K_FF(a, b) == Kd(F[a], F[b]));
    expected_load(a) = f(F[a]);
    for (const int c : C) expected_load(a) -= Kd(F[a], c) * u_full(c);
  }
  CHECK((dofs.RestrictLoad(K, f) - expected_load).norm() < 1e-14);
  CHECK(DenseMatrix(dofs.RestrictionMatrix() * K * dofs.RestrictionMatrix().transpose())
            .isApprox(K_FF, 0.0));

  const Vector u_free = Vector::LinSpaced(4, 10.0, 40.0);
  Vector expanded(n);
  expanded << 10.0, 0.25, 20.0, -1.5, 30.0, 2.0, 40.0;
  CHECK(dofs.Expand(u_free) == expanded);
  Vector homogeneous = expanded;
  homogeneous(1) = homogeneous(3) = homogeneous(5) = 0.0;
  CHECK(dofs.ExpandHomogeneous(u_free) == homogeneous);
  CHECK(dofs.RestrictVector(expanded) == u_free);

  DofMap moved = dofs;
  moved.SetPrescribedValues(Vector::Constant(n, 3.0));
  CHECK(moved.Expand(u_free)(3) == 3.0);
  CHECK(moved.PrescribedValues()(2) == 0.0);
}

TEST_CASE("DofMap rejects sizes and indices with expected vs actual", "[dof_map]") {
  CHECK_THROWS_WITH(DofMap(4, {4}),
                    Catch::Contains("[0, 4)") && Catch::Contains("got 4"));
  CHECK_THROWS_WITH(DofMap(4, {0}, Vector::Zero(3)),
                    Catch::Contains("must have size 4, got 3"));
  const DofMap dofs(4, {0});
  CHECK_THROWS_WITH(dofs.Expand(Vector::Zero(4)),
                    Catch::Contains("must have size 3, got 4"));
  CHECK_THROWS_WITH(dofs.RestrictMatrix(SparseMatrix(5, 5)),
                    Catch::Contains("must have size 4, got 5"));
}

TEST_CASE("MakeDofMap constrains group nodes per component", "[dof_map]") {
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {4, 2};
  options.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                        {Side::kYMin, BoundaryRole::kContact}};
  const Mesh mesh = MakeRectangleMesh(options);

  DirichletCondition clamp;  // all components on "fixed": 3 nodes x 2
  DirichletCondition roller;
  roller.group = kContactGroup;  // y only on the 5 bottom nodes, u_y = 0.01 x
  roller.components = {1};
  roller.displacement = [](const Eigen::VectorXd& x) {
    return Eigen::Vector2d(123.0, 0.01 * x(0)).eval();
  };
  const DofMap dofs = MakeDofMap(mesh, {clamp, roller});
  // x-dofs: 3 fixed; y-dofs: 3 fixed + 5 bottom - 1 shared corner.
  CHECK(dofs.NumConstrainedDofs() == 3 + 7);
  for (int i = 0; i < mesh.NumNodes(); ++i) {
    const Eigen::Vector2d x = mesh.nodes.col(i);
    const bool left = std::abs(x(0)) < 1e-12, bottom = std::abs(x(1)) < 1e-12;
    CHECK(dofs.IsConstrained(2 * i) == left);
    CHECK(dofs.IsConstrained(2 * i + 1) == (left || bottom));
    if (bottom) CHECK(dofs.PrescribedValues()(2 * i + 1) == Approx(0.01 * x(0)));
    CHECK(dofs.PrescribedValues()(2 * i) == 0.0);
  }

  DirichletCondition bad_component;
  bad_component.components = {2};
  CHECK_THROWS_WITH(MakeDofMap(mesh, {bad_component}),
                    Catch::Contains("component must lie in [0, 2), got 2"));
  DirichletCondition missing;
  missing.group = "clamp";
  CHECK_THROWS_WITH(MakeDofMap(mesh, {missing}),
                    Catch::Contains("no boundary group 'clamp'"));
  DirichletCondition wrong_size;
  wrong_size.displacement = [](const Eigen::VectorXd&) {
    return Eigen::VectorXd::Zero(3).eval();
  };
  CHECK_THROWS_WITH(MakeDofMap(mesh, {wrong_size}),
                    Catch::Contains("must have 2 components, got 3"));
}

}  // namespace
}  // namespace contact
