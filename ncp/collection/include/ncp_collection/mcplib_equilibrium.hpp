/// \file mcplib_equilibrium.hpp
/// Equilibrium problems of MCPLIB (Dirkse and Ferris 1995) and of the GAMS model library,
/// transcribed from their published formulas and data. Each function names its source;
/// the formulas are written out in the .cpp.
#pragma once

#include <vector>

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// MCPLIB `nash`: Harker's 10-firm Nash-Cournot oligopoly (Murphy, Sherali and Soyster
/// 1982; Harker 1988), n = 10, standard NCP. Data of the GAMS model library model NASH
/// (SEQ=269); the AMPL form of MCPLIB nash (netlib ampl/models/compl/nash.mod) gives the
/// same F. Interior solution (all q_i > 0).
TestProblem Nash10();

/// All problems of this file.
std::vector<TestProblem> McplibEquilibriumProblems();

}  // namespace ncp::collection
