/// \file gams_equilibrium.hpp
/// Economic equilibrium models of the GAMS model library in MCP form, transcribed from
/// their published formulas and data (the .cpp writes out, for each, the equations, the
/// data and the variables that GAMS fixes). Names are those of the model library.
#pragma once

#include <vector>

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// GAMS model library `vonthmcp` (SEQ=136): general-equilibrium variant of the von Thunen
/// model (Rowse et al.), 12 regions x 4 crops; the worker wage wl = 1 (numeraire) is
/// eliminated with its labor-market equation, n = 125, box MCP (lower bounds only).
TestProblem VonThunenMcp();

/// GAMS model library `mr5mcp` (SEQ=134): five-region growth model on the data of
/// Global 2100 (Manne and Richels 1992), 11 projection periods; the base-year
/// investment and capital and the income of the first region (numeraire) are
/// eliminated, n = 350, box MCP (lower bounds only). Unscaled (GAMS solves it with
/// variable scale factors).
TestProblem Mr5Mcp();

/// GAMS model library `oligomcp` (SEQ=133): a 5-firm Nash-Cournot oligopoly (Murphy,
/// Sherali and Soyster 1982) with the price kept as a variable and its demand equation:
/// x = (p, q_1..q_5), standard NCP, n = 6. Firm f's marginal cost is
/// c_f + (q_f/l)^(1/beta_f); l = 5 is the .gms data. l = 1/5 gives the marginal cost
/// c_f + (5 q_f)^(1/beta_f) of `nash5` (Harker 1988), i.e. nash5 with the price as a
/// variable (nash5 eliminates it).
TestProblem OligoMcp(double l = 5.0);

/// All problems of this file.
std::vector<TestProblem> GamsEquilibriumProblems();

}  // namespace ncp::collection
