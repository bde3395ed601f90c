// Readers of frictional contact problems: Siconos .dat (dense, sparse-block, sparse),
// FCLIB HDF5 (local, and global reduced to local), and malformed input.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>

#include "fc_support.hpp"
#include "ncp/fc/io.hpp"

using namespace ncp::fc;

namespace {
const std::string kData = NCP_FC_DATA_DIR;

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path =
      std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
      "/ncp_fc_test_" + name;
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST_CASE("dense .dat: FrictionContact3D_1c as published", "[fc][io]") {
  const FrictionProblem p = ReadSiconosDat(kData + "/FrictionContact3D_1c.dat");
  const FrictionProblem expected = test::OneContactProblem();
  CHECK(p.dimension == 3);
  CHECK(p.num_contacts == 1);
  CHECK(Eigen::MatrixXd(p.W) == Eigen::MatrixXd(expected.W));
  CHECK(p.q == expected.q);
  CHECK(p.mu == expected.mu);
}

TEST_CASE("sparse-block .dat: Capsules, 1011 blocks of 3x3", "[fc][io]") {
  const FrictionProblem p = ReadProblem(kData + "/Capsules-i101-404.dat");
  CHECK(p.dimension == 3);
  CHECK(p.num_contacts == 225);
  CHECK(p.W.rows() == 675);
  const Eigen::MatrixXd W(p.W);
  CHECK(p.W.nonZeros() == 1011 * 9);
  // The file's W is not exactly symmetric (Siconos' own reader gives the same matrix,
  // entry for entry: max |W - W'| = 4.3e-3 for max |W| = 7.28).
  CHECK_THAT((W - W.transpose()).cwiseAbs().maxCoeff(),
             Catch::Matchers::WithinAbs(4.35e-3, 1e-4));
  CHECK_THAT(W.cwiseAbs().maxCoeff(), Catch::Matchers::WithinAbs(7.27879, 1e-5));
  CHECK(W.diagonal().minCoeff() > 0.0);
  CHECK((p.mu.array() == 0.7).all());
}

TEST_CASE("2D .dat problems read with dimension 2", "[fc][io]") {
  const FrictionProblem p = ReadProblem(kData + "/FrictionContactProblem00071.dat");
  CHECK(p.dimension == 2);
  CHECK(p.num_contacts == 89);
  CHECK(p.q.size() == 178);
}

TEST_CASE("malformed .dat files are rejected with the reason", "[fc][io]") {
  // truncated: W announced 3 x 3, q missing
  const std::string truncated =
      WriteTemp("truncated.dat", "3 1 0 3 3 3 3 15 -1 -2 -1 14 1 -2 1 16\n");
  CHECK_THROWS_WITH(ReadSiconosDat(truncated),
                    Catch::Contains("expected a number for q"));
  const std::string wrong_size =
      WriteTemp("wrong_size.dat", "3 2 0 3 3 3 3 1 0 0 0 1 0 0 0 1 1 1 1 0.1\n");
  CHECK_THROWS_WITH(ReadSiconosDat(wrong_size), Catch::Contains("W must be 6 x 6"));
  const std::string negative_mu =
      WriteTemp("negative_mu.dat", "3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 1 1 1 -0.1\n");
  CHECK_THROWS_WITH(ReadSiconosDat(negative_mu), Catch::Contains("mu[0]"));
  const std::string storage = WriteTemp("storage.dat", "3 1 5 3 3\n");
  CHECK_THROWS_WITH(ReadSiconosDat(storage), Catch::Contains("storage type 5"));
  // a global problem (GFC3D_Example1: M, H, q, b, mu) is not taken for a local one
  CHECK_THROWS_WITH(
      ReadSiconosDat(std::string(NCP_FC_DATA_DIR) + "/../gfc3d/GFC3D_Example1.dat"),
      Catch::Contains("--global"));
  CHECK_THROWS_AS(ReadProblem(kData + "/no_such_file.dat"), std::runtime_error);
}

TEST_CASE("FCLIB local problem with its reference solution", "[fc][io][fclib]") {
  if (!HaveFclib())
    FAIL("built without FCLIB although scripts/setup.sh installs libfclib-dev");
  const std::string path = kData + "/BoxesStack-local_problem_test.hdf5";
  const FrictionProblem p = ReadProblem(path);
  CHECK(p.dimension == 3);
  CHECK(p.num_contacts == 48);
  CHECK((p.mu.array() == 0.7).all());
  const auto solution = ReadFclibSolution(path);
  REQUIRE(solution.has_value());
  CHECK(solution->size() == 144);
}

TEST_CASE("FCLIB global problem reduced to W = H' M^-1 H", "[fc][io][fclib]") {
  if (!HaveFclib())
    FAIL("built without FCLIB although scripts/setup.sh installs libfclib-dev");
  const FrictionProblem p = ReadFclib(kData + "/Box_Stacks-i0122-82-5.hdf5");
  CHECK(p.dimension == 3);
  CHECK(p.num_contacts == 82);
  const Eigen::MatrixXd W(p.W);
  CHECK((W - W.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * W.cwiseAbs().maxCoeff());
  // positive semidefinite: no eigenvalue below round-off
  const Eigen::VectorXd eig =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(W).eigenvalues();
  CHECK(eig.minCoeff() >= -1e-10 * eig.maxCoeff());
}

TEST_CASE("WriteSiconosDat round trip (sparse-block storage)", "[fc][io]") {
  const std::string name = GENERATE(std::string("Capsules-i101-404.dat"),
                                    std::string("FrictionContactProblem00071.dat"),
                                    std::string("BoxesStack-local_problem_test.hdf5"));
  const FrictionProblem p = ReadProblem(kData + "/" + name);
  const std::string path = WriteTemp("roundtrip.dat", "");
  WriteSiconosDat(p, path);
  const FrictionProblem back = ReadSiconosDat(path);
  CHECK(back.dimension == p.dimension);
  CHECK(back.num_contacts == p.num_contacts);
  CHECK((Eigen::MatrixXd(back.W) - Eigen::MatrixXd(p.W)).cwiseAbs().maxCoeff() == 0.0);
  CHECK(back.q == p.q);
  CHECK(back.mu == p.mu);
}

TEST_CASE("sparse (storage 2, CSC) .dat: a 2D granular flow of 667 contacts",
          "[fc][io]") {
  // Siconos' test data; the numbers checked are those printed in the file's own CSparse
  // header and first column ("1334-by-1334, nzmax: 3822 nnz: 3822", col 0: 856.713 at row
  // 0, -454.43 at row 649).
  const FrictionProblem p = ReadProblem(
      std::string(NCP_FC_DATA_DIR) + "/../fc2d/fc2d_granularflowonwall_00667_00000.dat");
  CHECK(p.dimension == 2);
  CHECK(p.num_contacts == 667);
  REQUIRE(p.W.rows() == 1334);
  CHECK(p.W.nonZeros() <= 3822);
  CHECK(p.W.coeff(0, 0) == 856.713);
  CHECK(p.W.coeff(649, 0) == -454.43);
  CHECK(p.W.coeff(1, 1) == 2559.98);
  CHECK(p.W.coeff(648, 1) == 454.43);
  CHECK(p.q.size() == 1334);
  CHECK(p.mu.size() == 667);
}

TEST_CASE("sparse (storage 2) .dat: triplet, CSC and CSR give the same W", "[fc][io]") {
  // W = [[4, 1], [2, 5]] (not symmetric, so a transposed reading shows), q = (-1, 0), mu
  // = 0.3.
  const std::string version =
      "CSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016\n";
  const std::string triplet = "2\n1\n2\n2\n2\n1\n" + version +
                              "triplet: 2-by-2, nzmax: 4 nnz: 4\n    0 0 : 4\n    1 0 : "
                              "2\n    0 1 : 1\n    1 1 : 5\n";
  const std::string csc =
      "2\n1\n2\n2\n2\n2\n" + version +
      "2-by-2, nzmax: 4 nnz: 4, 1-norm: 6\n    col 0 : locations 0 to 1\n      0 : 4\n"
      "      1 : 2\n    col 1 : locations 2 to 3\n      0 : 1\n      1 : 5\n";
  const std::string csr =
      "2\n1\n2\n2\n2\n3\n" + version +
      "csr: 2-by-2, nzmax: 4 nnz: 4, 1-norm: 6\n    row 0 : locations 0 to 1\n      0 : "
      "4\n"
      "      1 : 1\n    row 1 : locations 2 to 3\n      0 : 2\n      1 : 5\n";
  Eigen::MatrixXd expected(2, 2);
  expected << 4, 1, 2, 5;
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"triplet", triplet},
        {"csc", csc},
        {"csr", csr}}) {
    INFO(name);
    const FrictionProblem p =
        ReadSiconosDat(WriteTemp("storage2_" + name + ".dat", text + "-1 0\n0.3\n"));
    CHECK(Eigen::MatrixXd(p.W) == expected);
    CHECK(p.q == Eigen::Vector2d(-1.0, 0.0));
    CHECK(p.mu[0] == 0.3);
  }
  // A header that is not CSparse's, and a size that disagrees, are rejected with the
  // reason.
  CHECK_THROWS_WITH(ReadSiconosDat(WriteTemp("storage2_bad.dat",
                                             "2\n1\n2\n2\n2\n2\nnot csparse\n2-by-2\n")),
                    Catch::Contains("CSparse"));
  CHECK_THROWS_WITH(
      ReadSiconosDat(WriteTemp("storage2_size.dat", "2\n1\n2\n2\n2\n2\n" + version +
                                                        "3-by-3, nzmax: 0 nnz: 0\n")),
      Catch::Contains("3 x 3"));
}
