// Colville's problem 2 (mcplib_nlp.hpp) against the optimum Hock and Schittkowski
// published for it (problem 117), and the duality between its two MCPLIB forms. The
// checks every collection problem gets - Jacobians against central differences, the known
// solutions' natural residual, every start with FB and min on every backend - are in
// test_collection.cpp and test_solve_collection.cpp (StandardCollection holds these
// problems).
#include <catch2/catch.hpp>
#include <cmath>

#include "ncp/types.hpp"
#include "ncp_collection/mcplib_nlp.hpp"

using ncp::Vector;
using namespace ncp::collection;

TEST_CASE(
    "mcplib_nlp: Colville's problem reproduces Hock and Schittkowski's published "
    "optimum",
    "[collection][mcplib]") {
  // HS117 (1981): f* = 32.34867897, x* to 7 digits.
  const double x_hs[15] = {0,         0,         5.174136,  0,         3.061093,
                           11.83968,  0,         0,         0.1039071, 0,
                           0.2999929, 0.3334709, 0.3999910, 0.4283145, 0.2239607};
  TestProblem dual = ColvilleDual();
  const Vector z = dual.solutions.at(0);
  for (int i = 0; i < 15; ++i) CHECK(z(i) == Approx(x_hs[i]).margin(2e-4));
  // HS117's objective -b'v + w'Cw + 2 d'w^3 at the stored point, from the published data.
  const double b[10] = {-40, -2, -0.25, -4, -4, -1, -40, -60, 5, 1};
  const double C[5][5] = {{30, -20, -10, 32, -10},
                          {-20, 39, -6, -31, 32},
                          {-10, -6, 10, -6, -10},
                          {32, -31, -6, 39, -20},
                          {-10, 32, -10, -20, 30}};
  const double d[5] = {4, 8, 10, 6, 2};
  double f = 0;
  for (int k = 0; k < 10; ++k) f -= b[k] * z(k);
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) f += C[i][j] * z(10 + i) * z(10 + j);
    f += 2 * d[i] * std::pow(z(10 + i), 3);
  }
  CHECK(f == Approx(32.34867897).epsilon(1e-8));
  // Duality: the multipliers of HS117 are the primal variables w, and colvnlp's solution
  // is (w, v).
  for (int i = 0; i < 5; ++i) CHECK(z(15 + i) == Approx(z(10 + i)).margin(1e-9));
  TestProblem primal = ColvilleNlp();
  const Vector y = primal.solutions.at(0);
  for (int i = 0; i < 5; ++i) CHECK(y(i) == Approx(z(10 + i)).margin(1e-9));
  for (int k = 0; k < 10; ++k) CHECK(y(5 + k) == Approx(z(k)).margin(1e-9));
}
