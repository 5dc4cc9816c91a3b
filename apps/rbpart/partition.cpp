// rbpart partition: partition a graph in METIS format (docs/design.md#contracts) with one of rbpart's
// partitioners and refiners; part ids one per line (the METIS .part layout), and a one-line JSON
// quality report.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/metis_graph.hpp"
#include "io/text_format.hpp"
#include "partition/partition.hpp"

namespace rbpart::cli {

void add_partition_options(CLI::App* cmd, PartitionOptions& o, bool partitioner_required) {
  auto* partitioner = cmd->add_option("--partitioner", o.partitioner,
                                      "bfs, mindp, maxdp, mr, mix or metis" +
                                          std::string(partitioner_required ? "" : " (none: no partition)"));
  if (partitioner_required) partitioner->required();
  else partitioner->capture_default_str();
  cmd->add_option("--refine", o.refiner, "Refiner: none, kl, fm or fm-rollback")->capture_default_str();
  cmd->add_option("--nmax", o.params.nmax, "Most bodies in one sub-system")->capture_default_str();
  cmd->add_option("--tau-mr", o.params.tau_mr,
                  "MR: a body joins only if its mass ratio to the part's lightest body is below this (> 1)")
      ->capture_default_str();
  cmd->add_option("--tau-mix", o.params.tau_mix, "MIX: MinDP growth up to tau_mix * nmax bodies, in (0, 1)")
      ->capture_default_str();
  cmd->add_flag("--debug-checks", o.params.debug_checks,
                "Recompute refinement gains from scratch and check every partition's properties");
}

PartitionParams partition_params(const PartitionOptions& o) {
  PartitionParams p = o.params;
  p.partitioner = parse_partitioner(o.partitioner);
  p.refiner = parse_refiner(o.refiner);
  if (p.nmax < 1) throw InputError("--nmax must be at least 1, not " + std::to_string(p.nmax));
  if (!(p.tau_mr > 1)) throw InputError("--tau-mr must be greater than 1, not " + round_trip(p.tau_mr));
  if (!(p.tau_mix > 0 && p.tau_mix < 1))
    throw InputError("--tau-mix must lie in (0, 1), not " + round_trip(p.tau_mix));
  return p;
}

namespace {

struct Options {
  std::string graph, masses, out, report;
  int parts = 0;  // --parts K: 0 when not given
  PartitionOptions partition;
};

int run_partition(const Options& o) {
  PartitionParams params = partition_params(o.partition);
  if (params.partitioner == PartitionerKind::None)
    throw InputError("--partitioner none makes no partition (choose bfs, mindp, maxdp, mr, mix or metis)");
  MetisGraph input = read_metis_graph(o.graph);
  ConstraintGraph& graph = input.graph;
  if (o.parts > 0) params.nmax = nmax_for_parts(graph.node_count(), o.parts);
  if (!o.masses.empty()) graph.mass = read_masses(o.masses, graph.node_count());
  // Outputs are opened first so that a bad path fails before the work; each appears whole or not at all.
  std::optional<AtomicFile> out, report;
  if (!o.out.empty()) out.emplace(o.out);
  if (!o.report.empty()) report.emplace(o.report);

  Partition partition;
  const PartitionQuality q = partition_and_refine(graph, params, partition);
  nlohmann::ordered_json json = {
      {"partitioner", partitioner_name(params.partitioner)},
      {"refiner", refiner_name(params.refiner)},
      {"nmax", params.nmax},
      {"tau_mr", params.tau_mr},
      {"tau_mix", params.tau_mix},
      {"nodes", graph.node_count()},
      {"edges", graph.edge_count()},
      {"parts", q.parts},
      {"min_bodies", q.min_bodies},
      {"max_bodies", q.max_bodies},
      {"mean_bodies", q.mean_bodies},
      {"edge_cut", q.edge_cut},
      {"interface_rows", q.interface_rows},
      {"interface_bodies", q.interface_bodies},
      {"partition_ms", q.partition_ms},
      {"refine_ms", q.refine_ms}};
  if (o.parts > 0) json["requested_parts"] = o.parts;
  const std::string parts = part_file_text(partition), line = json.dump() + "\n";
  if (out) {
    out->write(parts);
    out->commit();
  } else {
    std::fwrite(parts.data(), 1, parts.size(), stdout);
  }
  if (report) {
    report->write(line);
    report->commit();
  } else {
    std::fputs(line.c_str(), stderr);
  }
  return 0;
}

}  // namespace

Run add_partition(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("partition", "Partition a graph in METIS format and report the partition's quality");
  auto o = std::make_shared<Options>();
  cmd->add_option("--graph", o->graph, "Graph in METIS format (fmt 0, 1, 10 or 11)")->required();
  cmd->add_option("--masses", o->masses, "Vertex masses, one per line (default 1)");
  add_partition_options(cmd, o->partition, true);
  cmd->add_option("--parts", o->parts,
                  "Parts wanted, as METIS counts them: sets --nmax to ceil(nodes / K), the cap of K balanced parts")
      ->check(at_least(1))
      ->excludes(cmd->get_option("--nmax"));
  cmd->add_option("--out", o->out, "Part ids, one per vertex per line (default: stdout)");
  cmd->add_option("--report", o->report, "One-line JSON quality report (default: stderr)");
  return [o]() { return run_partition(*o); };
}

}  // namespace rbpart::cli
