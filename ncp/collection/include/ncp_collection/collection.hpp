/// \file collection.hpp
/// The standard collection: every problem of the library at a fixed small size, in a
/// fixed order. Tests, examples and benchmarks iterate over it.
#pragma once

#include <vector>

#include "ncp_collection/affine_function.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/cops_bound_constrained.hpp"
#include "ncp_collection/gams_equilibrium.hpp"
#include "ncp_collection/mcplib_equilibrium.hpp"
#include "ncp_collection/mcplib_nlp.hpp"
#include "ncp_collection/mixed_examples.hpp"
#include "ncp_collection/obstacle.hpp"
#include "ncp_collection/random_lcp.hpp"
#include "ncp_collection/small_problems.hpp"
#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// kojshin, josephy, mathiesen-mod, nash5, billups, hs35-lcp, path-lcp, explcp-16,
/// colvdual, colvnlp, transmcp, harkmcp, scarfmcp, hansmcp, two3mcp, wallmcp, nash,
/// vonthmcp, mr5mcp, oligomcp, jbearing-25x25, torsion-25x25, minsurf-25x25,
/// obstacle1d-bump-100, obstacle1d-band-100, obstacle2d-bump-20x20,
/// obstacle2d-band-20x20, random-plcp-200, random-plcp-degenerate-200.
std::vector<TestProblem> StandardCollection();

}  // namespace ncp::collection
