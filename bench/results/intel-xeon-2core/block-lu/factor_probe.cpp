// The block LU (src/solve/block_lu.hpp) against KLU and CHOLMOD on the body-space matrices of real
// islands: a scene is stepped to step K, the largest islands of that step are taken, and for each
// (a) the interior point's fifth system (every row Free with its barrier shift, friction coupled to
// its normal: not symmetric) and (b) the symmetric system of every row Free (a sticking resting
// island's) are factored 20 times by each method; medians in ms. KLU as the solver used it before:
// AMD with block triangular form, no row scaling, refactorisation with the first LU's pivots.
// CHOLMOD: supernodal, AMD, as before. UMFPACK (multifrontal LU), its numeric factorisation. Build: see README.md. Usage: factor_probe SCENE K
#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Dense>
#include <Eigen/LU>
#define private public  // the probe reads PatternFactor's block pattern
#include "solve/pattern_factor.hpp"
#include "solve/body_space.hpp"
#include "solve/monolithic.hpp"
#undef private
#include "core/timer.hpp"
#include "scenes/scenes.hpp"
#include "solve/block_lu.hpp"
#include "solve/interior_point.hpp"
#include "solve/island_cache.hpp"
#include "solve/newton.hpp"
#include "step/world_internals.hpp"
#include <cholmod.h>
#include <klu.h>
#include <umfpack.h>
#include <cstdio>
#include <cstdlib>
using namespace rbpart;

struct Csc {
  int n = 0;
  std::vector<int> colptr{0}, rowind;
  std::vector<double> values;
};

// The block matrix in compressed columns, both triangles.
Csc to_csc(const PatternFactor& f) {
  Csc a;
  a.n = f.size();
  const int nb = a.n / 6;
  for (int c = 0; c < nb; ++c)
    for (int k = 0; k < 6; ++k) {
      for (int e = f.adjacent_start_[c]; e < f.adjacent_start_[c + 1]; ++e)
        for (int i = 0; i < 6; ++i) {
          a.rowind.push_back(6 * f.adjacent_[e] + i);
          a.values.push_back(f.values_[36 * e + 6 * k + i]);
        }
      a.colptr.push_back(static_cast<int>(a.rowind.size()));
    }
  return a;
}

template <class Fn>
double median_ms(Fn&& fn) {
  std::vector<double> t;
  for (int r = 0; r < 20; ++r) {
    const Timer timer;
    fn();
    t.push_back(timer.ms());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

void compare(const PatternFactor& f, bool symmetric) {
  const Csc a = to_csc(f);
  BlockLU block;
  const Timer ta;
  block.analyze(a.n / 6, f.adjacent_start_, f.adjacent_, -1);
  const double block_analyse = ta.ms();
  bool ok = true;
  const double block_ms = median_ms([&] { ok = block.factor(f.values_.data()) && ok; });
  std::vector<double> b(a.n, 1.0);
  const double block_solve = median_ms([&] { block.solve(b.data()); });

  klu_common kc;
  klu_defaults(&kc);
  kc.scale = -1;
  int* p = const_cast<int*>(a.colptr.data());
  int* i = const_cast<int*>(a.rowind.data());
  double* x = const_cast<double*>(a.values.data());
  const Timer tk;
  klu_symbolic* ks = klu_analyze(a.n, p, i, &kc);
  const double klu_analyse = tk.ms();
  klu_numeric* kn = klu_factor(p, i, x, ks, &kc);
  const double klu_refactor_ms = median_ms([&] { klu_refactor(p, i, x, ks, kn, &kc); });
  const double klu_factor_ms = median_ms([&] {
    klu_free_numeric(&kn, &kc);
    kn = klu_factor(p, i, x, ks, &kc);
  });
  const double klu_solve_ms = median_ms([&] { klu_solve(ks, kn, a.n, 1, b.data(), &kc); });
  klu_free_numeric(&kn, &kc);
  klu_free_symbolic(&ks, &kc);

  // UMFPACK: its symbolic analysis once, numeric factorisations (no row scaling, as KLU).
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_di_defaults(control);
  control[UMFPACK_SCALE] = UMFPACK_SCALE_NONE;
  void *symbolic = nullptr, *numeric = nullptr;
  umfpack_di_symbolic(a.n, a.n, p, i, x, &symbolic, control, info);
  const double umf_ms = median_ms([&] {
    umfpack_di_free_numeric(&numeric);
    umfpack_di_numeric(p, i, x, symbolic, &numeric, control, info);
  });
  umfpack_di_free_numeric(&numeric);
  umfpack_di_free_symbolic(&symbolic);

  double chol_ms = -1;
  if (symmetric) {
    cholmod_common c;
    cholmod_start(&c);
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    cholmod_sparse m{};
    m.nrow = m.ncol = a.n;
    m.nzmax = a.rowind.size();
    m.p = p;
    m.i = i;
    m.x = x;
    m.stype = -1;
    m.itype = CHOLMOD_INT;
    m.xtype = CHOLMOD_REAL;
    m.dtype = CHOLMOD_DOUBLE;
    m.sorted = m.packed = 1;
    cholmod_factor* l = cholmod_analyze(&m, &c);
    chol_ms = median_ms([&] { cholmod_factorize(&m, l, &c); });
    if (c.status != CHOLMOD_OK) chol_ms = -2;
    cholmod_free_factor(&l, &c);
    cholmod_finish(&c);
  }
  std::printf("  %-13s n %5d | block LU: analyse %.2f factor %.3f solve %.3f%s | KLU: analyse %.2f refactor %.3f factor %.3f "
              "solve %.3f | UMFPACK: factor %.3f",
              symmetric ? "symmetric" : "not symmetric", a.n, block_analyse, block_ms, block_solve, ok ? "" : " (failed)",
              klu_analyse, klu_refactor_ms, klu_factor_ms, klu_solve_ms, umf_ms);
  if (symmetric) std::printf(" | CHOLMOD: factor %.3f", chol_ms);
  std::printf("\n");
}

struct Problem {
  Rows rows;
  Bodies bodies;
  Islands islands;
};

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  World world(make_builtin_scene(argv[1]));
  std::vector<Problem> problems;
  set_problem_observer(world, [&](const Rows& r, const Bodies& b, const Islands& is, const ConstraintGraph&) {
    problems.push_back({r, b, is});
  });
  const int steps = std::atoi(argv[2]);
  for (int k = 0; k < steps; ++k) world.step();
  Problem& p = problems.back();
  const std::vector<int> order = largest_islands_first(p.islands);
  const std::vector<int> local = local_row_index(p.rows, p.islands);
  std::printf("%s, step %d\n", argv[1], steps);
  for (int k = 0; k < std::min<int>(2, order.size()); ++k) {
    IslandSystem s;
    s.gather(p.rows, p.bodies, p.islands, order[k], local);
    if (s.bodies <= 8) continue;
    std::printf(" island of %d rows on %d bodies\n", s.rows, s.bodies);
    MonolithicSystem system;
    system.assign(s);
    InteriorPoint ipm;
    IslandChunks chunks;
    ipm.start(s);
    for (int it = 0; it < 5; ++it) ipm.step(system, chunks);
    compare(system.n_.n_, false);
    Piece piece;
    piece.equation.assign(s.rows, RowEquation::Free);
    piece.tie.setZero(s.rows);
    piece.shift.setZero(s.rows);
    system.factor(piece);
    compare(system.n_.n_, true);
  }
}
