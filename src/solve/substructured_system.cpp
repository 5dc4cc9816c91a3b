#include "solve/substructured_system.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace rbpart {

namespace {

// fn()'s work and critical path: its time, where the loops it ran in `chunks` count at their
// chunks' tallies (IslandChunks).
template <class Fn>
std::array<double, 2> measure(const IslandChunks& chunks, Fn&& fn) {
  const double wall = chunks.wall_ms, work = chunks.work_ms, critical_path = chunks.critical_path_ms;
  const Timer timer;
  fn();
  const double own = timer.ms() - (chunks.wall_ms - wall);
  return {own + (chunks.work_ms - work), own + (chunks.critical_path_ms - critical_path)};
}

}  // namespace

template <class Fn, class Beside>
void SubstructuredSystem::for_parts(Fn&& fn, Beside&& beside) {
  const std::size_t n = parts_.size();
  std::array<double, 2> beside_cost{};
  parallel_for_each(n + 1, [&](std::size_t i) {
    if (i == n) {
      beside_cost = measure(interface_chunks_, beside);
    } else {
      Part& p = parts_[i];
      p.cost = measure(p.chunks, [&] { fn(p); });
    }
  });
  double slowest = beside_cost[1];
  last_.work_ms += beside_cost[0];
  for (const Part& p : parts_) {
    last_.work_ms += p.cost[0];
    slowest = std::max(slowest, p.cost[1]);
  }
  last_.critical_path_ms += slowest;
}

template <class Fn>
void SubstructuredSystem::for_parts(Fn&& fn) {
  for_parts(fn, [] {});
}

template <class Fn>
void SubstructuredSystem::serial(Fn&& fn) {
  const std::array<double, 2> cost = measure(interface_chunks_, fn);
  last_.work_ms += cost[0];
  last_.critical_path_ms += cost[1];
}

void SubstructuredSystem::finish_call(double wall_ms) {
  last_.wall_ms = wall_ms;
  total_.work_ms += last_.work_ms;
  total_.critical_path_ms += last_.critical_path_ms;
  total_.wall_ms += last_.wall_ms;
  total_.parts_refactored += last_.parts_refactored;
}

void SubstructuredSystem::assign(const IslandSystem& s, const std::vector<int>& part_of_body) {
  const Timer wall;
  last_ = total_ = SubstructuredCost{};
  interface_chunks_.set_count(kMaxChunks);
  const int part_count = *std::max_element(part_of_body.begin(), part_of_body.end()) + 1;
  // As many parts as at the last assign() (a resting island): each keeps its pattern and analyses
  // where these hold.
  if (static_cast<int>(parts_.size()) != part_count) parts_ = std::vector<Part>(part_count);
  // Rows by the parts of their bodies: {i, i} a sub-system row of part i, {i, k} an interface row
  // between parts i and k (by slot). The split's buffers keep their capacity from call to call.
  Split& split = split_;
  split.group.resize(s.rows);
  for (std::vector<std::vector<int>>* lists : {&split.bodies, &split.rows, &split.cliques}) {
    lists->resize(part_count);
    for (std::vector<int>& list : *lists) list.clear();
  }
  split.interface_rows.clear();
  split.interface_bodies.clear();
  split.boundary.assign(s.bodies, 0);
  for (int b = 0; b < s.bodies; ++b) split.bodies[part_of_body[b]].push_back(b);
  for (int j = 0; j < s.rows; ++j) {
    std::array<int, 2>& group = split.group[j];
    const int first = part_of_body[s.body[j][0]];
    group = {first, s.body[j][1] < 0 ? first : part_of_body[s.body[j][1]]};
    if (group[0] == group[1]) {
      split.rows[first].push_back(j);
    } else {
      split.interface_rows.push_back(j);
      split.boundary[s.body[j][0]] = split.boundary[s.body[j][1]] = 1;
    }
  }
  for (int j = 0; j < s.rows; ++j) {
    const int n = s.normal_of[j];
    if (n >= 0 && std::minmax(split.group[j][0], split.group[j][1]) != std::minmax(split.group[n][0], split.group[n][1]))
      throw std::invalid_argument("SubstructuredSystem: a friction row and its normal lie in different parts");
  }
  interface_rows_ = static_cast<int>(split.interface_rows.size());
  for (int b = 0; b < s.bodies; ++b)
    if (split.boundary[b]) split.interface_bodies.push_back(b);
  for (int i = 0; i < part_count; ++i) {
    Part& p = parts_[i];
    std::vector<int>& bodies = split.bodies[i];
    if (bodies.empty()) throw std::invalid_argument("SubstructuredSystem: part " + std::to_string(i) + " is empty");
    p.ok = p.refactored = false;
    p.chunks.set_count(chunks_for_rows(static_cast<int>(split.rows[i].size()), kMinPartRowsPerChunk));
    // N_i's bodies: I_i's first, then K_i's (each increasing), so that its LU eliminates K_i last.
    // (std::stable_partition would allocate its buffer.)
    const auto boundary = std::partition(bodies.begin(), bodies.end(), [&](int b) { return !split.boundary[b]; });
    std::sort(bodies.begin(), boundary);
    std::sort(boundary, bodies.end());
    p.interior = static_cast<int>(boundary - bodies.begin());
    p.boundary_at.clear();
    for (auto b = boundary; b != bodies.end(); ++b) {
      p.boundary_at.push_back(static_cast<int>(
          std::lower_bound(split.interface_bodies.begin(), split.interface_bodies.end(), *b) -
          split.interface_bodies.begin()));
      split.cliques[i].push_back(p.boundary_at.back());
    }
  }
  // The split so far is serial work.
  last_.work_ms = last_.critical_path_ms = wall.ms();
  // The patterns, the parts' in parallel (a large part's takes milliseconds).
  body_masses(s, split.mass);
  for_parts([&](Part& p) {
    const int i = static_cast<int>(&p - parts_.data());
    p.n.assign(s, split.bodies[i], split.rows[i], split.mass);
  });
  serial([&] {
    // S carries no mass of its own: the parts' blocks hold it.
    split.no_mass.assign(s.bodies, Mat6::Zero());
    interface_.assign(s, split.interface_bodies, split.interface_rows, split.no_mass, split.cliques);
    for (Part& p : parts_) {
      p.schur_at.clear();
      for (const int c : p.boundary_at)
        for (const int r : p.boundary_at) p.schur_at.push_back(interface_.slot(r, c));
    }
  });
  r_.resize(6 * interface_.bodies());
  finish_call(wall.ms());
}

void SubstructuredSystem::factor_part(Part& p, const Piece& piece) {
  p.refactored = !(p.ok && p.n.assembled_for(piece));
  if (p.refactored) {
    p.n.assemble(piece, &p.chunks);
    p.ok = p.n.factor_schur(p.interior, p.schur, &p.chunks);
  }
}

void SubstructuredSystem::add_schur(const Part& p) {
  const int k = static_cast<int>(p.boundary_at.size());
  for (int c = 0; c < k; ++c)
    for (int r = 0; r < k; ++r) interface_.block(p.schur_at[c * k + r]) += p.schur.block<6, 6>(6 * r, 6 * c);
}

bool SubstructuredSystem::factor(const Piece& piece) {
  const Timer wall;
  last_ = SubstructuredCost{};
  // S's own terms N_T are assembled beside the parts, then every part adds its block of S: the K_i
  // are disjoint, so each adds to blocks of its own, and each block of S is N_T's plus one part's
  // whatever the order.
  const bool coupled = interface_.bodies() > 0;
  for_parts([&](Part& p) { factor_part(p, piece); }, [&] {
    if (coupled) interface_.assemble(piece);
  });
  bool ok = true;
  for (const Part& p : parts_) {
    ok = ok && p.ok;
    last_.parts_refactored += p.refactored;
  }
  if (ok && coupled) for_parts([&](const Part& p) { add_schur(p); });
  if (ok && coupled) serial([&] { ok = interface_.factor_assembled(&interface_chunks_); });
  finish_call(wall.ms());
  return ok;
}

void SubstructuredSystem::solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  const Timer wall;
  last_ = SubstructuredCost{};
  x.resize(g.size());
  // The forward substitution over I_i, which leaves the part's terms of r, h_K - N_KI N_II^-1 h_I;
  // beside it the interface rows' terms h_T.
  for_parts(
      [&](Part& p) {
        p.h.setZero(6 * p.n.bodies());
        p.n.add_rhs(g, p.h);
        p.n.forward_interior(p.h);
      },
      [&] {
        r_.setZero();
        interface_.add_rhs(g, r_);
      });
  // The interface bodies' velocities u_K, the parts' terms added in part order.
  if (interface_.bodies() > 0)
    serial([&] {
      for (const Part& p : parts_)
        for (std::size_t l = 0; l < p.boundary_at.size(); ++l)
          r_.segment<6>(6 * p.boundary_at[l]) += p.h.segment<6>(6 * (p.interior + l));
      interface_.solve(r_.data());
    });
  // u_I = N_II^-1 (h_I - N_IK u_K), then the part's own impulses; beside it the interface rows'.
  for_parts(
      [&](Part& p) {
        const int k = static_cast<int>(p.boundary_at.size());
        p.u_k.resize(6 * k);
        for (int l = 0; l < k; ++l) p.u_k.segment<6>(6 * l) = r_.segment<6>(6 * p.boundary_at[l]);
        p.n.back_interior(p.h, p.u_k);
        p.n.recover(g, p.h, x);
      },
      [&] { interface_.recover(g, r_, x); });
  finish_call(wall.ms());
}

}  // namespace rbpart
