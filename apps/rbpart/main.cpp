// rbpart: rigid bodies with contact, solved by exact direct (and partitioned) methods.
// Exit status: 0 success, 2 bad input (one line naming the problem), 1 internal failure.
#include <cstdio>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/memory.hpp"

int main(int argc, char** argv) {
  // Before any output is opened: a signal must find every temporary file registered.
  rbpart::install_interrupt_handlers();
  // The study's replays solve without a World.
  rbpart::keep_freed_memory();
  CLI::App app{"rbpart: stiff rigid-body simulation with exact direct and partitioned BLCP solvers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "rbpart 0.1");
  const std::vector<std::pair<std::string, rbpart::cli::Run>> runs = {
      {"simulate", rbpart::cli::add_simulate(app)},
      {"scenes", rbpart::cli::add_scenes(app)},
      {"partition", rbpart::cli::add_partition(app)},
      {"view", rbpart::cli::add_view(app)},
      {"snapshot", rbpart::cli::add_snapshot(app)},
      {"bench", rbpart::cli::add_bench(app)},
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "rbpart: error: %s\n", e.what());
    return 2;
  }
  try {
    for (const auto& [name, run] : runs)
      if (app.got_subcommand(name)) return run();
    return 2;
  } catch (const rbpart::InputError& e) {
    std::fprintf(stderr, "rbpart: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rbpart: internal error: %s\n", e.what());
    return 1;
  }
}
