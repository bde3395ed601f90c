// Readers of frictional contact problems: Siconos .dat (dense and sparse-block), FCLIB
// HDF5 (local, and global reduced to local), and malformed input.
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
  const std::string storage = WriteTemp("storage.dat", "3 1 2 3 3\n");
  CHECK_THROWS_WITH(ReadSiconosDat(storage), Catch::Contains("storage type 2"));
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
