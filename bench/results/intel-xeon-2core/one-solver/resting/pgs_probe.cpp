// The Rock Pile's resting failure: PGS from the warm start of a step after a settled one, with
// 20 to 1000 sweeps, then the Newton solver (the direct solver, default budget) from the PGS answer.
#include "step/world_internals.hpp"
#include "scenes/scenes.hpp"
#include "io/scene_json.hpp"
#include "solve/solve.hpp"
#include "solve/newton.hpp"
#include "solve/island_system.hpp"
#include <cstdio>
#include <cstdlib>
using namespace rbpart;
int main(int argc, char** argv) {
  SceneDef scene = make_builtin_scene("rock_pile");
  World world(scene);
  SceneState st = load_state_file(argv[1], world.scene());
  world.restart(st.time, st.bodies);
  Rows rows; Bodies bodies; Islands islands;
  int upto = atoi(argv[2]);
  set_problem_observer(world, [&](const Rows& r, const Bodies& b, const Islands& is, const ConstraintGraph&) { rows = r; bodies = b; islands = is; });
  for (int k = 0; k < upto; ++k) world.step();
  printf("warm start residual %.3e\n", natural_map_residual(rows, bodies, islands));
  for (int sweeps : {20, 100, 1000}) {
    Rows r = rows; SolverParams p; p.kind = SolverKind::Pgs; p.pgs_iterations = sweeps; p.pgs_tolerance = 0;
    SolveStats s = solve_pgs(r, bodies, islands, p);
    int changed = 0, n = 0;
    for (std::size_t j = 0; j < r.size(); ++j) { if (r.state[j] != rows.state[j]) ++changed; ++n; }
    printf("pgs %6d sweeps: residual %.3e, rows whose stored state differs from the warm start's %d of %d\n", sweeps, s.residual, changed, n);
    SolverParams np; Rows r2 = r;
    SolveStats ns = solve_newton_direct(r2, bodies, islands, np);
    printf("  then the Newton solver from the PGS answer: residual %.3e, factorisations %d, unsettled %d\n", ns.residual, ns.factorizations, ns.unsettled);
  }
}
