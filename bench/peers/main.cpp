// rbpart_peers: runs one scene file with one peer engine, printing the per-step columns of
// `rbpart simulate --stats` that the peers share (docs/formats.md), one line per step, flushed, so
// that run_peers.py can stop a run whose step exceeds its budget.
//
//   rbpart_peers engines
//   rbpart_peers run --engine ode|bullet|mujoco --solver S --scene FILE [--steps N] [--no-residual]
//                    [--state FILE] [--settings FILE] [--mujoco-memory-gib G]
//   rbpart_peers measure --scene FILE --state FILE       (end measures as one JSON line)
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

#include "peers.hpp"

namespace {

using namespace peers;

struct Available {
  const char* engine;
  const char* solvers[2];
};

constexpr Available kBuilt[] = {
#ifdef PEERS_HAVE_ODE
    {"ode", {"dantzig", "quickstep"}},
#endif
    {"bullet", {"si", "mlcp"}},
#ifdef PEERS_HAVE_MUJOCO
    {"mujoco", {"newton", "pgs"}},
#endif
};

std::map<std::string, std::string> options(int argc, char** argv) {
  std::map<std::string, std::string> o;
  for (int i = 2; i < argc; ++i) {
    const std::string key = argv[i];
    if (key.rfind("--", 0) != 0) throw std::runtime_error("unexpected argument '" + key + "'");
    if (key == "--no-residual") o[key] = "1";
    else if (i + 1 < argc) o[key] = argv[++i];
    else throw std::runtime_error(key + " needs a value");
  }
  return o;
}

std::string need(const std::map<std::string, std::string>& o, const std::string& key) {
  const auto it = o.find(key);
  if (it == o.end()) throw std::runtime_error(key + " is required");
  return it->second;
}

std::unique_ptr<Engine> make(const std::string& engine, const Scene& scene, const std::string& solver, bool residual,
                             double memory_gib) {
#ifdef PEERS_HAVE_ODE
  if (engine == "ode") return make_ode(scene, solver, residual);
#endif
  if (engine == "bullet") return make_bullet(scene, solver, residual);
#ifdef PEERS_HAVE_MUJOCO
  if (engine == "mujoco") return make_mujoco(scene, solver, residual, memory_gib);
#endif
  (void)memory_gib;
  throw std::runtime_error("engine '" + engine + "' is not built here (rbpart_peers engines lists them)");
}

int run(const std::map<std::string, std::string>& o) {
  const Scene scene = load_scene(need(o, "--scene"));
  const int steps = o.count("--steps") ? std::stoi(o.at("--steps")) : scene.steps;
  const double memory_gib = o.count("--mujoco-memory-gib") ? std::stod(o.at("--mujoco-memory-gib")) : 1.9;
  auto engine = make(need(o, "--engine"), scene, need(o, "--solver"), !o.count("--no-residual"), memory_gib);
  if (o.count("--settings")) std::ofstream(o.at("--settings")) << engine->settings_json() << "\n";
  std::printf("step,contacts,total_ms,solve_ms,blcp_residual,max_penetration\n");
  std::fflush(stdout);
  for (int k = 1; k <= steps; ++k) {
    const StepReport r = engine->step();
    std::printf("%d,%d,%.6g,%.6g,%.6g,%.17g\n", k, r.contacts, r.total_ms, r.solve_ms, r.blcp_residual, r.max_penetration);
    std::fflush(stdout);
  }
  if (o.count("--state")) write_state(o.at("--state"), scene, engine->state(), steps * scene.dt);
  // Settings again: some are counted during the run (MLCP fallbacks, points per pair).
  if (o.count("--settings")) std::ofstream(o.at("--settings")) << engine->settings_json() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "engines") {
      for (const auto& a : kBuilt) std::printf("%s %s %s\n", a.engine, a.solvers[0], a.solvers[1]);
      return 0;
    }
    if (command == "run") return run(options(argc, argv));
    if (command == "measure") {
      const auto o = options(argc, argv);
      const Scene scene = load_scene(need(o, "--scene"));
      const EndMeasures m = measure_state(scene, read_state(need(o, "--state"), scene));
      std::printf("{\"kinetic_energy\": %.17g, \"max_point_speed\": %.17g, \"penetration\": %.17g}\n", m.kinetic_energy,
                  m.max_point_speed, m.penetration);
      return 0;
    }
    std::fprintf(stderr, "usage: rbpart_peers engines | run ... | measure ... (see bench/peers/README.md)\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rbpart_peers: %s\n", e.what());
    return 1;
  }
}
