/// \file small_problems.hpp
/// The classical small complementarity problems of the literature, each with the
/// starting points used there. Formulas are written out in the .cpp with their sources.
#pragma once

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// Kojima and Shindo (1986), MCPLIB `kojshin`, n = 4, standard NCP, the 8 MCPLIB starts.
/// Two solutions: (sqrt(6)/2, 0, 0, 1/2), degenerate in component 3 (x3 = F3 = 0), and
/// (1, 0, 3, 0), nondegenerate.
TestProblem KojimaShindo();

/// Josephy (1979) via Kojima, MCPLIB `josephy`, n = 4, standard NCP, the 8 MCPLIB starts.
/// Unique solution (sqrt(6)/2, 0, 0, 1/2), nondegenerate.
TestProblem Josephy();

/// Kanzow's modification of the Mathiesen equilibrium problem (Kanzow 1994; De Luca,
/// Facchinei and Kanzow 1996, sec. 6), n = 4, standard NCP. Non-isolated solutions
/// (lambda, 0, 0, 0) for lambda in [0, 3].
TestProblem ModifiedMathiesen();

/// Nash-Cournot oligopoly with 5 firms (Murphy, Sherali and Soyster 1982; Harker 1988),
/// n = 5, standard NCP. Solution approx. (15.4293, 12.4986, 9.6635, 7.1651, 5.1326).
TestProblem NashCournot5();

/// Billups' one-dimensional NCP, F(x) = (x - 1)^2 - 1.01, x >= 0 (Billups 1995).
/// From x0 = 0 a merit-function method stalls at a local minimizer of psi that is not a
/// solution (documented failure); from x0 = 3 it converges to 1 + sqrt(1.01).
TestProblem Billups();

/// LCP of the KKT conditions of Hock-Schittkowski problem 35 (Hock and Schittkowski
/// 1981), n = 4 (3 primal variables + 1 multiplier). Solution (4/3, 7/9, 4/9, 2/9).
TestProblem Hs35Lcp();

/// The 4x4 LCP of the PATH library examples (Ferris and Munson 1999), solution
/// (2.8, 0, 0.8, 1.2).
TestProblem PathManualLcp();

/// Murty's exponential LCP (Murty 1978; the family of MCPLIB `explcp`): M lower
/// triangular, M_ii = 1, M_ij = 2 below the diagonal, q = -1. Unique solution e_1.
TestProblem MurtyExponentialLcp(int n);

/// A box MCP with every kind of bound, n = 10 (not in StandardCollection; tests of the
/// box MCP's mixed form): F(x) = M x + q + x.^3 / 10 with M = 2 I + (K - K') + B B' / n,
/// K_ij = sin(1 + i + 2 j), B_ij = cos(3 i - j) (i, j from 0), so x'Mx >= 2 |x|^2 and
/// F' = M + diag(0.3 x.^2) is positive definite: one solution. Bounds: x0..x3 free, x4,
/// x5 >= 0, x6 >= -0.5, x7 <= 1, -1 <= x8 <= 1, x9 = 0.3 (fixed). q_i = sin(7 i), except
/// q4, chosen so that F4 = 0 exactly at the start "degenerate" (0.5 everywhere, x4 = 0,
/// x9 = 0.3), where pair 4 has x4 - l4 = F4 = 0 (the degenerate set of the FB family).
/// Starts: "zero", "half" (0.5 everywhere, x9 = 0.3), "degenerate".
TestProblem EveryBoundCubic();

}  // namespace ncp::collection
