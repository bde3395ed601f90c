// Reads a problem with the installed ncp::fc, solves it, prints the error; exit 0 if
// solved.
#include <cstdio>

#include "ncp/fc/error.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/solver.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const ncp::fc::FrictionProblem problem = ncp::fc::ReadProblem(argv[1]);
  ncp::Vector r;
  ncp::fc::Summary summary;
  ncp::fc::Solve(ncp::fc::Options(), problem, &r, &summary);
  std::printf("%s: error %.3e\n", problem.name.c_str(),
              ncp::fc::NaturalMapError(problem, r));
  return summary.IsSolutionUsable() ? 0 : 1;
}
