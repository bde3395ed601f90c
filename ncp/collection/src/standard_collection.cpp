#include "ncp_collection/collection.hpp"

namespace ncp::collection {

std::vector<TestProblem> StandardCollection() {
  std::vector<TestProblem> problems;
  problems.push_back(KojimaShindo());
  problems.push_back(Josephy());
  problems.push_back(ModifiedMathiesen());
  problems.push_back(NashCournot5());
  problems.push_back(Billups());
  problems.push_back(Hs35Lcp());
  problems.push_back(PathManualLcp());
  problems.push_back(MurtyExponentialLcp(16));
  // MCPLIB / GAMS model library problems (mcplib_nlp.hpp, mcplib_equilibrium.hpp,
  // gams_equilibrium.hpp) and the COPS grid problems of the GAMS model library
  // (cops_bound_constrained.hpp, 25 x 25 interior nodes).
  for (auto* family : {&McplibNlpProblems, &McplibEquilibriumProblems,
                       &GamsEquilibriumProblems, &CopsBoundConstrainedProblems})
    for (TestProblem& p : family()) problems.push_back(std::move(p));
  problems.push_back(Obstacle1D(100, ObstacleKind::kLowerBump));
  problems.push_back(Obstacle1D(100, ObstacleKind::kTwoSidedBand));
  problems.push_back(Obstacle2D(20, ObstacleKind::kLowerBump));
  problems.push_back(Obstacle2D(20, ObstacleKind::kTwoSidedBand));
  problems.push_back(RandomPLcp(200));
  RandomLcpOptions degenerate;
  degenerate.degenerate_fraction = 0.1;
  degenerate.seed = 7;
  problems.push_back(RandomPLcp(200, degenerate));
  return problems;
}

}  // namespace ncp::collection
