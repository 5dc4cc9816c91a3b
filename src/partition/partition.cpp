// partition_graph: islands first (docs/design.md#graph), then the chosen partitioner on each island of more
// than nmax bodies; and the partitioners' and refiners' names. Adding a partitioner = one file with
// its island entry point (partition/grow.hpp) + one line in kPartitioners.
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "core/validate.hpp"
#include "partition/grow.hpp"

namespace rbpart {

namespace {

using IslandPartitioner = void (*)(GrowState&, const PartitionParams&, const int*, int);

struct PartitionerEntry {
  PartitionerKind kind;
  const char* name;
  IslandPartitioner run;
};

constexpr PartitionerEntry kPartitioners[] = {
    {PartitionerKind::None, "none", nullptr},
    {PartitionerKind::Bfs, "bfs", partition_island_bfs},
    {PartitionerKind::MinDp, "mindp", partition_island_min_dp},
    {PartitionerKind::MaxDp, "maxdp", partition_island_max_dp},
    {PartitionerKind::Mr, "mr", partition_island_mr},
    {PartitionerKind::Mix, "mix", partition_island_mix},
    {PartitionerKind::Metis, "metis", partition_island_metis},
};

struct RefinerEntry {
  RefinerKind kind;
  const char* name;
};

constexpr RefinerEntry kRefiners[] = {
    {RefinerKind::None, "none"}, {RefinerKind::Kl, "kl"}, {RefinerKind::Fm, "fm"}, {RefinerKind::FmRollback, "fm-rollback"}};

template <class Table>
const auto& entry_of(const Table& table, decltype(table[0].kind) kind) {
  for (const auto& e : table)
    if (e.kind == kind) return e;
  throw std::invalid_argument("unlisted partitioner or refiner kind");
}

template <class Table>
auto parse_name(const Table& table, const std::string& name, const char* what) {
  std::string choices;
  for (const auto& e : table) {
    if (name == e.name) return e.kind;
    choices += choices.empty() ? "" : ", ";
    choices += e.name;
  }
  throw InputError("unknown " + std::string(what) + " '" + name + "' (choose one of " + choices + ")");
}

}  // namespace

bool same_partition_input(const ConstraintGraph& a, const ConstraintGraph& b) {
  return a.body_of == b.body_of && a.mass == b.mass && a.offset == b.offset && a.adjacency == b.adjacency &&
         a.weight == b.weight;
}

void partition_graph(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition) {
  const IslandPartitioner run = entry_of(kPartitioners, params.partitioner).run;
  if (run == nullptr) throw std::invalid_argument("partition_graph: no partitioner chosen");
  if (params.nmax < 1) throw std::invalid_argument("partition_graph: nmax must be at least 1");

  const int n = graph.node_count();
  partition.part_of.assign(n, -1);
  thread_local GrowState s;  // scratch kept across calls (no allocation once warmed up)
  thread_local std::vector<int> island_of, island_offset, island_nodes, queue;
  s.reset(graph, params.nmax, partition.part_of);
  // Islands by breadth-first search, numbered in order of their lowest node ...
  island_of.assign(n, -1);
  island_offset.assign(1, 0);
  for (int root = 0; root < n; ++root) {
    if (island_of[root] >= 0) continue;
    const int id = static_cast<int>(island_offset.size()) - 1;
    queue.assign(1, root);
    island_of[root] = id;
    for (std::size_t head = 0; head < queue.size(); ++head)
      for (int k = graph.offset[queue[head]]; k < graph.offset[queue[head] + 1]; ++k)
        if (island_of[graph.adjacency[k]] < 0) {
          island_of[graph.adjacency[k]] = id;
          queue.push_back(graph.adjacency[k]);
        }
    island_offset.push_back(island_offset.back() + static_cast<int>(queue.size()));
  }
  // ... and listed per island in increasing node order (a counting sort).
  island_nodes.resize(n);
  queue.assign(island_offset.begin(), island_offset.end() - 1);
  for (int v = 0; v < n; ++v) island_nodes[queue[island_of[v]]++] = v;

  for (std::size_t i = 0; i + 1 < island_offset.size(); ++i) {
    const int* nodes = island_nodes.data() + island_offset[i];
    const int count = island_offset[i + 1] - island_offset[i];
    // One sub-system without interface, whatever the partitioner (docs/design.md#graph).
    if (count <= params.nmax) {
      for (int k = 0; k < count; ++k) partition.part_of[nodes[k]] = s.part_count;
      ++s.part_count;
    } else {
      run(s, params, nodes, count);
    }
  }
  partition.part_count = s.part_count;
  RBPART_CHECK(check_partition(graph, partition, params.nmax));
}

PartitionQuality partition_and_refine(const ConstraintGraph& graph, const PartitionParams& params,
                                      Partition& partition) {
  const Timer partition_timer;
  partition_graph(graph, params, partition);
  const double partition_ms = partition_timer.ms();
  const Timer refine_timer;
  refine_partition(graph, params, partition);
  const double refine_ms = refine_timer.ms();
  if (params.debug_checks) {
    const std::string violation = check_partition(graph, partition, params.nmax);
    if (!violation.empty()) throw std::logic_error("partition breaks its properties: " + violation);
  }
  PartitionQuality q = measure_partition(graph, partition);
  q.partition_ms = partition_ms;
  q.refine_ms = refine_ms;
  return q;
}

const char* partitioner_name(PartitionerKind kind) { return entry_of(kPartitioners, kind).name; }
const char* refiner_name(RefinerKind kind) { return entry_of(kRefiners, kind).name; }
PartitionerKind parse_partitioner(const std::string& name) { return parse_name(kPartitioners, name, "partitioner"); }
RefinerKind parse_refiner(const std::string& name) { return parse_name(kRefiners, name, "refiner"); }

}  // namespace rbpart
