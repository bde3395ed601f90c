// hertz-example: a steel cylinder pressed onto a rigid plane (plane strain), compared
// with the Hertz solution on three meshes refined at the contact.
//
//   hertz-example OUTPUT_DIR [ORDER [N ...]]
//
// ORDER 1 (default): 3-node triangles; 2: 6-node triangles with the mid-side nodes of the
// arc on the circle. N: elements per contact half-width a (default 10 20 40). Prints the
// comparison table and writes into OUTPUT_DIR
//   hertz_table.csv               one row per mesh: h, a, p0, their errors, CPU seconds
//                                 (hertz_table_order2.csv for ORDER 2)
//   hertz_pressure_a_over_h_N.csv contact pressure vs x, computed and exact, per mesh.
//
// Hertz (Johnson, Contact Mechanics, 1985, section 4.3, eq. 4.43-4.45), cylinder of
// radius R on a rigid flat, load P per unit length, E* = E / (1 - nu^2):
//     a = sqrt(4 P R / (pi E*)),   p(x) = p0 sqrt(1 - x^2 / a^2),   p0 = 2 P / (pi a).

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <vector>

#include "hertz_problem.hpp"

using hertz::HertzData;
using hertz::HertzProblem;
using hertz::Row;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR [ORDER [N ...]]\n";
    return 2;
  }
  const std::filesystem::path output_dir = argv[1];
  const int order = argc > 2 ? std::atoi(argv[2]) : 1;
  std::vector<int> sizes;
  for (int k = 3; k < argc; ++k) sizes.push_back(std::atoi(argv[k]));
  if (sizes.empty()) sizes = {10, 20, 40};
  if ((order != 1 && order != 2) ||
      std::any_of(sizes.begin(), sizes.end(), [](int n) { return n < 1 || n > 1000; })) {
    std::cerr << "ORDER must be 1 or 2 and N in [1, 1000]\n";
    return 2;
  }
  std::filesystem::create_directories(output_dir);
  const HertzData data;
  std::printf("Hertz, plane strain: R = %g m, E = %g Pa, nu = %g, P = %.6g N/m\n", data.R,
              data.steel.youngs_modulus, data.steel.poisson_ratio, data.P);
  std::printf("exact: a = %.6e m, p0 = %.6e Pa\n\n", data.a, data.p0);
  std::printf(
      "| h [m] | a/h | dofs | loaded nodes | a [m] | a error | p0 [Pa] | p0 error | max "
      "|p - p_exact| / p0 | Newton its | CPU s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::ofstream table(output_dir /
                      (order == 2 ? "hertz_table_order2.csv" : "hertz_table.csv"));
  table << "h_m,a_over_h,dofs,loaded_nodes,a_m,a_exact_m,p0_Pa,p0_exact_Pa,max_error_"
           "over_p0,cpu_seconds\n";
  table.precision(10);
  for (const int n : sizes) {
    HertzProblem problem(data, n, order);
    const Row r = problem.run(output_dir);
    std::printf(
        "| %.2e | %d | %d | %d | %.5e | %+.2e | %.5e | %+.2e | %.2e | %d | %.3f |\n", r.h,
        n, r.dofs, r.loaded, r.a, r.a / data.a - 1, r.p0, r.p0 / data.p0 - 1, r.max_error,
        r.newton_iterations, r.seconds);
    table << r.h << "," << n << "," << r.dofs << "," << r.loaded << "," << r.a << ","
          << data.a << "," << r.p0 << "," << data.p0 << "," << r.max_error << ","
          << r.seconds << "\n";
  }
  std::printf("\nwritten: %s/hertz_table%s.csv and hertz_pressure_a_over_h_N%s.csv\n",
              output_dir.string().c_str(), order == 2 ? "_order2" : "",
              order == 2 ? "_order2" : "");
  return 0;
}
