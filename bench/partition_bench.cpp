// Partition and refinement time per body, and the result's quality, for every partitioner and
// refiner on two kinds of graphs:
//   partition/<partitioner>+<refiner>/pile:<n>/nmax:<nmax>  rock-pile-like generated graphs
//       (graph/generate.hpp pile_graph, masses from {10, 100, 1000} kg) of 10^3, 10^4, 10^5 bodies;
//   partition/<partitioner>+<refiner>/<scene>/nmax:<nmax>   the paper's scenes' constraint graphs
//       after 300 steps (settled with PGS, which is quick; only the contact graph matters here).
// Counters: partition_ns_per_body, refine_ns_per_body (thread CPU time, so that other load on the
// machine does not inflate them; both stages are serial), parts, cut, interface_rows, and
// cut_vs_metis (the edge cut over METIS's, without refinement, on the same graph and nmax).
#include <benchmark/benchmark.h>
#include <rbpart/world.hpp>
#include <time.h>

#include <functional>
#include <map>
#include <string>
#include <utility>

#include "graph/constraint_graph.hpp"
#include "graph/generate.hpp"
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

// Graphs by name, made once on first use.
const ConstraintGraph& workload(const std::string& name, const std::function<ConstraintGraph()>& make) {
  static std::map<std::string, ConstraintGraph> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, make()).first;
  return it->second;
}

ConstraintGraph settled_scene_graph(const std::string& scene) {
  SolverParams pgs;
  pgs.kind = SolverKind::Pgs;
  World world(make_builtin_scene(scene), {}, pgs);
  for (int i = 0; i < 300; ++i) world.step();
  return world_graph(world);
}

int metis_cut(const std::string& name, const ConstraintGraph& g, int nmax) {
  static std::map<std::pair<std::string, int>, int> cache;
  const auto key = std::make_pair(name, nmax);
  auto it = cache.find(key);
  if (it == cache.end()) {
    PartitionParams p;
    p.partitioner = PartitionerKind::Metis;
    p.nmax = nmax;
    Partition part;
    partition_graph(g, p, part);
    it = cache.emplace(key, measure_partition(g, part).edge_cut).first;
  }
  return it->second;
}

double thread_cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * t.tv_sec + t.tv_nsec;
}

void run(benchmark::State& state, const PartitionParams& params, const std::string& name, const ConstraintGraph& g) {
  const int reference = metis_cut(name, g, params.nmax);
  double partition_ns = 0, refine_ns = 0;
  Partition part;
  for (auto _ : state) {
    const double t0 = thread_cpu_ns();
    partition_graph(g, params, part);
    const double t1 = thread_cpu_ns();
    refine_partition(g, params, part);
    partition_ns += t1 - t0;
    refine_ns += thread_cpu_ns() - t1;
    benchmark::DoNotOptimize(part.part_of.data());
  }
  const double per_body = 1.0 / (static_cast<double>(state.iterations()) * g.node_count());
  const PartitionQuality q = measure_partition(g, part);
  state.counters["partition_ns_per_body"] = partition_ns * per_body;
  state.counters["refine_ns_per_body"] = refine_ns * per_body;
  state.counters["parts"] = q.parts;
  state.counters["cut"] = q.edge_cut;
  state.counters["interface_rows"] = q.interface_rows;
  state.counters["cut_vs_metis"] = reference > 0 ? static_cast<double>(q.edge_cut) / reference : 1.0;
}

void register_workload(const std::string& name, const std::function<ConstraintGraph()>& make) {
  for (int nmax : {8, 32})
    for (PartitionerKind kind : {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                                 PartitionerKind::Mr, PartitionerKind::Mix, PartitionerKind::Metis})
      for (RefinerKind refiner : {RefinerKind::None, RefinerKind::Kl, RefinerKind::Fm, RefinerKind::FmRollback}) {
        PartitionParams p;
        p.partitioner = kind;
        p.refiner = refiner;
        p.nmax = nmax;
        const std::string label = std::string("partition/") + partitioner_name(kind) + "+" + refiner_name(refiner) +
                                  "/" + name + "/nmax:" + std::to_string(nmax);
        benchmark::RegisterBenchmark(label.c_str(), [p, name, make](benchmark::State& s) {
          run(s, p, name, workload(name, make));
        })->Unit(benchmark::kMillisecond);
      }
}

void register_all() {
  for (int bodies : {1000, 10000, 100000})
    register_workload("pile:" + std::to_string(bodies), [bodies] {
      return with_masses(pile_graph(bodies, 42), random_masses(bodies, 43));
    });
  for (const char* scene : {"chain_drop", "log_tower", "rock_pile", "large_rock_pile"})
    register_workload(scene, [scene] { return settled_scene_graph(scene); });
}

}  // namespace
}  // namespace rbpart

int main(int argc, char** argv) {
  rbpart::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
