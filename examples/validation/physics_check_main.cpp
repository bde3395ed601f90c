// contact-physics-check: the closed-form checks of physics_checks.hpp over a sweep of
// materials, time steps, mass kinds and dimensions, with default solver settings.
//   contact-physics-check [--quick] [--csv FILE] [--step S] [--solver M] [--friction
//   lagged-bound|coulomb-fc] [--tolerance T]
//                         [--dim 2|3] [--mass lumped|consistent]
// Prints one line per run and a count; exit code 1 if any check failed.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "physics_checks.hpp"

using namespace contact::validation;

int main(int argc, char** argv) {
  bool quick = false;
  int only_dim = 0;
  std::string only_mass;
  std::string csv, step, solver, friction;
  double tolerance = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      quick = true;
    else if (a == "--csv" && i + 1 < argc)
      csv = argv[++i];
    else if (a == "--step" && i + 1 < argc)
      step = argv[++i];
    else if (a == "--solver" && i + 1 < argc)
      solver = argv[++i];
    else if (a == "--friction" && i + 1 < argc)
      friction = argv[++i];
    else if (a == "--tolerance" && i + 1 < argc)
      tolerance = std::stod(argv[++i]);
    else if (a == "--dim" && i + 1 < argc)
      only_dim = std::stoi(argv[++i]);
    else if (a == "--mass" && i + 1 < argc)
      only_mass = argv[++i];
    else {
      std::fprintf(stderr,
                   "usage: contact-physics-check [--quick] [--csv FILE] [--step S] "
                   "[--solver M] [--friction lagged-bound|coulomb-fc] [--tolerance T] "
                   "[--dim 2|3] [--mass lumped|consistent]\n");
      return 2;
    }
  }
  const std::vector<double> moduli =
      quick ? std::vector<double>{1e6, 2e11} : std::vector<double>{1e6, 1e8, 7e10, 2e11};
  const std::vector<double> fractions =
      quick ? std::vector<double>{0.1, 0.95} : std::vector<double>{0.01, 0.1, 0.5, 0.95};
  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    out << "check,dim,young_modulus,dt_fraction,mass,step,solver,passed,status,steps,"
           "newton_per_step,seconds,measured,expected,detail\n";
  }
  int passed = 0, total = 0;
  for (int dim : {2, 3})
    for (bool lumped : {true, false})
      for (double E : moduli)
        for (double fraction : fractions) {
          Case c;
          c.dim = dim;
          c.lumped = lumped;
          c.young_modulus = E;
          c.dt_fraction = fraction;
          c.step = step;
          c.solver = solver;
          c.friction_formulation = friction;
          c.tolerance = tolerance;
          if ((only_dim && dim != only_dim) ||
              (!only_mass.empty() && only_mass != (lumped ? "lumped" : "consistent")))
            continue;
          std::vector<Outcome> outcomes{FreeFall(c), Incline(c, +1.0), Incline(c, -1.0),
                                        Sliding(c), BarImpact(c)};
          for (const Outcome& o : outcomes) {
            ++total;
            passed += o.passed;
            std::printf(
                "%-4s %-16s %-40s %-22s %6d steps %5.2f Newton/step %8.3f s  %s\n",
                o.passed ? "ok" : "FAIL", o.check.c_str(), c.Label().c_str(),
                contact::ToString(o.status), o.steps, o.newton_per_step, o.seconds,
                o.detail.c_str());
            if (!o.passed && o.status != contact::DynamicStatus::kCompleted)
              std::printf("     %s\n", o.message.c_str());
            std::fflush(stdout);
            if (out.is_open())
              out << o.check << ',' << dim << ',' << E << ',' << fraction << ','
                  << (lumped ? "lumped" : "consistent") << ','
                  << (step.empty() ? "default" : step) << ','
                  << (solver.empty() ? "default" : solver) << ',' << o.passed << ','
                  << contact::ToString(o.status) << ',' << o.steps << ','
                  << o.newton_per_step << ',' << o.seconds << ',' << o.measured << ','
                  << o.expected << ",\"" << o.detail << "\"\n";
          }
        }
  std::printf("%d passed, %d failed\n", passed, total - passed);
  return passed == total ? 0 : 1;
}
