// The fixed-bounds BLCP core and its backends (DESIGN.md §3), against the BLCP conditions, against
// each other, and against an exhaustive enumeration of index sets.
#include "solve/blcp.hpp"
#include "solve/dense_matrix.hpp"
#include "solve/residual.hpp"
#include "solve/sparse_matrix.hpp"

#include "solve/random_blcp.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <limits>
#include <thread>

namespace rbpart {
namespace {

using testing::DenseBlcp;
using testing::kInf;
using testing::RandomIsland;

struct Solution {
  Eigen::VectorXd lambda;
  std::vector<RowState> state;
  BlcpResult result;
};

std::vector<RowState> random_states(std::mt19937& rng, int n) {
  std::vector<RowState> state(n);
  for (auto& s : state) s = static_cast<RowState>(std::uniform_int_distribution<int>(0, 2)(rng));
  return state;
}

Solution run(BlcpMatrix& a, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
             std::vector<RowState> state, const BlcpSettings& settings = {}) {
  Solution s;
  s.lambda = Eigen::VectorXd::Zero(q.size());
  s.state = std::move(state);
  BlcpWorkspace ws;
  s.result = solve_blcp(a, q, lo, hi, s.lambda, s.state, settings, ws);
  return s;
}

// The residual cannot be computed finer than the round-off of w = A lambda + q: eps times a row's
// terms, each up to max_j A_jj |lambda_j| (large when redundant rows fight over an inconsistent q,
// lambda ~ q / sigma). The bound on the scaled residual is 1e-10 or that floor, whichever is larger.
double residual_bound(const Eigen::VectorXd& diag, const Eigen::VectorXd& q, const Eigen::VectorXd& lambda) {
  const double scale = std::max(q.cwiseAbs().maxCoeff(), 1e-12);
  const double terms = lambda.cwiseAbs().cwiseProduct(diag).maxCoeff();
  return std::max(1e-10, 256 * std::numeric_limits<double>::epsilon() * terms / scale);
}

double relative_difference(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  return (x - y).cwiseAbs().maxCoeff() / std::max(1.0, y.cwiseAbs().maxCoeff());
}

// The sets must match lambda: clamped rows sit on their (finite) bound, fixed rows are clamped.
void expect_consistent_sets(const Solution& s, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  for (Eigen::Index j = 0; j < lo.size(); ++j) {
    if (lo[j] == hi[j]) EXPECT_NE(s.state[j], RowState::Free);
    if (s.state[j] == RowState::Lower) EXPECT_EQ(s.lambda[j], lo[j]);
    if (s.state[j] == RowState::Upper) EXPECT_EQ(s.lambda[j], hi[j]);
    EXPECT_TRUE(std::isfinite(s.lambda[j]));
  }
}

TEST(Blcp, RandomDenseProblemsDenseAndCholmodAgree) {
  std::mt19937 rng(12345);
  int problems = 0;
  for (int n = 1; n <= 60; ++n)
    for (int k = 0; k < 40; ++k, ++problems) {
      const DenseBlcp p = testing::random_dense_blcp(rng, n);
      const std::vector<RowState> warm = random_states(rng, n);
      DenseBlcpMatrix dense;
      dense.assign(p.a);
      SparseBlcpMatrix sparse;
      sparse.assign(LowerCsc::from_dense(p.a));
      const Solution d = run(dense, p.q, p.lo, p.hi, warm);
      const Solution s = run(sparse, p.q, p.lo, p.hi, warm);
      ASSERT_TRUE(d.result.converged) << "n=" << n << " k=" << k;
      ASSERT_TRUE(s.result.converged) << "n=" << n << " k=" << k;
      EXPECT_LE(natural_map_residual(p.a, p.q, p.lo, p.hi, d.lambda), 1e-10) << "n=" << n << " k=" << k;
      EXPECT_LE(natural_map_residual(p.a, p.q, p.lo, p.hi, s.lambda), 1e-10) << "n=" << n << " k=" << k;
      EXPECT_LE(relative_difference(s.lambda, d.lambda), 1e-9) << "n=" << n << " k=" << k;
      expect_consistent_sets(d, p.lo, p.hi);
      expect_consistent_sets(s, p.lo, p.hi);
    }
  EXPECT_EQ(problems, 2400);
}

// Contact-like islands (redundant, tiny sigma): the three backends give the same exact answer.
TEST(Blcp, RandomContactIslandsAllBackendsAgree) {
  std::mt19937 rng(777);
  RandomIsland island;
  int floored = 0, total = 0;
  for (int rows = 3; rows <= 60; rows += 3)
    for (int k = 0; k < 30; ++k) {
      testing::IslandOptions opt;
      opt.rows = rows;
      opt.bodies = 1 + static_cast<int>(rng() % std::max(1, rows / 6));
      testing::random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      DenseBlcpMatrix dense;
      build_dense(s, dense.matrix());
      dense.finalize();
      SparseBlcpMatrix sparse;
      LowerCsc lower;
      build_lower_csc(s, lower);
      sparse.assign(std::move(lower));
      BodySpaceBlcpMatrix body_space;
      body_space.assign(s);

      const std::vector<RowState> warm = random_states(rng, s.rows);
      const Solution d = run(dense, s.q, s.lo, s.hi, warm);
      const Solution c = run(sparse, s.q, s.lo, s.hi, warm);
      const Solution b = run(body_space, s.q, s.lo, s.hi, warm);
      const std::string where = "rows=" + std::to_string(s.rows) + " k=" + std::to_string(k);
      ASSERT_TRUE(d.result.converged && c.result.converged && b.result.converged) << where;
      const Eigen::MatrixXd& a = dense.matrix();
      const double bound = residual_bound(s.diag, s.q, d.lambda);
      floored += bound > 1e-10;
      EXPECT_LE(natural_map_residual(a, s.q, s.lo, s.hi, d.lambda), bound) << where;
      EXPECT_LE(natural_map_residual(a, s.q, s.lo, s.hi, c.lambda), bound) << where;
      EXPECT_LE(natural_map_residual(a, s.q, s.lo, s.hi, b.lambda), bound) << where;
      EXPECT_LE(relative_difference(c.lambda, d.lambda), 1e-9) << where;
      EXPECT_LE(relative_difference(b.lambda, d.lambda), 1e-9) << where;
      ++total;
    }
  // The round-off floor is the exception (a few problems with strongly fighting rows), not the rule.
  EXPECT_LE(floored, total / 10) << floored << " of " << total;
}

// The sparse matrices really are A: products and diagonals against the dense assembly.
TEST(Blcp, SparseAssemblyMatchesDense) {
  std::mt19937 rng(99);
  RandomIsland island;
  testing::IslandOptions opt;
  opt.rows = 90;
  testing::random_contact_island(rng, opt, island);
  const IslandSystem& s = island.system;
  DenseBlcpMatrix dense;
  build_dense(s, dense.matrix());
  dense.finalize();
  // Independent reference: A = J M^-1 J^T + Sigma from the explicit dense J and M^-1.
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(s.rows, 6 * s.bodies), minv = Eigen::MatrixXd::Zero(6 * s.bodies, 6 * s.bodies);
  for (int r = 0; r < s.rows; ++r)
    for (int slot = 0; slot < 2; ++slot)
      if (s.body[r][slot] >= 0) j.block<1, 6>(r, 6 * s.body[r][slot]) += s.jac[r][slot].transpose();
  for (int b = 0; b < s.bodies; ++b) {
    minv.block<3, 3>(6 * b, 6 * b) = s.inv_mass[b] * Mat3::Identity();
    minv.block<3, 3>(6 * b + 3, 6 * b + 3) = s.inv_inertia[b];
  }
  Eigen::MatrixXd reference = j * minv * j.transpose();
  reference.diagonal() += s.sigma;
  EXPECT_LE((dense.matrix() - reference).cwiseAbs().maxCoeff(), 1e-12 * reference.cwiseAbs().maxCoeff());

  SparseBlcpMatrix sparse;
  LowerCsc lower;
  build_lower_csc(s, lower);
  sparse.assign(std::move(lower));
  BodySpaceBlcpMatrix body_space;
  body_space.assign(s);
  const Eigen::VectorXd x = testing::uniform_matrix(rng, s.rows, 1);
  Eigen::VectorXd y1, y2;
  sparse.multiply(x, y1);
  body_space.multiply(x, y2);
  const Eigen::VectorXd y = reference * x;
  EXPECT_LE((y1 - y).cwiseAbs().maxCoeff(), 1e-12 * y.cwiseAbs().maxCoeff());
  EXPECT_LE((y2 - y).cwiseAbs().maxCoeff(), 1e-12 * y.cwiseAbs().maxCoeff());
  EXPECT_LE((sparse.diagonal() - reference.diagonal()).cwiseAbs().maxCoeff(), 1e-12 * reference.diagonal().maxCoeff());

  // Solves with A_FF for a random free set: A_FF x_F = b_F.
  std::vector<char> free(s.rows);
  for (auto& f : free) f = rng() % 3 != 0;
  for (BlcpMatrix* m : std::initializer_list<BlcpMatrix*>{&dense, &sparse, &body_space}) {
    ASSERT_EQ(m->prepare(free), 1);
    EXPECT_EQ(m->prepare(free), 0);  // same set: the factor is reused
    Eigen::VectorXd b = testing::uniform_matrix(rng, s.rows, 1), xs = b;
    m->solve(xs);
    for (int r = 0; r < s.rows; ++r)
      if (!free[r]) {
        EXPECT_EQ(xs[r], b[r]);  // untouched
        xs[r] = 0;
      }
    // Backward error |A_FF x_F - b_F| / (|A_FF| |x_F| + |b_F|): round-off for Cholesky of A_FF; the
    // body-space solve (refined by the BLCP core, not here) cancels digits, ~ eps / sigma_floor.
    Eigen::MatrixXd aff = reference;
    for (int r = 0; r < s.rows; ++r)
      if (!free[r]) {
        aff.row(r).setZero();
        aff.col(r).setZero();
      }
    const Eigen::VectorXd ax = aff * xs;
    double err = 0;
    for (int r = 0; r < s.rows; ++r)
      if (free[r]) err = std::max(err, std::abs(ax[r] - b[r]));
    const double size = (aff.cwiseAbs() * xs.cwiseAbs()).maxCoeff() + b.cwiseAbs().maxCoeff();
    EXPECT_LE(err / size, m == &body_space ? 1e-8 : 1e-14);
  }
}

// Islands are solved in parallel, each with its own CHOLMOD factor, and CHOLMOD calls BLAS: the
// calls must not share state. Two threads factor and solve the same small dense matrix (one
// supernode) many times, refactoring for another free set every 10 solves; every answer must be
// bit for bit the serial one. Without the lock of sparse_matrix.cpp, Debian's single-threaded
// OpenBLAS failed this in 18 of 18 runs (2 to 2212 wrong answers of 40000).
TEST(Blcp, ConcurrentCholmodSolvesAreTheSerialOnes) {
  std::mt19937 rng(2024);
  const int n = 120;
  const Eigen::MatrixXd b = testing::uniform_matrix(rng, n, n);
  Eigen::MatrixXd a = b * b.transpose() / n;
  a.diagonal().array() += 1.0;
  const LowerCsc lower = LowerCsc::from_dense(a);
  const Eigen::VectorXd rhs = testing::uniform_matrix(rng, n, 1);
  std::vector<std::vector<char>> sets(2, std::vector<char>(n, 1));
  sets[1][n / 2] = 0;
  auto solve_with = [&](SparseBlcpMatrix& m, const std::vector<char>& free) {
    EXPECT_GE(m.prepare(free), 0);
    Eigen::VectorXd x = rhs;
    m.solve(x);
    return x;
  };
  std::vector<Eigen::VectorXd> serial;
  {
    SparseBlcpMatrix m;
    m.assign(lower);
    for (const auto& free : sets) serial.push_back(solve_with(m, free));
  }
  const int rounds = 20000;
  std::vector<int> mismatches(2, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t)
    threads.emplace_back([&, t] {
      SparseBlcpMatrix m;
      m.assign(lower);
      for (int i = 0; i < rounds; ++i)
        mismatches[t] += solve_with(m, sets[(i / 10) % 2]) != serial[(i / 10) % 2];
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches[0] + mismatches[1], 0) << "of " << 2 * rounds << " concurrent solves";
}

// Friction bounds +-mu lambda_n through the outer loop: at a settled fixed point the residual with
// bounds from the final normal impulses is exact, and dense and body-space agree.
TEST(Blcp, FrictionCoupledOuterLoop) {
  std::mt19937 rng(4242);
  RandomIsland island;
  int settled = 0, total = 0, jumps[2] = {0, 0}, pivots[2] = {0, 0}, tied[2] = {0, 0};
  for (int rows = 3; rows <= 60; rows += 3)
    for (int k = 0; k < 15; ++k, ++total) {
      testing::IslandOptions opt;
      opt.rows = rows;
      opt.joint_fraction = 0.05;
      opt.box_fraction = 0;
      testing::random_contact_island(rng, opt, island);
      IslandSystem& s = island.system;
      DenseBlcpMatrix dense;
      build_dense(s, dense.matrix());
      dense.finalize();
      BodySpaceBlcpMatrix body_space;
      body_space.assign(s);
      Eigen::VectorXd lambda_d[2];
      bool ok[2];
      int index = 0;
      for (BlcpMatrix* m : std::initializer_list<BlcpMatrix*>{&dense, &body_space}) {
        Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.rows), previous, lo = s.lo, hi = s.hi;
        std::vector<RowState> state(s.rows, RowState::Free);
        BlcpWorkspace ws;
        CoupledWorkspace cw;
        const FrictionPassResult fp = friction_passes(
            s.coupling(), s.diag, lambda, state, lo, hi, 200, 1e-12, previous,
            [&] { return solve_blcp(*m, s.q, lo, hi, lambda, state, BlcpSettings{}, ws).converged; },
            [&]() -> const Eigen::VectorXd& { return ws.w; },
            [&] { return coupled_friction_step(*m, s.q, lo, hi, s.coupling(), lambda, state, BlcpSettings{}, cw); });
        ASSERT_TRUE(fp.solved);
        jumps[index] += cw.jumps;
        pivots[index] += cw.events;
        tied[index] += cw.tied_factorizations;
        ok[index] = fp.settled;
        if (fp.settled) {
          set_friction_bounds(s.coupling(), lambda, lo, hi);
          EXPECT_LE(natural_map_residual(dense.matrix(), s.q, lo, hi, lambda), residual_bound(s.diag, s.q, lambda))
              << rows << " " << k;
        }
        lambda_d[index++] = lambda;
      }
      if (ok[0] && ok[1]) {
        ++settled;
        EXPECT_LE(relative_difference(lambda_d[1], lambda_d[0]), 1e-9) << rows << " " << k;
      }
    }
  // The fixed-point iteration need not contract for every random coupling (strong lever arms,
  // mu up to 0.8), but does for most.
  EXPECT_GE(settled, total * 3 / 4) << settled << " of " << total;
  // Both ways of the coupled step ran on both backends: jumps, and paths where the jump's block
  // pivots failed; on the body-space backend both on factored tied systems (tied_factor.hpp).
  for (int m = 0; m < 2; ++m) {
    EXPECT_GT(jumps[m], 0) << m;
    EXPECT_GT(pivots[m], 0) << m;
  }
  EXPECT_EQ(tied[0], 0);
  EXPECT_GT(tied[1], 0);
}

// The tied system of the coupled step's jump (tied_factor.hpp), factored in body space, against
// the same equations assembled densely from A: (A x)_j = r_j on free rows, x_t - c_t x_n = r_t on
// sliding friction rows, x_j = r_j elsewhere. Like every body-space solve it is refined against A.
TEST(Blcp, TiedBodySpaceSolveIsTheDenseTiedSystem) {
  std::mt19937 rng(515);
  RandomIsland island;
  int tied_rows = 0;
  for (int rows = 30; rows <= 150; rows += 30)
    for (int k = 0; k < 4; ++k) {
      testing::IslandOptions opt;
      opt.rows = rows;
      testing::random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      DenseBlcpMatrix dense;
      build_dense(s, dense.matrix());
      const Eigen::MatrixXd& a = dense.matrix();
      std::vector<char> free(s.rows);
      for (int j = 0; j < s.rows; ++j) free[j] = s.normal_of[j] < 0 ? rng() % 4 != 0 : rng() % 2 != 0;
      std::vector<int> sliding;
      std::vector<double> coef;
      for (int j = 0; j < s.rows; ++j)
        if (s.normal_of[j] >= 0 && free[s.normal_of[j]] && !free[j] && rng() % 3 != 0) {
          sliding.push_back(j);
          coef.push_back((rng() % 2 ? 1.0 : -1.0) * s.mu[j]);
        }
      tied_rows += static_cast<int>(sliding.size());
      Eigen::MatrixXd e = Eigen::MatrixXd::Identity(s.rows, s.rows);
      for (int j = 0; j < s.rows; ++j)
        if (free[j]) e.row(j) = a.row(j);
      for (std::size_t i = 0; i < sliding.size(); ++i) e(sliding[i], s.normal_of[sliding[i]]) = -coef[i];
      const Eigen::VectorXd r = testing::uniform_matrix(rng, s.rows, 1);
      const Eigen::VectorXd expected = e.partialPivLu().solve(r);

      BodySpaceBlcpMatrix body_space;
      body_space.assign(s);
      ASSERT_TRUE(body_space.factor_tied(free, sliding, coef));
      Eigen::VectorXd x = r;
      body_space.solve_tied(x);
      for (int round = 0; round < 3; ++round) {
        Eigen::VectorXd correction = r - e * x;
        body_space.solve_tied(correction);
        x += correction;
      }
      // The dense LU is no finer than E's condition (~1/sigma floor) allows: compare answers to
      // 1e-8, residuals at the round-off of E x.
      const double terms = (e.cwiseAbs() * x.cwiseAbs()).maxCoeff();
      EXPECT_LE(relative_difference(x, expected), 1e-8) << rows << " " << k;
      EXPECT_LE((r - e * x).cwiseAbs().maxCoeff(), 64 * std::numeric_limits<double>::epsilon() * terms)
          << rows << " " << k;
    }
  EXPECT_GT(tied_rows, 100);
}

// A diagonal A: independent rows, for problems far larger than a dense test matrix.
class DiagonalMatrix final : public BlcpMatrix {
 public:
  explicit DiagonalMatrix(Eigen::VectorXd d) : d_(std::move(d)) {}
  int size() const override { return static_cast<int>(d_.size()); }
  const Eigen::VectorXd& diagonal() const override { return d_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override { y = d_.cwiseProduct(x); }
  void solve(Eigen::VectorXd& x) override {
    for (int j = 0; j < size(); ++j)
      if (free_[j]) x[j] /= d_[j];
  }

 protected:
  bool factor(const std::vector<char>& free) override {
    free_ = free;
    return true;
  }

 private:
  Eigen::VectorXd d_;
  std::vector<char> free_;
};

// `contacts` independent contacts, each a normal row (A = 1, q = -1: lambda_n = 1) and a friction
// row (A = 1, q = -pull, mu = 0.5): with pull 1 it slides on its bound mu lambda_n = 0.5, with pull
// 0.4 it sticks. The warm start is a pass on bounds from lambda_n = 0.5, so every friction row sits
// on the lagged bound 0.25.
void coupled_step_on_sliding_contacts(int contacts, double pull, bool& solved, Eigen::VectorXd& lambda,
                                      CoupledWorkspace& ws) {
  const int n = 2 * contacts;
  DiagonalMatrix a(Eigen::VectorXd::Ones(n));
  Eigen::VectorXd q = -Eigen::VectorXd::Ones(n);
  std::vector<int> normal_of(n, -1);
  std::vector<double> mu(n, 0.0);
  Eigen::VectorXd lo(n), hi(n);
  lambda.resize(n);
  std::vector<RowState> state(n);
  for (int c = 0; c < contacts; ++c) {
    lo[2 * c] = 0;
    hi[2 * c] = kInf;
    lambda[2 * c] = 1;
    state[2 * c] = RowState::Free;
    normal_of[2 * c + 1] = 2 * c;
    mu[2 * c + 1] = 0.5;
    lo[2 * c + 1] = -0.25;
    hi[2 * c + 1] = 0.25;
    lambda[2 * c + 1] = 0.25;
    state[2 * c + 1] = RowState::Upper;
    q[2 * c + 1] = -pull;
  }
  solved = coupled_friction_step(a, q, lo, hi, FrictionCoupling{&normal_of, &mu}, lambda, state, BlcpSettings{}, ws);
}

// When the lagged pass's sets are the coupled problem's, the coupled step solves it by block pivots
// on its own equations (a jump), with no path pivots: for any number of sliding rows (no path is
// tried above kCoupledMaxSliding), and after one swap for friction rows that stick within their new
// boxes though they sat on the lagged bounds.
TEST(Blcp, CoupledStepJumpsToTheAnswerWithoutAPath) {
  for (const int contacts : {8, kCoupledMaxSliding + 1}) {
    bool solved = false;
    Eigen::VectorXd lambda;
    CoupledWorkspace ws;
    coupled_step_on_sliding_contacts(contacts, 1.0, solved, lambda, ws);
    ASSERT_TRUE(solved);
    EXPECT_EQ(ws.jumps, 1);
    EXPECT_EQ(ws.events, 0);
    for (int c = 0; c < contacts; ++c) {
      EXPECT_NEAR(lambda[2 * c], 1.0, 1e-12);
      EXPECT_NEAR(lambda[2 * c + 1], 0.5, 1e-12);
    }
  }
  bool solved = false;
  Eigen::VectorXd lambda;
  CoupledWorkspace ws;
  coupled_step_on_sliding_contacts(8, 0.4, solved, lambda, ws);
  ASSERT_TRUE(solved);
  EXPECT_EQ(ws.jumps, 1);
  EXPECT_EQ(ws.events, 0);
  for (int c = 0; c < 8; ++c) {
    EXPECT_NEAR(lambda[2 * c], 1.0, 1e-12);
    EXPECT_NEAR(lambda[2 * c + 1], 0.4, 1e-12);
  }
}

// Independent reference: try all 3^n index sets, solve each with LU, keep the one that satisfies
// the BLCP conditions. For SPD A the solution is unique.
Eigen::VectorXd enumerate_solution(const DenseBlcp& p, int& found) {
  const int n = static_cast<int>(p.q.size());
  int sets = 1;
  for (int j = 0; j < n; ++j) sets *= 3;
  Eigen::VectorXd best;
  found = 0;
  for (int code = 0; code < sets; ++code) {
    std::vector<int> free_rows;
    Eigen::VectorXd lambda(n);
    bool valid = true;
    for (int j = 0, c = code; j < n; ++j, c /= 3) {
      const int s = c % 3;
      if (s == 0) free_rows.push_back(j);
      else lambda[j] = s == 1 ? p.lo[j] : p.hi[j];
      if (s != 0 && !std::isfinite(lambda[j])) valid = false;
    }
    if (!valid) continue;
    const int nf = static_cast<int>(free_rows.size());
    if (nf > 0) {
      Eigen::MatrixXd aff(nf, nf);
      Eigen::VectorXd rhs(nf);
      for (int r = 0; r < nf; ++r) {
        rhs[r] = -p.q[free_rows[r]];
        for (int j = 0, c = code; j < n; ++j, c /= 3)
          if (c % 3 != 0) rhs[r] -= p.a(free_rows[r], j) * lambda[j];
        for (int c = 0; c < nf; ++c) aff(r, c) = p.a(free_rows[r], free_rows[c]);
      }
      const Eigen::VectorXd x = aff.partialPivLu().solve(rhs);
      for (int r = 0; r < nf; ++r) lambda[free_rows[r]] = x[r];
    }
    const Eigen::VectorXd w = p.a * lambda + p.q;
    const double tol = 1e-9 * std::max(1.0, p.q.cwiseAbs().maxCoeff());
    bool ok = true;
    for (int j = 0, c = code; j < n && ok; ++j, c /= 3) {
      const int s = c % 3;
      if (s == 0) ok = lambda[j] >= p.lo[j] - tol && lambda[j] <= p.hi[j] + tol && std::abs(w[j]) <= tol;
      else if (p.lo[j] == p.hi[j]) ok = true;
      else ok = s == 1 ? w[j] >= -tol : w[j] <= tol;
    }
    if (ok) {
      ++found;
      if (best.size() == 0) best = lambda;
    }
  }
  return best;
}

TEST(Blcp, AgreesWithExhaustiveEnumeration) {
  std::mt19937 rng(2024);
  for (int n = 1; n <= 7; ++n)
    for (int k = 0; k < 60; ++k) {
      DenseBlcp p = testing::random_dense_blcp(rng, n);
      p.a.diagonal().array() += 0.05;  // keep the LU reference well conditioned
      int found = 0;
      const Eigen::VectorXd reference = enumerate_solution(p, found);
      ASSERT_GE(found, 1) << "n=" << n << " k=" << k;
      DenseBlcpMatrix dense;
      dense.assign(p.a);
      SparseBlcpMatrix sparse;
      sparse.assign(LowerCsc::from_dense(p.a));
      for (BlcpMatrix* m : std::initializer_list<BlcpMatrix*>{&dense, &sparse}) {
        const Solution s = run(*m, p.q, p.lo, p.hi, random_states(rng, n));
        ASSERT_TRUE(s.result.converged);
        EXPECT_LE(relative_difference(s.lambda, reference), 1e-9) << "n=" << n << " k=" << k;
      }
    }
}

TEST(Blcp, WarmStartFromTheSolutionSetsTakesOneIteration) {
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const DenseBlcp p = testing::random_dense_blcp(rng, 5 + k % 40);
    DenseBlcpMatrix a;
    a.assign(p.a);
    const Solution cold = run(a, p.q, p.lo, p.hi, std::vector<RowState>(p.q.size(), RowState::Free));
    ASSERT_TRUE(cold.result.converged);
    DenseBlcpMatrix fresh;
    fresh.assign(p.a);
    const Solution warm = run(fresh, p.q, p.lo, p.hi, cold.state);
    ASSERT_TRUE(warm.result.converged);
    EXPECT_EQ(warm.result.iterations, 1);
    EXPECT_EQ(warm.result.factorizations, 1);
    EXPECT_EQ(warm.state, cold.state);
    EXPECT_LE(relative_difference(warm.lambda, cold.lambda), 1e-12);
    // Solving again on the same matrix reuses the factor of the same free set.
    const Solution again = run(fresh, p.q, p.lo, p.hi, cold.state);
    EXPECT_EQ(again.result.factorizations, 0);
  }
}

// pivot_patience = 0: projected Newton takes over at the first pivoting iteration that does not
// reach a new low of infeasible rows, from the interior-point phase's point when it runs (dense
// backend, interior_min_rows 0; CHOLMOD on A has no shifted factorisation, so never there). The
// answers must not change, and every path must be taken.
TEST(Blcp, ProjectedNewtonAfterTheFirstStallGivesTheSameSolution) {
  std::mt19937 rng(31337);
  BlcpSettings settings;
  settings.pivot_patience = 0;
  BlcpSettings interior = settings;
  interior.interior_min_rows = 0;
  int newton = 0, interior_runs = 0;
  for (int k = 0; k < 300; ++k) {
    const DenseBlcp p = testing::random_dense_blcp(rng, 10 + k % 50);
    const std::vector<RowState> warm = random_states(rng, static_cast<int>(p.q.size()));
    DenseBlcpMatrix a;
    a.assign(p.a);
    SparseBlcpMatrix sparse;
    sparse.assign(LowerCsc::from_dense(p.a));
    const Solution block = run(a, p.q, p.lo, p.hi, warm);
    const Solution single = run(a, p.q, p.lo, p.hi, warm, settings);
    const Solution ip = run(a, p.q, p.lo, p.hi, warm, interior);
    const Solution none = run(sparse, p.q, p.lo, p.hi, warm, interior);
    ASSERT_TRUE(block.result.converged && single.result.converged && ip.result.converged && none.result.converged);
    newton += single.result.newton;
    interior_runs += ip.result.interior;
    EXPECT_FALSE(single.result.interior || none.result.interior);
    for (const Solution* s : {&single, &ip}) {
      EXPECT_LE(relative_difference(s->lambda, block.lambda), 1e-9) << k;
      EXPECT_LE(natural_map_residual(p.a, p.q, p.lo, p.hi, s->lambda), 1e-10) << k;
      expect_consistent_sets(*s, p.lo, p.hi);
    }
  }
  EXPECT_GT(newton, 30);
  EXPECT_GT(interior_runs, 30);
}

// Sliding piles with box friction: block pivoting stalls with many infeasible rows; projected Newton
// must finish, with or without the interior-point phase first (body space), and the answer must
// still be exact and match the dense one.
TEST(Blcp, StalledPivotingIsFinishedExactly) {
  std::mt19937 rng(2718);
  RandomIsland island;
  BlcpSettings interior;
  interior.interior_min_rows = 0;
  int newton = 0, interior_runs = 0;
  for (int k = 0; k < 6; ++k) {
    testing::IslandOptions opt;
    opt.rows = 300 + 60 * k;
    opt.neighbour_radius = 1.2;
    opt.q_consistent = 1.0;  // every body moving: most contacts slide
    opt.box_fraction = 0;
    testing::random_contact_island(rng, opt, island);
    const IslandSystem& s = island.system;
    DenseBlcpMatrix dense;
    build_dense(s, dense.matrix());
    dense.finalize();
    BodySpaceBlcpMatrix body_space;
    body_space.assign(s);
    // Cold start: every bounded row at its lower bound.
    std::vector<RowState> cold(s.rows);
    for (int j = 0; j < s.rows; ++j) cold[j] = std::isfinite(s.lo[j]) ? RowState::Lower : RowState::Free;
    const Solution d = run(dense, s.q, s.lo, s.hi, cold);
    const Solution b = run(body_space, s.q, s.lo, s.hi, cold);
    const Solution i = run(body_space, s.q, s.lo, s.hi, cold, interior);
    ASSERT_TRUE(d.result.converged && b.result.converged && i.result.converged) << k;
    newton += d.result.newton;
    interior_runs += i.result.interior;
    const double bound = residual_bound(s.diag, s.q, d.lambda);
    EXPECT_LE(natural_map_residual(dense.matrix(), s.q, s.lo, s.hi, d.lambda), bound) << k;
    EXPECT_LE(natural_map_residual(dense.matrix(), s.q, s.lo, s.hi, b.lambda), bound) << k;
    EXPECT_LE(natural_map_residual(dense.matrix(), s.q, s.lo, s.hi, i.lambda), bound) << k;
    EXPECT_LE(relative_difference(b.lambda, d.lambda), 1e-9) << k;
    EXPECT_LE(relative_difference(i.lambda, d.lambda), 1e-9) << k;
  }
  EXPECT_GE(newton, 3);
  EXPECT_GE(interior_runs, 3);
}

// The iteration cap: not converged, but the iterate is finite, admissible and consistent.
TEST(Blcp, IterationCapLeavesAnAdmissibleIterate) {
  std::mt19937 rng(8);
  int capped = 0;
  for (int k = 0; k < 100; ++k) {
    const DenseBlcp p = testing::random_dense_blcp(rng, 40);
    DenseBlcpMatrix a;
    a.assign(p.a);
    BlcpSettings settings;
    settings.max_iterations = 1;
    const Solution s = run(a, p.q, p.lo, p.hi, random_states(rng, 40), settings);
    if (s.result.converged) continue;
    ++capped;
    for (int j = 0; j < 40; ++j) {
      EXPECT_GE(s.lambda[j], p.lo[j]);
      EXPECT_LE(s.lambda[j], p.hi[j]);
    }
    expect_consistent_sets(s, p.lo, p.hi);
  }
  EXPECT_GT(capped, 50);
}

// The residual measure itself: zero at the solution, the analytic value away from it.
TEST(Blcp, NaturalMapResidualValues) {
  Eigen::MatrixXd a(2, 2);
  a << 2, 0, 0, 4;
  const Eigen::VectorXd q = Eigen::Vector2d(-2, 4), lo = Eigen::Vector2d(0, 0), hi = Eigen::Vector2d(kInf, kInf);
  // Solution: lambda = (1, 0), w = (0, 4).
  EXPECT_EQ(natural_map_residual(a, q, lo, hi, Eigen::Vector2d(1, 0)), 0.0);
  // lambda = (0.5, 0): w_0 = -1, clamp(0.5 + 0.5) = 1, |r_0| A_00 / s = 0.5 * 2 / 4.
  EXPECT_DOUBLE_EQ(natural_map_residual(a, q, lo, hi, Eigen::Vector2d(0.5, 0)), 0.25);
  // lambda = (1, 1): w_1 = 8, clamp(1 - 2) = 0, |r_1| A_11 / s = 1 * 4 / 4.
  EXPECT_DOUBLE_EQ(natural_map_residual(a, q, lo, hi, Eigen::Vector2d(1, 1)), 1.0);
}

}  // namespace
}  // namespace rbpart
