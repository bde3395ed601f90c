/// \file mcplib_nlp.hpp
/// Published complementarity problems of MCPLIB (Dirkse and Ferris 1995) and of the GAMS
/// model library, transcribed from their published formulas and data (the .cpp gives,
/// for each, the equations and the file that was read). Names are those of the source.
#pragma once

#include <vector>

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// Colville's second test problem in its dual form, Hock and Schittkowski (1981) problem
/// 117, written as its KKT system: n = 15 + 5 = 20, standard NCP (MCPLIB `colvdual`).
TestProblem ColvilleDual();

/// Colville's second test problem in its primal form (the NLP whose Wolfe dual is HS117),
/// written as its KKT system: n = 5 + 10 = 15, standard NCP (MCPLIB `colvnlp`).
TestProblem ColvilleNlp();

/// GAMS model library `transmcp` (SEQ=126): Dantzig's transportation model as an LCP
/// (model `fixedqty`), n = 11.
TestProblem TransMcp();

/// GAMS model library `harkmcp` (SEQ=128): Harker's spatial price equilibrium (model
/// `harker`, competitive case with average-cost pricing of transport), n = 32.
TestProblem HarkMcp();

/// GAMS model library `scarfmcp` (SEQ=132): Scarf's activity analysis economy (Scarf and
/// Hansen 1973), income of agent 1 fixed as numeraire, n = 18, box MCP.
TestProblem ScarfMcp();

/// GAMS model library `hansmcp` (SEQ=135): Hansen's activity analysis economy (Scarf and
/// Hansen 1973), price of agric fixed as numeraire, n = 43, box MCP.
TestProblem HansMcp();

/// GAMS model library `two3mcp` (SEQ=131, model `jel`): Shoven and Whalley's 2 x 2 x 2
/// general equilibrium model, wage of labor fixed as numeraire, n = 7, box MCP.
TestProblem Two3Mcp();

/// GAMS model library `wallmcp` (SEQ=127): Wall, Greening and Woolsey's chemical
/// equilibrium, a square nonlinear system in 6 free variables.
TestProblem WallMcp();

/// All of the above.
std::vector<TestProblem> McplibNlpProblems();

}  // namespace ncp::collection
