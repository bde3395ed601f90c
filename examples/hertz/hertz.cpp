// hertz-example: a steel cylinder pressed onto a rigid plane (plane strain), compared
// with the Hertz solution on three meshes refined at the contact.
//
//   hertz-example OUTPUT_DIR
//
// prints the comparison table and writes into OUTPUT_DIR
//   hertz_table.csv               one row per mesh: h, a, p0 and their errors
//   hertz_pressure_a_over_h_N.csv contact pressure vs x, computed and exact, per mesh.
//
// Hertz (Johnson, Contact Mechanics, 1985, section 4.3, eq. 4.43-4.45), cylinder of
// radius R on a rigid flat, load P per unit length, E* = E / (1 - nu^2):
//     a = sqrt(4 P R / (pi E*)),   p(x) = p0 sqrt(1 - x^2 / a^2),   p0 = 2 P / (pi a).

#include <iostream>

#include "hertz_problem.hpp"

using hertz::HertzData;
using hertz::HertzProblem;
using hertz::Row;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR\n";
    return 2;
  }
  const std::filesystem::path output_dir = argv[1];
  std::filesystem::create_directories(output_dir);
  const HertzData data;
  std::printf("Hertz, plane strain: R = %g m, E = %g Pa, nu = %g, P = %.6g N/m\n", data.R,
              data.steel.youngs_modulus, data.steel.poisson_ratio, data.P);
  std::printf("exact: a = %.6e m, p0 = %.6e Pa\n\n", data.a, data.p0);
  std::printf(
      "| h [m] | a/h | dofs | loaded nodes | a [m] | a error | p0 [Pa] | p0 error | max "
      "|p - p_exact| / p0 | Newton its |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  std::ofstream table(output_dir / "hertz_table.csv");
  table << "h_m,a_over_h,dofs,loaded_nodes,a_m,a_exact_m,p0_Pa,p0_exact_Pa,max_error_"
           "over_p0\n";
  table.precision(10);
  for (const int n : {10, 20, 40}) {
    HertzProblem problem(data, n);
    const Row r = problem.run(output_dir);
    std::printf("| %.2e | %d | %d | %d | %.5e | %+.2e | %.5e | %+.2e | %.2e | %d |\n",
                r.h, n, r.dofs, r.loaded, r.a, r.a / data.a - 1, r.p0, r.p0 / data.p0 - 1,
                r.max_error, r.newton_iterations);
    table << r.h << "," << n << "," << r.dofs << "," << r.loaded << "," << r.a << ","
          << data.a << "," << r.p0 << "," << data.p0 << "," << r.max_error << "\n";
  }
  std::printf("\nwritten: %s/hertz_table.csv, hertz_pressure_a_over_h_{10,20,40}.csv\n",
              output_dir.string().c_str());
  return 0;
}
