// contact-finite-strain-bench: cost of the finite-strain internal force f_int(u) (total
// Lagrangian, ElasticBody::InternalForce) against one sparse product K x with the
// small-strain stiffness, on unit cubes of Hex8 elements and of Tet4 elements (each cube
// cell split into 6 tetrahedra along its main diagonal), from ~10^3 to --max-dofs dofs.
//
// Each (element, size, quantity) runs in its own child process (fork), so the reported
// peak resident memory (ru_maxrss) is that of one quantity alone: "fint" holds the mesh,
// u and f (what a finite-strain step needs); "Kx" holds the mesh, K, x and y (what a
// small-strain step needs). Times are the fastest of repeated evaluations (at least 3,
// at least 0.2 s in all), serial: run with OMP_NUM_THREADS=1 on a shared machine.
// The displacement is a smooth field with a rotation of 0.5 rad and strains of ~1e-2.
//
// Usage: contact-finite-strain-bench [--max-dofs N] [--model svk|neo-hookean]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The fastest of at least 3 calls of f, repeated for at least 0.2 s [s].
template <class F>
double FastestOf(const F& f) {
  double fastest = std::numeric_limits<double>::infinity(), total = 0.0;
  for (int i = 0; i < 3 || total < 0.2; ++i) {
    const auto start = Clock::now();
    f();
    const double t = SecondsSince(start);
    fastest = std::min(fastest, t);
    total += t;
  }
  return fastest;
}

// The Hex8 cube n^3 (direct generator), or its Tet4 split: the 6 tetrahedra of the Kuhn
// subdivision of every cell (conforming across cells), oriented to positive volume.
contact::Mesh CubeMesh(int n, contact::ElementType type) {
  contact::BoxMeshOptions options;
  options.cells = {n, n, n};
  contact::Mesh hex = contact::MakeStructuredBoxMesh(options);
  hex.boundary_groups.clear();
  if (type == contact::ElementType::kHexahedron8) return hex;
  // Hex8 corners (gmsh order): 0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101),
  // 6 (111), 7 (011). Kuhn paths from 000 to 111 through one axis after another.
  static const int kTets[6][4] = {{0, 1, 2, 6}, {0, 1, 5, 6}, {0, 3, 2, 6},
                                  {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 4, 7, 6}};
  contact::Mesh tet;
  tet.dim = 3;
  tet.nodes = hex.nodes;
  tet.element_type = contact::ElementType::kTetrahedron4;
  tet.elements.resize(4, 6 * hex.NumElements());
  for (int e = 0; e < hex.NumElements(); ++e)
    for (int t = 0; t < 6; ++t) {
      Eigen::Vector4i c;
      for (int a = 0; a < 4; ++a) c(a) = hex.elements(kTets[t][a], e);
      Eigen::Matrix3d edges;
      for (int a = 0; a < 3; ++a)
        edges.col(a) = tet.nodes.col(c(a + 1)) - tet.nodes.col(c(0));
      if (edges.determinant() < 0) std::swap(c(1), c(2));
      tet.elements.col(6 * e + t) = c;
    }
  return tet;
}

// u = (R - I) X + 0.01 (sin(2 pi X), sin(2 pi Y), sin(2 pi Z)), R a rotation by 0.5 rad
// about z [m]: every element is rotated and strained.
contact::Vector TestDisplacement(const contact::Mesh& mesh) {
  const double c = std::cos(0.5) - 1.0, s = std::sin(0.5), two_pi = 2.0 * M_PI;
  contact::Vector u(mesh.NumDofs());
  for (int a = 0; a < mesh.NumNodes(); ++a) {
    const Eigen::Vector3d X = mesh.nodes.col(a);
    u.segment<3>(3 * a) << c * X(0) - s * X(1) + 0.01 * std::sin(two_pi * X(0)),
        s * X(0) + c * X(1) + 0.01 * std::sin(two_pi * X(1)),
        0.01 * std::sin(two_pi * X(2));
  }
  return u;
}

// Runs one quantity in a child and returns {seconds, peak MB}; seconds < 0 on failure.
template <class F>
std::pair<double, double> Isolated(const F& measure) {
  int fds[2];
  if (pipe(fds) != 0) return {-1.0, 0.0};
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    double seconds = -1.0;
    try {
      seconds = measure();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
    }
    if (write(fds[1], &seconds, sizeof seconds) < 0) _exit(3);
    _exit(0);
  }
  close(fds[1]);
  double seconds = -1.0;
  if (read(fds[0], &seconds, sizeof seconds) != sizeof seconds) seconds = -1.0;
  close(fds[0]);
  int wstatus = 0;
  struct rusage usage {};
  wait4(pid, &wstatus, 0, &usage);
  return {seconds, static_cast<double>(usage.ru_maxrss) / 1024.0};  // ru_maxrss in KB
}

}  // namespace

int main(int argc, char** argv) {
  long long max_dofs = 1100000;
  contact::MaterialModel model = contact::MaterialModel::kSaintVenantKirchhoff;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--max-dofs")) {
      max_dofs = std::atoll(argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--model")) {
      model = contact::MaterialModelFromString(argv[i + 1]);
    } else {
      std::fprintf(stderr, "usage: %s [--max-dofs N] [--model NAME]\n", argv[0]);
      return 2;
    }
  }
  const contact::IsotropicMaterial steel{210e9, 0.3, 7850};
  std::printf(
      "# unit cubes, n^3 cells (Tet4: 6 n^3 elements), model %s; serial times [s]\n",
      contact::ToString(model));
  std::printf("%5s %5s %9s %9s %11s %11s %8s %10s %10s\n", "type", "n", "dofs",
              "elements", "fint_s", "Kx_s", "ratio", "fint_MB", "Kx_MB");
  int failures = 0;
  for (const auto type :
       {contact::ElementType::kHexahedron8, contact::ElementType::kTetrahedron4}) {
    for (const int n : {6, 9, 14, 21, 31, 46, 69}) {
      const long long dofs = 3LL * (n + 1) * (n + 1) * (n + 1);
      if (dofs > max_dofs) break;
      const auto fint = Isolated([&] {
        const contact::ElasticBody body(CubeMesh(n, type), steel);
        const contact::Vector u = TestDisplacement(body.mesh());
        contact::Vector f;
        bool ok = true;
        const double t =
            FastestOf([&] { ok = ok && body.InternalForce(u, model, &f).ok; });
        return ok ? t : -1.0;
      });
      const auto kx = Isolated([&] {
        const contact::ElasticBody body(CubeMesh(n, type), steel);
        const contact::SparseMatrix K = body.StiffnessMatrix();
        const contact::Vector x = TestDisplacement(body.mesh());
        contact::Vector y = contact::Vector::Zero(x.size());
        return FastestOf([&] { y.noalias() = K * x; });
      });
      const int elements =
          (type == contact::ElementType::kHexahedron8 ? 1 : 6) * n * n * n;
      if (fint.first < 0 || kx.first < 0) ++failures;
      std::printf("%5s %5d %9lld %9d %11.4e %11.4e %8.2f %10.1f %10.1f\n",
                  type == contact::ElementType::kHexahedron8 ? "Hex8" : "Tet4", n, dofs,
                  elements, fint.first, kx.first, fint.first / kx.first, fint.second,
                  kx.second);
      std::fflush(stdout);
    }
  }
  if (failures) std::fprintf(stderr, "%d case(s) failed\n", failures);
  return failures ? 1 : 0;
}
