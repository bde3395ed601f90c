// ncp::ScopedBlasThreads (blas_threads.hpp): the BLAS thread count inside a guard and
// inside ncp::Solver's solves (Options::blas_threads), and the count restored after.
// OpenBLAS's own setter (found here independently with dlsym) sets a known count first,
// so the checks do not depend on the machine's core count.
#include <dlfcn.h>

#include <catch2/catch.hpp>
#include <stdexcept>

#include "ncp/blas_threads.hpp"
#include "ncp/solver.hpp"
#include "ncp_collection/mixed_examples.hpp"

namespace {

// Sets OpenBLAS's thread count directly; false if the process has no OpenBLAS.
bool SetOpenBlasThreads(int threads) {
  const auto set =
      reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return false;
  set(threads);
  return true;
}

}  // namespace

TEST_CASE("ScopedBlasThreads lowers the count while alive and restores it", "[blas]") {
  CHECK_THROWS_AS(ncp::ScopedBlasThreads(-1), std::invalid_argument);
  if (!SetOpenBlasThreads(3)) {
    WARN("no OpenBLAS in this process: the guard does nothing");
    CHECK_FALSE(ncp::BlasThreadsAdjustable());
    CHECK(ncp::BlasThreads() == -1);
    const ncp::ScopedBlasThreads guard(1);
    CHECK(ncp::BlasThreads() == -1);
    return;
  }
  REQUIRE(ncp::BlasThreadsAdjustable());
  REQUIRE(ncp::BlasThreads() == 3);
  {
    const ncp::ScopedBlasThreads outer(1);
    CHECK(ncp::BlasThreads() == 1);
    {
      const ncp::ScopedBlasThreads inner(2);  // a larger request keeps the smaller count
      CHECK(ncp::BlasThreads() == 1);
    }
    CHECK(ncp::BlasThreads() == 1);  // the inner guard's end does not restore yet
    {
      const ncp::ScopedBlasThreads unchanged(0);
      CHECK(ncp::BlasThreads() == 1);
    }
  }
  CHECK(ncp::BlasThreads() == 3);
  {
    const ncp::ScopedBlasThreads two(2);
    CHECK(ncp::BlasThreads() == 2);
  }
  CHECK(ncp::BlasThreads() == 3);
  SetOpenBlasThreads(1);
}

TEST_CASE("ncp::Solver runs with Options::blas_threads and restores the count",
          "[blas]") {
  ncp::Vector a(6);
  a << 0.8, 0.6, -0.2, 0.1, 0.35, -1.0;
  ncp::collection::MixedTestProblem p = ncp::collection::SimplexProjection(a);
  ncp::Options options;
  CHECK(options.blas_threads == 1);
  std::string error;
  options.blas_threads = -1;
  CHECK_FALSE(options.IsValid(&error));
  CHECK(error.find("blas_threads") != std::string::npos);
  if (!SetOpenBlasThreads(2)) {
    WARN("no OpenBLAS in this process: nothing to check");
    return;
  }
  for (const int requested : {1, 0}) {
    options.blas_threads = requested;
    int during = -2;
    options.callback = [&](const ncp::IterationRecord&) {
      during = ncp::BlasThreads();
      return true;
    };
    ncp::Vector z = p.starts.front().x;
    ncp::Summary summary;
    ncp::Solver(options).Solve(*p.problem, &z, &summary);
    INFO("blas_threads = " << requested << ": " << summary.BriefReport());
    CHECK(summary.termination == ncp::TerminationType::kConverged);
    CHECK(during == (requested == 0 ? 2 : requested));
    CHECK(ncp::BlasThreads() == 2);
  }
  SetOpenBlasThreads(1);
}
