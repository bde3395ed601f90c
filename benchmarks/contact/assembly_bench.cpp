// contact-assembly-bench: assembly cost of the 3D Hex8 FEM model on cube meshes from
// ~10^3 to ~10^6 dofs. One row per mesh: dofs, elements, mesh generation time (direct
// structured generator, and the gmsh transfinite path up to --gmsh-max-dofs, default: all
// sizes), set-up time (ElasticBody: mesh validation and sparsity pattern), K and M
// assembly times, nnz. The last line fits log(time) = slope log(elements) + c: linear
// assembly has slope ~1.
//
// Usage: contact-assembly-bench [--max-dofs N] [--gmsh-max-dofs N]
#include <chrono>
#include <cmath>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "log_log_slope.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  long long max_dofs = 1100000;
  long long gmsh_max_dofs = -1;  // -1: same as max_dofs
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--max-dofs"))
      max_dofs = std::atoll(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--gmsh-max-dofs"))
      gmsh_max_dofs = std::atoll(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: %s [--max-dofs N] [--gmsh-max-dofs N]\n", argv[0]);
      return 2;
    }
  }

  if (gmsh_max_dofs < 0) gmsh_max_dofs = max_dofs;
  const contact::IsotropicMaterial steel{210e9, 0.3, 7850};
  std::printf(
      "# Hex8 unit-cube meshes, n^3 elements, 3 (n+1)^3 dofs; times in seconds\n");
  std::printf("%5s %9s %9s %10s %10s %9s %9s %9s %11s %12s\n", "n", "dofs", "elements",
              "mesh", "mesh_gmsh", "setup", "K", "M", "nnz", "K_us/elem");
  std::vector<double> elements, k_times, m_times, setup_times;
  for (const int n : {6, 9, 14, 21, 31, 46, 69}) {
    const long long dofs = 3LL * (n + 1) * (n + 1) * (n + 1);
    if (dofs > max_dofs) break;
    contact::BoxMeshOptions options;
    options.cells = {n, n, n};
    options.side_roles = {{contact::Side::kZMin, contact::BoundaryRole::kContact},
                          {contact::Side::kXMin, contact::BoundaryRole::kFixed}};

    auto start = Clock::now();
    contact::Mesh mesh = contact::MakeStructuredBoxMesh(options);
    const double mesh_time = SecondsSince(start);

    double gmsh_time = std::nan("");
    if (dofs <= gmsh_max_dofs) {
      start = Clock::now();
      const contact::Mesh from_gmsh = contact::MakeBoxMesh(options);
      gmsh_time = SecondsSince(start);
      if (from_gmsh.NumElements() != mesh.NumElements()) {
        std::fprintf(stderr, "gmsh and direct meshes differ: %d vs %d elements\n",
                     from_gmsh.NumElements(), mesh.NumElements());
        return 1;
      }
    }

    start = Clock::now();
    const contact::ElasticBody body(std::move(mesh), steel);
    const double setup_time = SecondsSince(start);

    long long nnz = 0;
    double k_time = 0, m_time = 0;
    {
      start = Clock::now();
      const contact::SparseMatrix K = body.StiffnessMatrix();
      k_time = SecondsSince(start);
      nnz = K.nonZeros();
    }
    {
      start = Clock::now();
      const contact::SparseMatrix M = body.ConsistentMassMatrix();
      m_time = SecondsSince(start);
    }
    const int num_elements = body.mesh().NumElements();
    std::printf("%5d %9d %9d %10.4f %10.4f %9.4f %9.4f %9.4f %11lld %12.3f\n", n,
                body.NumDofs(), num_elements, mesh_time, gmsh_time, setup_time, k_time,
                m_time, nnz, 1e6 * k_time / num_elements);
    std::fflush(stdout);
    elements.push_back(num_elements);
    k_times.push_back(k_time);
    m_times.push_back(m_time);
    setup_times.push_back(setup_time);
  }
  // The smallest meshes are dominated by fixed costs; fit from ~10^4 dofs on.
  if (elements.size() >= 4) {
    const std::vector<double> e(elements.begin() + 2, elements.end());
    auto tail = [](const std::vector<double>& v) {
      return std::vector<double>(v.begin() + 2, v.end());
    };
    std::printf(
        "# log-log slope of time vs elements (n >= 14): setup %.3f, K %.3f, M %.3f "
        "(1 = linear)\n",
        LogLogSlope(e, tail(setup_times)), LogLogSlope(e, tail(k_times)),
        LogLogSlope(e, tail(m_times)));
  }
  return 0;
}
