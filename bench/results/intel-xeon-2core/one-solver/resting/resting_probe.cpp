// The Rock Pile's resting failure (README.md): from a state written by `rbpart simulate --scene rock_pile
// --threads 1 --steps 300 --state rock300.json`, steps the pile and records each step's solve input;
// for the last two steps, the main island's interior-point phase alone from its cold start (residual
// of its projected iterate every 10th step and at the end, with the rows of largest residual), and
// the solver with budgets of 1 to 160 factorisations. Usage: resting_probe rock300.json 6
#include "step/world_internals.hpp"
#include "scenes/scenes.hpp"
#include "io/scene_json.hpp"
#include "solve/island_cache.hpp"
#include "solve/newton_island.hpp"
#include "solve/residual.hpp"
#include <cstdio>
#include <cstdlib>
#include "solve/interior_point.hpp"
#include "solve/newton.hpp"
#include <algorithm>
using namespace rbpart;
struct P { Rows rows; Bodies bodies; Islands islands; };
int main(int argc, char** argv) {
  SceneDef scene = make_builtin_scene("rock_pile");
  World world(scene);
  SceneState st = load_state_file(argv[1], world.scene());
  world.restart(st.time, st.bodies);
  int upto = atoi(argv[2]);
  std::vector<P> probs;
  set_problem_observer(world, [&](const Rows& r, const Bodies& b, const Islands& is, const ConstraintGraph&) { probs.push_back({r, b, is}); });
  for (int k = 0; k < upto; ++k) { const StepStats& s = world.step(); printf("step %d unsettled %d fact %d res %.2e\n", k, s.solve.unsettled, s.solve.factorizations, s.solve.residual); }
  // the big island of the last problems: budgets 1..N
  for (int pi = (int)probs.size() - 2; pi < (int)probs.size(); ++pi) {
    P& p = probs[pi];
    std::vector<int> order = largest_islands_first(p.islands);
    int big = order[0];
    std::vector<int> local = local_row_index(p.rows, p.islands);
    printf("problem %d: island rows %d\n", pi, p.islands.row_offset[big+1]-p.islands.row_offset[big]);
    {
      IslandSystem s; s.gather(p.rows, p.bodies, p.islands, big, local);
      MonolithicSystem sys; sys.assign(s, 8);
      InteriorPoint ipm; IslandChunks ch; ipm.start(s);
      double scale = 0; for (int j = 0; j < s.rows; ++j) scale = std::max(scale, std::abs(s.q[j]));
      for (int it = 0; it < 60; ++it) {
        double len = ipm.step(sys, ch);
        Eigen::VectorXd l = ipm.lambda(), du, w, fw;
        // project
        for (int j = 0; j < s.rows; ++j) if (s.normal_of[j] < 0) l[j] = std::clamp(l[j], s.lo[j], s.hi[j]);
        for (int j = 0; j < s.rows; ++j) if (s.normal_of[j] >= 0) { double b = s.mu[j]*std::max(0.0, l[s.normal_of[j]]); l[j] = std::clamp(l[j], -b, b); }
        apply_a(s, l, du, w); w += s.q; scaled_natural_map(s, l, w, fw);
        if (it % 10 == 0) printf("   ipm %2d len %.2e res %.3e\n", it, len, fw.cwiseAbs().maxCoeff()/scale);
        if (len == 0 || it == 59) {
          std::vector<int> idx(s.rows); for (int j = 0; j < s.rows; ++j) idx[j] = j;
          std::sort(idx.begin(), idx.end(), [&](int a, int b) { return std::abs(fw[a]) > std::abs(fw[b]); });
          for (int t = 0; t < 8; ++t) { int j = idx[t]; int n = s.normal_of[j];
            printf("     row %d %s fw/scale %.2e lambda %.4e w %.3e diag %.3e normal %d lam_n %.4e mu %.2f bodies %d %d\n", j, n < 0 ? "N/J" : "fric", fw[j]/scale, l[j], w[j], s.diag[j], n, n >= 0 ? l[n] : 0.0, s.mu[j], s.body[j][0], s.body[j][1]); }
          break; }
      }
    }
    for (int budget : {1, 10, 20, 30, 40, 80, 160}) {
      IslandSystem s; s.gather(p.rows, p.bodies, p.islands, big, local);
      MonolithicSystem sys; sys.assign(s, 8);
      NewtonWorkspace ws; Rows rows = p.rows;
      NewtonResult r = solve_island_newton(s, sys, budget, rows, ws);
      printf("  budget %3d: fact %3d res %.3e settled %d\n", budget, r.factorizations, r.residual, r.settled);
    }
  }
}
