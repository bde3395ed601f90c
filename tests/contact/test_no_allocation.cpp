// No heap allocation in the Newton loop of a contact step (ContactSystem::Update,
// Evaluate and Jacobian at a fixed set of friction nodes; the iterations of
// ncp::Solver::Solve) and in the explicit time loop of RunDynamics (a constant few per
// step with the Newton-based steps), counted by replacing the process's allocation
// functions.
//
// Every heap allocation goes through operator new / new[] (std containers and strings,
// the values of Eigen's SparseMatrix) or malloc / calloc / realloc (Eigen's dense storage
// and sparse outer indices, SuiteSparse through SuiteSparse_malloc). The replacements
// below forward to glibc and, while counting is on, log the return address of each call,
// so an allocation is attributed afterwards (dladdr) to the shared object that asked for
// it: SuiteSparse's numeric factorizations and solves allocate inside the SuiteSparse
// libraries, which we cannot change; everything else - our code and the Eigen code
// inlined into it - must allocate nothing. Aligned operator new (unused here) is not
// counted. glibc only (__libc_malloc and friends).
#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <string>
#include <vector>

#include "block_on_floor.hpp"
#include "contact/contact_boundary.hpp"
#include "contact/contact_frames.hpp"
#include "contact/contact_system.hpp"
#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/obstacle.hpp"
#include "contact/scene.hpp"
#include "contact/static_contact.hpp"
#include "ncp/fc/operator_problem.hpp"
#include "ncp/fc/solver.hpp"
#include "ncp/solver.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/small_problems.hpp"

// ---------------------------------------------------------------------------------------
// Allocation log.
// ---------------------------------------------------------------------------------------

namespace {

constexpr long kLogCapacity = 1 << 16;
std::atomic<bool> g_counting{false};
std::atomic<long> g_count{0};
void* g_callers[kLogCapacity];  // return address of allocation k (k < kLogCapacity)

void LogAllocation(void* caller) {
  if (!g_counting.load(std::memory_order_relaxed)) return;
  const long k = g_count.fetch_add(1, std::memory_order_relaxed);
  if (k < kLogCapacity) g_callers[k] = caller;
}

void* CountedNew(std::size_t size, void* caller);

}  // namespace

extern "C" {
void* __libc_malloc(std::size_t size) noexcept;
void* __libc_calloc(std::size_t count, std::size_t size) noexcept;
void* __libc_realloc(void* pointer, std::size_t size) noexcept;
void __libc_free(void* pointer) noexcept;

void* malloc(std::size_t size) noexcept {
  LogAllocation(__builtin_return_address(0));
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  LogAllocation(__builtin_return_address(0));
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  LogAllocation(__builtin_return_address(0));
  return __libc_realloc(pointer, size);
}
}

void* operator new(std::size_t size) {
  return CountedNew(size, __builtin_return_address(0));
}
void* operator new[](std::size_t size) {
  return CountedNew(size, __builtin_return_address(0));
}
void operator delete(void* pointer) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { __libc_free(pointer); }

namespace {

void* CountedNew(std::size_t size, void* caller) {
  LogAllocation(caller);
  if (void* pointer = __libc_malloc(size == 0 ? 1 : size)) return pointer;
  throw std::bad_alloc();
}

long AllocationCount() { return g_count.load(); }

// True for an address inside one of the SuiteSparse libraries.
bool InSuiteSparse(void* address) {
  Dl_info info;
  if (dladdr(address, &info) == 0 || info.dli_fname == nullptr) return false;
  const std::string file = info.dli_fname;
  for (const char* library :
       {"libsuitesparseconfig", "libumfpack", "libklu", "libamd", "libcolamd", "libbtf",
        "libcholmod", "libcamd", "libccolamd"})
    if (file.find(library) != std::string::npos) return true;
  return false;
}

// The allocations logged while an instance was counting (one at a time).
class AllocationLog {
 public:
  AllocationLog() {
    g_count = 0;
    g_counting = true;
  }
  ~AllocationLog() { g_counting = false; }

  // Stops counting and attributes the logged allocations.
  void Stop() {
    g_counting = false;
    const long total = g_count.load();
    REQUIRE(total <= kLogCapacity);
    suitesparse_.assign(static_cast<size_t>(total), false);
    for (long k = 0; k < total; ++k)
      suitesparse_[static_cast<size_t>(k)] = InSuiteSparse(g_callers[k]);
  }
  long Total() const { return static_cast<long>(suitesparse_.size()); }
  // Allocations k in [begin, end) not made by SuiteSparse.
  long Ours(long begin, long end) const {
    long count = 0;
    for (long k = begin; k < end; ++k)
      count += suitesparse_[static_cast<size_t>(k)] ? 0 : 1;
    return count;
  }
  long Ours() const { return Ours(0, Total()); }
  // "address (shared object: symbol)" of the first 10 of our allocations in [begin, end).
  std::string DescribeOurs(long begin, long end) const {
    std::string out;
    int listed = 0;
    for (long k = begin; k < end && listed < 10; ++k) {
      if (suitesparse_[static_cast<size_t>(k)]) continue;
      ++listed;
      Dl_info info{};
      dladdr(g_callers[k], &info);
      char address[32];
      std::snprintf(address, sizeof address, "%p", g_callers[k]);
      out += std::string("\n  ") + address + " (" +
             (info.dli_fname ? info.dli_fname : "?") + ": " +
             (info.dli_sname ? info.dli_sname : "?") + ")";
    }
    return out;
  }

 private:
  std::vector<bool> suitesparse_;
};

// ---------------------------------------------------------------------------------------
// The contact problem: a steel block on a rigid floor with Tresca friction.
// ---------------------------------------------------------------------------------------

// Block [0, 2] x [0, 1] (x [0, 1]) m of steel, 8 x 4 Q4 in 2D (4 x 2 x 2 Hex8 in 3D),
// roller u_x = 0 on x = 0, pressed onto the floor by p = 10 MPa and pulled along +x by
// s = 2 MPa on the top; Tresca bound g_c = 0.1 p area_c, so that some floor nodes stick
// and some slip. As in SolveStaticContact, S = K / k and q = -f / k, k = max_i K_ii.
struct BlockOnFloor {
  Eigen::SparseMatrix<double> S;
  Eigen::VectorXd q, bound;
  std::vector<contact::ContactNode> nodes;
};

BlockOnFloor MakeBlockOnFloor(int dim) {
  using namespace contact;
  const double pressure = 10e6, shear = 2e6;
  Mesh mesh;
  if (dim == 2) {
    RectangleMeshOptions o;
    o.size = {2.0, 1.0};
    o.cells = {8, 4};
    o.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                    {Side::kYMin, BoundaryRole::kContact},
                    {Side::kYMax, BoundaryRole::kLoad}};
    mesh = MakeRectangleMesh(o);
  } else {
    BoxMeshOptions o;
    o.size = {2.0, 1.0, 1.0};
    o.cells = {4, 2, 2};
    o.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                    {Side::kZMin, BoundaryRole::kContact},
                    {Side::kZMax, BoundaryRole::kLoad}};
    mesh = MakeStructuredBoxMesh(o);
  }
  DofMap dofs = MakeDofMap(mesh, {DirichletCondition{kFixedGroup, {0}, {}}});
  const ElasticBody body(std::move(mesh), IsotropicMaterial{210e9, 0.3, 7850.0});
  const ContactBoundary boundary = MakeContactBoundary(body);
  const ContactFrames frames = MakeContactFrames(
      body.mesh(), boundary, dofs, HalfSpace::ObstacleBelow(dim, dim - 1, 0.0),
      NormalSource::kObstacle);
  Eigen::VectorXd traction = Eigen::VectorXd::Zero(dim);
  traction(0) = shear;
  traction(dim - 1) = -pressure;
  const SparseMatrix K_full = body.StiffnessMatrix();
  const SparseMatrix K = dofs.RestrictMatrix(K_full);
  const Vector f = dofs.RestrictLoad(K_full, body.TractionLoad(traction));
  const double k = K.diagonal().maxCoeff();
  BlockOnFloor block;
  block.S = K / k;
  block.q = -f / k;
  block.nodes = frames.nodes;
  block.bound.resize(static_cast<Eigen::Index>(block.nodes.size()));
  for (size_t c = 0; c < block.nodes.size(); ++c)
    block.bound(static_cast<Eigen::Index>(c)) = 0.1 * pressure * block.nodes[c].area / k;
  return block;
}

// marks[k]: the allocation count when iterate k of one solve was reported. Nothing
// allocated before the first iterate (Evaluate, Jacobian, the Jacobian of Phi) or between
// two iterates (Newton solve, line search, Jacobian at the new iterate); after the last
// one at most the Summary's termination message (returned).
long CheckNothingAllocatedPerIteration(const AllocationLog& log,
                                       const std::vector<long>& marks) {
  INFO("start:" << log.DescribeOurs(0, marks.front()));
  CHECK(log.Ours(0, marks.front()) == 0);
  for (size_t k = 0; k + 1 < marks.size(); ++k) {
    INFO("iteration " << k + 1 << ":" << log.DescribeOurs(marks[k], marks[k + 1]));
    CHECK(log.Ours(marks[k], marks[k + 1]) == 0);
  }
  const long ours_at_end = log.Ours(marks.back(), log.Total());
  CHECK(ours_at_end <= 8);
  return ours_at_end;
}

}  // namespace

TEST_CASE(
    "ContactSystem: Update, Evaluate and Jacobian allocate nothing at a fixed layout",
    "[contact][allocation]") {
  const int dim = GENERATE(2, 3);
  CAPTURE(dim);
  const BlockOnFloor block = MakeBlockOnFloor(dim);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(block.q.size());
  contact::ContactSystem system(dim, block.S, block.nodes);
  system.Update(block.q, zero, block.bound);
  REQUIRE(system.num_friction_nodes() > 0);
  const int N = system.NumVariables(), m = system.NumEquations();
  // The start point (zero slips; in 3D the direction t = (1, 0), so entries t_2 and the
  // slips are exactly 0 there) and two pseudo-random points.
  const ncp::Vector start = system.StartPoint(zero);
  const ncp::Vector points[3] = {start, start + 1e-3 * ncp::Vector::Random(N),
                                 start + ncp::Vector::Random(N)};
  // Data of the next step: other loads and bounds, same friction nodes.
  const Eigen::VectorXd q_next = 2.0 * block.q, bound_next = 0.5 * block.bound;

  ncp::Vector E(m), A(N - m), B(N - m);
  ncp::SparseMatrix JE, JA, JB;
  {
    // Warm-up: builds the patterns and sizes JE, JA, JB - with allocations the log sees.
    AllocationLog warm_up;
    REQUIRE(system.Evaluate(start, &E, &A, &B));
    REQUIRE(system.Jacobian(start, &JE, &JA, &JB));
    warm_up.Stop();
    CHECK(warm_up.Ours() > 0);
  }
  const double* storage[3] = {JE.valuePtr(), JA.valuePtr(), JB.valuePtr()};

  AllocationLog log;
  for (const ncp::Vector& z : points) {
    system.Evaluate(z, &E, &A, &B);
    system.Jacobian(z, &JE, &JA, &JB);
  }
  system.Update(q_next, zero, bound_next);
  system.Evaluate(points[2], &E, &A, &B);
  system.Jacobian(points[2], &JE, &JA, &JB);
  log.Stop();
  INFO("allocations:" << log.DescribeOurs(0, log.Total()));
  CHECK(log.Total() == 0);
  CHECK(JE.valuePtr() == storage[0]);
  CHECK(JA.valuePtr() == storage[1]);
  CHECK(JB.valuePtr() == storage[2]);

  // The values written in place equal a fresh assembly at that point.
  contact::ContactSystem fresh(dim, block.S, block.nodes);
  fresh.Update(q_next, zero, bound_next);
  ncp::SparseMatrix fresh_JE, fresh_JA, fresh_JB;
  REQUIRE(fresh.Jacobian(points[2], &fresh_JE, &fresh_JA, &fresh_JB));
  CHECK(Eigen::MatrixXd(JE) == Eigen::MatrixXd(fresh_JE));
  CHECK(Eigen::MatrixXd(JA) == Eigen::MatrixXd(fresh_JA));
  CHECK(Eigen::MatrixXd(JB) == Eigen::MatrixXd(fresh_JB));
}

// Eigen::SparseLU is not run here: its factorize() allocates its supernodal storage on
// every numeric factorization, in Eigen code inlined into ncp (not attributable, and not
// avoidable without rewriting it).
TEST_CASE("ncp::Solver on a frictional contact problem: no allocation in the iterations",
          "[contact][allocation]") {
  const ncp::LinearSolverType backend =
      GENERATE(ncp::LinearSolverType::kDenseLU, ncp::LinearSolverType::kUmfpack,
               ncp::LinearSolverType::kKlu);
  CAPTURE(ncp::ToString(backend));
  const BlockOnFloor block = MakeBlockOnFloor(2);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(block.q.size());
  contact::ContactSystem system(2, block.S, block.nodes);
  system.Update(block.q, zero, block.bound);

  // Allocation count at every callback, i.e. at every iterate k after its Jacobian.
  std::vector<long> marks;
  marks.reserve(1000);
  ncp::Options options = contact::ContactNcpOptions();
  options.linear_solver = backend;
  options.callback = [&marks](const ncp::IterationRecord&) {
    marks.push_back(AllocationCount());
    return true;
  };
  ncp::Solver solver(options);
  ncp::Summary summary;
  ncp::Vector z = system.StartPoint(zero);
  solver.Solve(system, &z, &summary);  // warm-up: workspace, patterns, symbolic analysis
  INFO(summary.message);
  REQUIRE(summary.IsSolutionUsable());
  // One symbolic analysis for the whole solve: ContactSystem's pattern stays fixed (the
  // dense LU has no symbolic phase).
  CHECK(summary.symbolic_factorizations ==
        (backend == ncp::LinearSolverType::kDenseLU ? 0 : 1));
  const Eigen::VectorXd solution = system.Extract(z).x;

  // A new start: half the solution displacement.
  z = system.StartPoint(0.5 * solution);
  marks.clear();
  AllocationLog log;
  solver.Solve(system, &z, &summary);
  log.Stop();
  INFO(summary.message);
  REQUIRE(summary.IsSolutionUsable());
  CHECK(summary.symbolic_factorizations == 0);  // the warm-up's analysis is reused
  REQUIRE(summary.iterations >= 3);
  REQUIRE(marks.size() == static_cast<size_t>(summary.iterations) + 1);

  const long ours_at_end = CheckNothingAllocatedPerIteration(log, marks);
  // Dense LU is Eigen only: nothing at all from SuiteSparse; UMFPACK and KLU allocate in
  // every numeric factorization (and UMFPACK in every solve), which the log attributes.
  if (backend == ncp::LinearSolverType::kDenseLU)
    CHECK(log.Total() == log.Ours());
  else
    CHECK(log.Total() - log.Ours() >= summary.iterations);
  std::printf(
      "%s: %d iterations, allocations: %ld ours (%ld in the termination message), %ld in "
      "SuiteSparse\n",
      ncp::ToString(backend), summary.iterations, log.Ours(), ours_at_end,
      log.Total() - log.Ours());
}

// The static solver's repeated solves: Coulomb friction by a fixed point of Tresca solves
// (SolveStaticContact), one ncp::Solver and one ContactSystem for all rounds. The Newton
// iterations allocate nothing (test above); a round allocates a constant few whatever its
// iteration count: the start point and the extracted result, returned by value by
// ContactSystem, and the Summary's termination message.
TEST_CASE("SolveStaticContact, Coulomb fixed point: a constant few allocations per round",
          "[contact][allocation]") {
  const BlockOnFloor block = MakeBlockOnFloor(2);
  contact::StaticContactOptions options;
  options.friction = contact::FrictionLaw::kCoulomb;
  options.friction_coefficient = 0.1;
  // The start of every round (its iterate 0, after the start point's Jacobian).
  std::vector<long> round_starts;
  std::vector<int> round_iterations;
  round_starts.reserve(1000);
  round_iterations.reserve(1000);
  options.ncp.callback = [&](const ncp::IterationRecord& record) {
    if (record.iteration == 0) {
      round_starts.push_back(AllocationCount());
      round_iterations.push_back(0);
    } else {
      round_iterations.back() = record.iteration;
    }
    return true;
  };
  // S = K / k with k = max_i K_ii: max_i S_ii = 1, so S and -q are K and f in units where
  // k = 1.
  AllocationLog log;
  const contact::StaticContactResult result =
      contact::SolveStaticContact(2, block.S, -block.q, block.nodes, options);
  log.Stop();
  INFO(result.message);
  REQUIRE(result.converged);
  REQUIRE(round_starts.size() == static_cast<size_t>(result.fixed_point_iterations));
  REQUIRE(result.fixed_point_iterations >= 3);
  // Rounds 2 .. last - 1 (from the start of one round to the start of the next).
  long fewest = std::numeric_limits<long>::max(), most = 0;
  int iterations = 0;
  for (size_t k = 1; k + 1 < round_starts.size(); ++k) {
    const long ours = log.Ours(round_starts[k], round_starts[k + 1]);
    fewest = std::min(fewest, ours);
    most = std::max(most, ours);
    iterations += round_iterations[k];
  }
  std::printf(
      "SolveStaticContact Coulomb: %d rounds, %d Newton iterations in rounds 2-%d, %ld "
      "to "
      "%ld allocations per round\n",
      result.fixed_point_iterations, iterations, result.fixed_point_iterations - 1,
      fewest, most);
  CHECK(iterations > static_cast<int>(round_starts.size()) - 2);  // rounds iterate
  // The start point (2 vectors), the result (5) and the message, whose length varies.
  CHECK(most <= 24);
}

// ---------------------------------------------------------------------------------------
// The light path of small box MCPs: a Solver kept between solves.
// ---------------------------------------------------------------------------------------

TEST_CASE("ncp box MCP, n = 4, a Solver kept between solves: no allocation per iteration",
          "[ncp][allocation]") {
  // Kojima and Shindo's NCP (MCPLIB kojshin), whose Jacobian fills a fixed dense pattern.
  ncp::collection::TestProblem kojshin = ncp::collection::KojimaShindo();
  ncp::SquareFunction& F = *kojshin.F;
  const ncp::Vector& lower = kojshin.lower;
  const ncp::Vector& upper = kojshin.upper;
  std::vector<long> marks;
  marks.reserve(1000);
  ncp::Options options;  // defaults: FB, kAuto = dense LU at n = 4
  options.callback = [&marks](const ncp::IterationRecord&) {
    marks.push_back(AllocationCount());
    return true;
  };
  ncp::Solver solver(options);
  ncp::Summary summary;
  ncp::Vector x = kojshin.starts.front().x;
  solver.Solve(F, lower, upper, &x,
               &summary);  // warm-up: workspace, mixed form, J's pattern
  REQUIRE(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_used == ncp::LinearSolverType::kDenseLU);

  for (const double start : {1.0, 100.0}) {
    CAPTURE(start);
    x = ncp::Vector::Constant(4, start);
    marks.clear();
    AllocationLog log;
    solver.Solve(F, lower, upper, &x, &summary);
    log.Stop();
    INFO(summary.message);
    REQUIRE(summary.IsSolutionUsable());
    REQUIRE(marks.size() == static_cast<size_t>(summary.iterations) + 1);
    // The solution: min(x, F(x)) = 0 recomputed, and one of Kojima-Shindo's two known
    // solutions, (1, 0, 3, 0) and (sqrt(6)/2, 0, 0, 1/2).
    ncp::Vector Fx(4);
    F.Evaluate(x, &Fx);
    CHECK(x.cwiseMin(Fx).cwiseAbs().maxCoeff() <= 1e-9);
    double distance = std::numeric_limits<double>::infinity();
    for (const ncp::Vector& known : kojshin.solutions)
      distance = std::min(distance, (x - known).lpNorm<Eigen::Infinity>());
    CHECK(kojshin.solutions.size() == 2);
    CHECK(distance <= 1e-8);
    // Nothing before the first iterate, nothing in any iteration, only the termination
    // message at the end.
    CheckNothingAllocatedPerIteration(log, marks);
    CHECK(log.Total() == log.Ours());  // dense LU: nothing from SuiteSparse
    std::printf("kojshin from %g: %d iterations, %ld allocations (termination message)\n",
                start, summary.iterations, log.Ours());
  }
}

// A mixed problem with free variables, one- and two-sided bounds and a fixed variable:
// the box MCP's mixed form has equations, pairs and slacks, and on the dense backend
// writes the Jacobian of Phi itself.
TEST_CASE(
    "ncp box MCP with every kind of bound, n = 10, a Solver kept: no allocation per "
    "iteration",
    "[ncp][allocation]") {
  ncp::collection::TestProblem p = ncp::collection::EveryBoundCubic();
  std::vector<long> marks;
  marks.reserve(1000);
  ncp::Options options;  // defaults: FB, kAuto = dense LU at n = 10 (+ 2 slacks)
  options.callback = [&marks](const ncp::IterationRecord&) {
    marks.push_back(AllocationCount());
    return true;
  };
  ncp::Solver solver(options);
  ncp::Summary summary;
  ncp::Vector x = p.starts.front().x;
  solver.Solve(*p.F, p.lower, p.upper, &x, &summary);  // warm-up: workspace, mixed form
  REQUIRE(summary.IsSolutionUsable());
  CHECK(summary.linear_solver_used == ncp::LinearSolverType::kDenseLU);
  CHECK(summary.num_equations == 6);  // 4 free, 1 fixed, 1 two-sided (slack split)
  for (const ncp::collection::StartPoint& start : p.starts) {
    CAPTURE(start.label);
    x = start.x;
    marks.clear();
    AllocationLog log;
    solver.Solve(*p.F, p.lower, p.upper, &x, &summary);
    log.Stop();
    INFO(summary.message);
    REQUIRE(summary.IsSolutionUsable());
    REQUIRE(marks.size() == static_cast<size_t>(summary.iterations) + 1);
    CHECK(summary.iterations >= 3);
    // The solution, recomputed: x - mid(l, u, x - F(x)) = 0.
    CHECK(ncp::collection::NaturalResidual(*p.F, p.lower, p.upper, x) <= 1e-9);
    CheckNothingAllocatedPerIteration(log, marks);
    CHECK(log.Total() == log.Ours());  // dense LU: nothing from SuiteSparse
    std::printf(
        "every-bound-cubic from %s: %d iterations, %ld allocations (termination "
        "message)\n",
        start.label.c_str(), summary.iterations, log.Ours());
  }
}

// ---------------------------------------------------------------------------------------
// ncp::fc's solvers kept between solves (the steps of contact's coulomb-fc steps).
// ---------------------------------------------------------------------------------------

namespace {

// 8 contacts in 3D, W = G G' / 24 + 0.1 I (G 24 x 24 pseudo-random, fixed seed: symmetric
// positive definite, every contact coupled to every other), mu = 0.3, and six q whose
// normal parts change sign from solve to solve: the set of separated contacts (and with
// it the reduced system of the dense solver) changes between solves.
struct FcSequence {
  Eigen::MatrixXd W;
  ncp::fc::FrictionProblem problem;  // W sparse, q of the first solve
  std::vector<Eigen::VectorXd> q;
};

FcSequence MakeFcSequence() {
  constexpr int kContacts = 8, kSize = 3 * kContacts;
  std::srand(28);
  const Eigen::MatrixXd G = Eigen::MatrixXd::Random(kSize, kSize);
  FcSequence s;
  s.W = G * G.transpose() / kSize + 0.1 * Eigen::MatrixXd::Identity(kSize, kSize);
  for (int k = 0; k < 6; ++k) {
    Eigen::VectorXd q = 0.5 * Eigen::VectorXd::Random(kSize);
    for (int a = 0; a < kContacts; ++a) q(3 * a) = std::cos(0.9 * k + 1.7 * a);
    s.q.push_back(q);
  }
  s.problem.dimension = 3;
  s.problem.num_contacts = kContacts;
  s.problem.W = s.W.sparseView(0.0, 0.0);
  s.problem.q = s.q.front();
  s.problem.mu = Eigen::VectorXd::Constant(kContacts, 0.3);
  s.problem.name = "allocation sequence";
  return s;
}

// Contacts with r_N > 0 (3D: r_N every third entry).
int Touching(const Eigen::VectorXd& r) {
  int count = 0;
  for (Eigen::Index i = 0; i < r.size(); i += 3) count += r(i) > 0.0 ? 1 : 0;
  return count;
}

}  // namespace

TEST_CASE(
    "ncp::fc::Solver and OperatorSolver kept between solves: nothing allocated after the "
    "first, the same bits as one-shot solves",
    "[fc][allocation]") {
  const bool matrix_free = GENERATE(false, true);
  CAPTURE(matrix_free);
  const FcSequence sequence = MakeFcSequence();
  const ncp::fc::Options options;  // the hybrid, tolerance 1e-8

  // One-shot solves (a new solver each): the reference, from r = 0.
  ncp::fc::OperatorProblem op;
  op.dimension = 3;
  op.num_contacts = sequence.problem.num_contacts;
  op.apply_W = [&sequence](const Eigen::VectorXd& r, Eigen::VectorXd* Wr) {
    Wr->noalias() = sequence.W * r;
  };
  op.diagonal = sequence.W.diagonal();
  op.mu = sequence.problem.mu;
  op.name = sequence.problem.name;
  std::vector<Eigen::VectorXd> reference;
  std::vector<int> iterations;
  for (const Eigen::VectorXd& q : sequence.q) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(q.size());
    ncp::fc::Summary summary;
    if (matrix_free) {
      op.q = q;
      ncp::fc::Solve(options, op, &r, &summary);
    } else {
      ncp::fc::FrictionProblem problem = sequence.problem;
      problem.q = q;
      ncp::fc::Solve(options, problem, &r, &summary);
    }
    INFO(summary.message);
    REQUIRE(summary.IsSolutionUsable());
    REQUIRE(summary.iterations > 0);
    reference.push_back(r);
    iterations.push_back(summary.iterations);
  }
  int fewest = 1 << 30, most = 0;
  for (const Eigen::VectorXd& r : reference) {
    fewest = std::min(fewest, Touching(r));
    most = std::max(most, Touching(r));
  }
  CHECK(fewest < most);  // the contact set changes between solves

  // One solver for the sequence: after the first solve, nothing allocated at all.
  ncp::fc::Solver solver(sequence.problem);
  ncp::fc::OperatorSolver operator_solver;
  ncp::fc::Summary summary;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(sequence.problem.size());
  for (size_t k = 0; k < sequence.q.size(); ++k) {
    CAPTURE(k);
    r.setZero();
    AllocationLog log;
    if (matrix_free) {
      op.q = sequence.q[k];
      operator_solver.Solve(options, op, &r, &summary);
    } else {
      solver.SetQ(sequence.q[k]);
      solver.Solve(options, &r, &summary);
    }
    log.Stop();
    INFO(summary.message);
    REQUIRE(summary.IsSolutionUsable());
    CHECK(summary.iterations == iterations[k]);
    CHECK(r == reference[k]);  // bit for bit
    if (k > 0) {
      INFO("allocations:" << log.DescribeOurs(0, log.Total()));
      CHECK(log.Total() == 0);
    }
  }
}

// ---------------------------------------------------------------------------------------
// The time loop of RunDynamics.
// ---------------------------------------------------------------------------------------

namespace {

// A 2 x 1 m steel block of 8 x 4 Q4 thrown at the floor y >= 0 with v = (1, -1) m/s, f_c
// = 0.3: its bottom nodes hit the floor in the first steps and slide on it.
contact::SceneModel ThrownBlock(
    contact::StepMethod method,
    contact::FrictionFormulation formulation = contact::FrictionFormulation::kLaggedBound,
    int steps = 30) {
  using namespace contact;
  Scene scene = testing::SteelBlockOnFloor(
      method == StepMethod::kExplicit ? MassKind::kLumped : MassKind::kConsistent);
  scene.dynamics.end_time = steps * scene.dynamics.dt;
  scene.dynamics.step_method = method;
  // kLaggedBound: the Newton steps of ContactSystem (eq. 94); kCoulombFc: ncp::fc.
  scene.dynamics.friction_formulation = formulation;
  scene.dynamics.initial_state = InitialState::kPrescribed;
  scene.initial_velocity = Eigen::Vector2d(1.0, -1.0);
  return BuildSceneModel(scene);
}

}  // namespace

TEST_CASE(
    "RunDynamics: the explicit time loop allocates nothing, Newton steps a constant",
    "[contact][allocation][dynamics]") {
  const contact::StepMethod method =
      GENERATE(contact::StepMethod::kExplicit, contact::StepMethod::kCondensed,
               contact::StepMethod::kFull);
  CAPTURE(contact::ToString(method));
  contact::SceneModel built = ThrownBlock(method);
  // Allocation count after every step (the callback itself allocates nothing).
  std::vector<long> marks;
  marks.reserve(100);
  double normal_force = 0.0, friction_force = 0.0;
  built.options.on_step = [&](const contact::StepRecord& r, const Eigen::VectorXd&,
                              const contact::ContactSystem::Result&, double) {
    marks.push_back(AllocationCount());
    normal_force = std::max(normal_force, r.normal_force_sum);
    friction_force = std::max(friction_force, r.tangent_force_sum);
  };
  AllocationLog log;
  const contact::DynamicSummary s = contact::RunDynamics(built.model, built.options);
  log.Stop();
  INFO(s.message);
  REQUIRE(s.status == contact::DynamicStatus::kCompleted);
  REQUIRE(marks.size() == 30);
  CHECK(normal_force > 0.0);    // it hit the floor
  CHECK(friction_force > 0.0);  // and slid with friction
  // Steps 5..30 (after the contact set and friction layout have settled).
  long most = 0, total = 0;
  for (size_t k = 4; k + 1 < marks.size(); ++k) {
    const long ours = log.Ours(marks[k], marks[k + 1]);
    most = std::max(most, ours);
    total += ours;
  }
  std::printf(
      "RunDynamics %s: at most %ld allocations per step in steps 5-30 (%ld in all), %ld "
      "in SuiteSparse\n",
      contact::ToString(method), most, total, log.Total() - log.Ours());
  if (method == contact::StepMethod::kExplicit) {
    INFO("allocations:" << log.DescribeOurs(marks[4], marks.back()));
    CHECK(total == 0);
    CHECK(log.Total() - log.Ours() == 0);
  } else {
    // The Newton iterations allocate nothing (test above); per step remain the start
    // point, the extracted result and the Summary's message: a few, whatever the
    // iteration count.
    CHECK(most <= 24);
  }
}

// Implicit Coulomb (kCoulombFc) by ncp::fc: the condensed step keeps one ncp::fc::Solver
// for the run (W's block form, rho, the Jacobian's pattern, the work vectors, the reduced
// system's storage for all contacts coupled, the trace for max_iterations records), the
// sparse step one ncp::fc::OperatorSolver (the Newton blocks and vectors, the GMRES basis
// of n x 51); the attempt sequence is static and the Summary's message is written into
// its kept storage. So once the first step with Newton iterations has sized them, no step
// allocates - also while the contact set changes, which moves the size of the condensed
// step's reduced system and the preconditioner's blocks of the sparse one. (CHOLMOD's
// solves with the factor of M in the sparse step allocate inside SuiteSparse: reported,
// not ours.)
TEST_CASE(
    "RunDynamics: the coulomb-fc condensed and sparse steps allocate nothing after "
    "warm-up",
    "[contact][allocation][dynamics]") {
  const contact::StepMethod method =
      GENERATE(contact::StepMethod::kCondensed, contact::StepMethod::kSparse);
  CAPTURE(contact::ToString(method));
  constexpr int kSteps = 200;
  contact::SceneModel built =
      ThrownBlock(method, contact::FrictionFormulation::kCoulombFc, kSteps);
  std::vector<long> marks;
  std::vector<int> iterations, in_contact;
  marks.reserve(kSteps);
  iterations.reserve(kSteps);
  in_contact.reserve(kSteps);
  double friction_force = 0.0;
  built.options.on_step = [&](const contact::StepRecord& r, const Eigen::VectorXd&,
                              const contact::ContactSystem::Result& result, double) {
    marks.push_back(AllocationCount());
    iterations.push_back(r.newton_iterations);
    in_contact.push_back(static_cast<int>((result.normal_force.array() > 0.0).count()));
    friction_force = std::max(friction_force, r.tangent_force_sum);
  };
  AllocationLog log;
  const contact::DynamicSummary s = contact::RunDynamics(built.model, built.options);
  log.Stop();
  INFO(s.message);
  REQUIRE(s.status == contact::DynamicStatus::kCompleted);
  REQUIRE(marks.size() == static_cast<size_t>(kSteps));
  CHECK(friction_force > 0.0);  // it slid with friction
  // Warm-up: up to the first step with Newton iterations (it sizes the workspaces).
  size_t first = 0;
  while (first < iterations.size() && iterations[first] == 0) ++first;
  REQUIRE(first + 1 < iterations.size());
  // Steps first + 1 .. kSteps (step k + 1 spans marks[k] .. marks[k + 1]).
  long total = 0, suitesparse = 0, newton = 0;
  int fewest = std::numeric_limits<int>::max(), most = 0;
  for (size_t k = first; k + 1 < marks.size(); ++k) {
    const long ours = log.Ours(marks[k], marks[k + 1]);
    INFO("step " << k + 2 << " (" << iterations[k + 1] << " Newton iterations, "
                 << in_contact[k + 1]
                 << " nodes in contact):" << log.DescribeOurs(marks[k], marks[k + 1]));
    CHECK(ours == 0);
    total += ours;
    suitesparse += marks[k + 1] - marks[k] - ours;
    newton += iterations[k + 1];
    fewest = std::min(fewest, in_contact[k + 1]);
    most = std::max(most, in_contact[k + 1]);
  }
  std::printf(
      "RunDynamics coulomb-fc %s: steps %zu-%d: %ld allocations of ours, %ld in "
      "SuiteSparse, %ld Newton iterations, %d to %d nodes in contact\n",
      contact::ToString(method), first + 2, kSteps, total, suitesparse, newton, fewest,
      most);
  // The counted steps solve (Newton iterations) and the contact set changes in them.
  CHECK(newton > 0);
  CHECK(fewest < most);
}
