// contact-static-hertz-bench: the static solve of the 2D Hertz problem
// (examples/hertz/hertz_problem.hpp) on the meshes a/h = 5, 10, 20, in four settings:
//   default     the defaults (StaticContactOptions: closed start, min function)
//   zero-fb     u = 0 start, Fischer-Burmeister (the defaults before the closed start)
//   zero-min    u = 0 start, min function
//   closed-fb   closed start, Fischer-Burmeister
//
//   contact-static-hertz-bench OUTPUT_DIR [REPEATS [BLAS_THREADS]]
//
// Times SolveStaticContact alone (the best of REPEATS runs, default 3; wall and CPU
// seconds of the process), with ncp::Options::blas_threads = BLAS_THREADS (default 1, the
// library default; 0 leaves OpenBLAS at its own count, as before that option), and writes
// into OUTPUT_DIR
//   static_hertz_ours.csv           one row per (mesh, setting)
//   hertz_mesh_a_over_h_N.txt       the mesh: nodes, triangles, contact nodes
//   hertz_forces_a_over_h_N.csv     nodal contact forces of the default setting [N/m]
// which benchmarks/contact/static_hertz_getfem.py reads to solve the same meshes with
// GetFEM's nodal contact brick.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "../../examples/hertz/hertz_problem.hpp"

namespace {

struct Setting {
  const char* name;
  contact::StaticStart start;
  ncp::NcpFunction function;
  bool is_default;
};

struct Timing {
  double wall_s = 1e300, cpu_s = 1e300;
};

// The mesh in a plain text form: "nodes N" and N lines x y [m]; "triangles M" and M lines
// of node indices; "contact_nodes C" and C node indices (the candidate contact nodes).
void WriteMesh(const hertz::HertzProblem& problem, const std::filesystem::path& path) {
  const contact::Mesh& mesh = problem.mesh();
  std::ofstream out(path);
  out.precision(17);
  out << "nodes " << mesh.nodes.cols() << "\n";
  for (Eigen::Index i = 0; i < mesh.nodes.cols(); ++i)
    out << mesh.nodes(0, i) << " " << mesh.nodes(1, i) << "\n";
  out << "triangles " << mesh.elements.cols() << "\n";
  for (Eigen::Index e = 0; e < mesh.elements.cols(); ++e)
    out << mesh.elements(0, e) << " " << mesh.elements(1, e) << " " << mesh.elements(2, e)
        << "\n";
  out << "contact_nodes " << problem.frames().nodes.size() << "\n";
  for (const contact::ContactNode& node : problem.frames().nodes)
    out << node.node << "\n";
}

void WriteForces(const hertz::HertzProblem& problem,
                 const contact::StaticContactResult& result,
                 const std::filesystem::path& path) {
  std::ofstream out(path);
  out.precision(17);
  out << "node,x_m,y_m,normal_force_N_per_m\n";
  const auto& nodes = problem.frames().nodes;
  for (size_t c = 0; c < nodes.size(); ++c)
    out << nodes[c].node << "," << problem.mesh().nodes(0, nodes[c].node) << ","
        << problem.mesh().nodes(1, nodes[c].node) << ","
        << result.normal_force(static_cast<Eigen::Index>(c)) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR [REPEATS [BLAS_THREADS]]\n";
    return 2;
  }
  const std::filesystem::path output_dir = argv[1];
  const int repeats = argc >= 3 ? std::atoi(argv[2]) : 3;
  const int blas_threads = argc == 4 ? std::atoi(argv[3]) : 1;
  if (blas_threads < 0) {
    std::cerr << "BLAS_THREADS must be an integer >= 0, got '" << argv[3] << "'\n";
    return 2;
  }
  if (repeats < 1) {
    std::cerr << "REPEATS must be an integer >= 1, got '" << argv[2] << "'\n";
    return 2;
  }
  std::filesystem::create_directories(output_dir);
  const Setting settings[] = {
      {"default", contact::StaticStart::kClosed, ncp::NcpFunction::kMin, true},
      {"zero-fb", contact::StaticStart::kZero, ncp::NcpFunction::kFischerBurmeister,
       false},
      {"zero-min", contact::StaticStart::kZero, ncp::NcpFunction::kMin, false},
      {"closed-fb", contact::StaticStart::kClosed, ncp::NcpFunction::kFischerBurmeister,
       false},
  };
  std::ofstream csv(output_dir / "static_hertz_ours.csv");
  csv << "a_over_h,dofs,contact_nodes,setting,newton_iterations,closed_start,converged,"
         "wall_s,cpu_s,a_error,p0_error\n";
  std::printf(
      "| a/h | dofs | setting | Newton its | wall [s] | CPU [s] | a error | p0 error "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  const hertz::HertzData data;
  bool all_converged = true;
  for (const int n : {5, 10, 20}) {
    hertz::HertzProblem problem(data, n);
    problem.make_mesh();
    problem.assemble();
    WriteMesh(problem,
              output_dir / ("hertz_mesh_a_over_h_" + std::to_string(n) + ".txt"));
    for (const Setting& setting : settings) {
      contact::StaticContactOptions options;  // the library defaults
      options.start = setting.start;
      options.ncp.ncp_function = setting.function;
      options.ncp.blas_threads = blas_threads;
      Timing best;
      for (int r = 0; r < repeats; ++r) {
        const std::clock_t cpu0 = std::clock();
        const auto wall0 = std::chrono::steady_clock::now();
        problem.solve(options);
        const std::chrono::duration<double> wall =
            std::chrono::steady_clock::now() - wall0;
        best.wall_s = std::min(best.wall_s, wall.count());
        best.cpu_s = std::min(best.cpu_s, double(std::clock() - cpu0) / CLOCKS_PER_SEC);
      }
      const contact::StaticContactResult& result = problem.solve(options);
      all_converged = all_converged && result.converged;
      const hertz::Row row = problem.write_output(output_dir);
      if (setting.is_default)
        WriteForces(problem, result,
                    output_dir / ("hertz_forces_a_over_h_" + std::to_string(n) + ".csv"));
      std::printf("| %d | %d | %s | %d | %.3f | %.3f | %+.2e | %+.2e |\n", n, row.dofs,
                  setting.name, result.newton_iterations, best.wall_s, best.cpu_s,
                  row.a / data.a - 1, row.p0 / data.p0 - 1);
      csv << n << "," << row.dofs << "," << problem.frames().nodes.size() << ","
          << setting.name << "," << result.newton_iterations << ","
          << (result.closed_start ? 1 : 0) << "," << (result.converged ? 1 : 0) << ","
          << best.wall_s << "," << best.cpu_s << "," << row.a / data.a - 1 << ","
          << row.p0 / data.p0 - 1 << "\n";
    }
  }
  return all_converged ? 0 : 1;
}
