// The OpenMP loops (batched element matrices in the assembly, SymmetricMultiply) give the
// same bits for 1 and 2 threads, and SymmetricMultiply is the product K x.
#include <omp.h>

#include <catch2/catch.hpp>

#include "contact/dynamics.hpp"
#include "contact/elastic_body.hpp"
#include "contact/mesh_generation.hpp"

using namespace contact;

namespace {

// Restores the thread count a test changed.
struct ThreadCount {
  int saved = omp_get_max_threads();
  explicit ThreadCount(int n) { omp_set_num_threads(n); }
  ~ThreadCount() { omp_set_num_threads(saved); }
};

bool SameBits(const SparseMatrix& a, const SparseMatrix& b) {
  if (a.nonZeros() != b.nonZeros() || a.rows() != b.rows()) return false;
  return std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(),
                    b.innerIndexPtr());
}

}  // namespace

TEST_CASE("Parallel assembly and K x are bit-for-bit those of one thread", "[parallel]") {
  // 20^3 Hex8 (27783 dofs, 8000 elements): above the thresholds where the loops go
  // parallel (256 elements per batch, 20000 rows).
  BoxMeshOptions o;
  o.cells = {20, 20, 20};
  const ElasticBody body(MakeStructuredBoxMesh(o), IsotropicMaterial{210e9, 0.3, 7850.0});
  SparseMatrix K1, M1, K2, M2;
  Eigen::VectorXd y1, y2;
  const Eigen::VectorXd x = Eigen::VectorXd::Random(body.NumDofs());
  {
    ThreadCount one(1);
    K1 = body.StiffnessMatrix();
    M1 = body.ConsistentMassMatrix();
    SymmetricMultiply(K1, x, &y1);
  }
  {
    ThreadCount two(2);
    REQUIRE(omp_get_max_threads() == 2);
    K2 = body.StiffnessMatrix();
    M2 = body.ConsistentMassMatrix();
    SymmetricMultiply(K2, x, &y2);
  }
  CHECK(SameBits(K1, K2));
  CHECK(SameBits(M1, M2));
  CHECK(y1 == y2);
  // And it is K x (Eigen's column-major product sums in another order: round-off only).
  const Eigen::VectorXd reference = K1 * x;
  CHECK((y1 - reference).lpNorm<Eigen::Infinity>() <=
        1e-12 * reference.lpNorm<Eigen::Infinity>());
  CHECK_THROWS_WITH(SymmetricMultiply(K1, Eigen::VectorXd::Zero(3), &y1),
                    Catch::Contains("as many columns as x has entries"));
}
