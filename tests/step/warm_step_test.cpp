// A warm step allocates nothing of its own (DESIGN.md §3: no allocation per step once warm): the
// solve stage given the same problem again, with its island cache, and a World stepping a pile at
// rest make no heap call at all. Counted by interposing malloc, calloc and realloc in this test
// program, so that Eigen's and the standard library's allocations count as well as operator new's.
// Not under the sanitizers, which interpose malloc themselves.
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "solve/island_cache.hpp"
#include "solve/newton_substructured.hpp"
#include "solve/random_blcp.hpp"
#include "solve/solve.hpp"
#include "step/world_internals.hpp"

#include <rbpart/world.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstddef>
#include <random>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RBPART_COUNTS_ALLOCATIONS 0
#else
#define RBPART_COUNTS_ALLOCATIONS 1
#endif

namespace {

std::atomic<bool> counting{false};
std::atomic<long> ours{0};

void count_one() {
  if (counting.load(std::memory_order_relaxed)) ours.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

#if RBPART_COUNTS_ALLOCATIONS
// glibc's own entry points, under the names it exports for interposers.
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);

extern "C" void* malloc(std::size_t n) {
  count_one();
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t count, std::size_t n) {
  count_one();
  return __libc_calloc(count, n);
}
extern "C" void* realloc(void* p, std::size_t n) {
  count_one();
  return __libc_realloc(p, n);
}
#endif

namespace rbpart {
namespace {

// Our heap calls while fn() runs.
template <class Fn>
long allocations_in(Fn&& fn) {
  ours = 0;
  counting = true;
  fn();
  counting = false;
  return ours.load();
}

// One step's solve-stage input.
struct Problem {
  Rows rows;
  Bodies bodies;
  Islands islands;
  ConstraintGraph graph;
};

// The built-in box pile's step after `steps` steps: islands of every size, dense and sparse, some
// rows tied and, in the falling phase, islands that need the interior-point phase.
Problem box_pile_step(int steps) {
  World world(make_builtin_scene("box_pile"));
  for (int i = 0; i < steps; ++i) world.step();
  Problem p;
  set_problem_observer(world, [&](const Rows& rows, const Bodies& bodies, const Islands& islands,
                                  const ConstraintGraph& graph) {
    p.rows = rows;
    p.bodies = bodies;
    p.islands = islands;
    p.graph = graph;
  });
  world.step();
  return p;
}

class WarmStep : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!RBPART_COUNTS_ALLOCATIONS) GTEST_SKIP() << "the sanitizers interpose malloc themselves";
  }
  // One thread: a TBB worker joining for the first time sets up its own state, and which thread
  // first meets which island or pair (and grows its buffers) is up to the scheduler.
  tbb::global_control one_thread{tbb::global_control::max_allowed_parallelism, 1};
};

TEST_F(WarmStep, TheDirectSolverAllocatesNothingOnAStepItHasSeen) {
  const Problem p = box_pile_step(60);
  DirectCache cache;
  const SolverParams params;
  for (int call = 0; call < 3; ++call) {
    Rows rows = p.rows;  // the same warm start every time
    const long count = allocations_in([&] { solve_newton_direct(rows, p.bodies, p.islands, params, &cache); });
    // The first call sets up every island's buffers: the counter counts.
    if (call == 0) EXPECT_GT(count, 0);
    else EXPECT_EQ(count, 0) << "call " << call;
  }
}

TEST_F(WarmStep, TheSubstructuredSolverAllocatesNothingOnAStepItHasSeen) {
  const Problem p = box_pile_step(60);
  for (const PartitionerKind partitioner : {PartitionerKind::Mix, PartitionerKind::Metis}) {
    PartitionParams pp;
    pp.partitioner = partitioner;
    pp.nmax = 4;
    Partition partition;
    partition_graph(p.graph, pp, partition);
    SubstructuredCache cache;
    const SolverParams params;
    for (int call = 0; call < 3; ++call) {
      Rows rows = p.rows;
      NewtonSubstructuredReport report;
      const long count = allocations_in(
          [&] { report = solve_newton_substructured(rows, p.bodies, p.islands, p.graph, partition, params, &cache); });
      if (call == 0) {
        EXPECT_GT(count, 0);
        EXPECT_GT(report.interface_rows, 0);  // parts and an interface to set up
      } else {
        EXPECT_EQ(count, 0) << "call " << call;
      }
    }
  }
}

// Random islands harder than a pile's (many contacts on few bodies): the interior-point phase, and
// both the dense and the sparse factorisations.
TEST_F(WarmStep, HardRandomIslandsAllocateNothingWhenSolvedAgain) {
  std::mt19937 rng(5);
  for (const int bodies : {3, 40}) {
    testing::IslandOptions options;
    options.rows = 15 * bodies;
    options.bodies = bodies;
    testing::RandomIsland island;
    testing::random_contact_island(rng, options, island);
    DirectCache cache;
    const SolverParams params;
    for (int call = 0; call < 3; ++call) {
      Rows rows = island.rows;
      SolveStats stats;
      const long count =
          allocations_in([&] { stats = solve_newton_direct(rows, island.bodies, island.islands, params, &cache); });
      if (call == 0) EXPECT_GT(count, 0);
      else EXPECT_EQ(count, 0) << bodies << " bodies, call " << call;
      EXPECT_GT(stats.factorizations, 1);
    }
  }
}

// A stack of boxes at rest, its contacts unchanged from step to step: every stage (collision, the
// graph and islands, the solve, integration). On one thread, as the fixture has it: with more,
// which thread first meets which pair (and grows its scratch) is up to the scheduler.
TEST_F(WarmStep, AWorldAtRestAllocatesNothingFromStepToStep) {
  World world(make_builtin_scene("box_stack", {{"boxes", "6"}}));
  for (int i = 0; i < 120; ++i) world.step();
  const int contacts = world.step().contacts;
  ASSERT_GT(contacts, 0);
  for (int i = 0; i < 5; ++i) {
    int now = 0;
    const long count = allocations_in([&] { now = world.step().contacts; });
    ASSERT_EQ(now, contacts) << "the stack is not at rest";
    EXPECT_EQ(count, 0) << "step " << i;
  }
}

}  // namespace
}  // namespace rbpart
