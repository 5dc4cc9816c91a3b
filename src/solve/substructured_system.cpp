#include "solve/substructured_system.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

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

// The interface bodies: a cover of the pairs of bodies in two parts that rows join, so that every
// row between two parts has a body on the interface and no row couples two parts' own bodies.
// Taking both bodies of every such pair (Peiret et al.'s interface) would double S; the cover is
// built greedily: the body on the most pairs not yet covered joins it (the lowest on a tie) until
// every pair is covered.
void SubstructuredSystem::cover_cuts(const IslandSystem& s, const std::vector<int>& part_of_body, Cover& c,
                                     std::vector<char>& on_interface) {
  c.pairs.clear();
  for (int j = 0; j < s.rows; ++j) {
    const int a = s.body[j][0], b = s.body[j][1];
    if (b >= 0 && part_of_body[a] != part_of_body[b]) c.pairs.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(c.pairs.begin(), c.pairs.end());
  c.pairs.erase(std::unique(c.pairs.begin(), c.pairs.end()), c.pairs.end());
  // Each body's pairs, by the other body: c.other[c.start[b] .. c.start[b + 1]).
  c.start.assign(s.bodies + 1, 0);
  for (const auto& [a, b] : c.pairs) ++c.start[a + 1], ++c.start[b + 1];
  for (int b = 0; b < s.bodies; ++b) c.start[b + 1] += c.start[b];
  c.other.resize(2 * c.pairs.size());
  c.uncovered.assign(s.bodies, 0);  // here: each body's pairs filled in so far
  for (const auto& [a, b] : c.pairs) {
    c.other[c.start[a] + c.uncovered[a]++] = b;
    c.other[c.start[b] + c.uncovered[b]++] = a;
  }
  on_interface.assign(s.bodies, 0);
  c.heap.clear();
  for (int b = 0; b < s.bodies; ++b)
    if (c.uncovered[b] > 0) c.heap.push_back({c.uncovered[b], -b});
  std::make_heap(c.heap.begin(), c.heap.end());
  while (!c.heap.empty()) {
    std::pop_heap(c.heap.begin(), c.heap.end());
    const auto [count, minus_b] = c.heap.back();
    c.heap.pop_back();
    const int b = -minus_b;
    if (on_interface[b] || count != c.uncovered[b]) continue;  // an entry from before a neighbour joined
    on_interface[b] = 1;
    for (int k = c.start[b]; k < c.start[b + 1]; ++k) {
      const int other = c.other[k];
      if (!on_interface[other] && --c.uncovered[other] > 0) {
        c.heap.push_back({c.uncovered[other], -other});
        std::push_heap(c.heap.begin(), c.heap.end());
      }
    }
  }
}

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
  Split& split = split_;
  cover_cuts(s, part_of_body, split.cover, split.on_interface);
  // Parts with a body off the interface, renumbered in the partition's order.
  const int ids = *std::max_element(part_of_body.begin(), part_of_body.end()) + 1;
  split.part_of_id.assign(ids, -1);
  for (int b = 0; b < s.bodies; ++b)
    if (!split.on_interface[b]) split.part_of_id[part_of_body[b]] = 0;
  int part_count = 0;
  for (int& p : split.part_of_id)
    if (p == 0) p = part_count++;
  // As many parts as at the last assign() (a resting island): each keeps its pattern and analyses
  // where these hold.
  if (static_cast<int>(parts_.size()) != part_count) parts_ = std::vector<Part>(part_count);
  // Rows by owner: the part of a body of theirs off the interface, or the interface (-1). The
  // split's buffers keep their capacity from call to call.
  for (std::vector<std::vector<int>>* lists : {&split.bodies, &split.rows, &split.cliques}) {
    lists->resize(part_count);
    for (std::vector<int>& list : *lists) list.clear();
  }
  split.interface_rows.clear();
  split.interface_bodies.clear();
  split.owner.resize(s.rows);
  for (int b = 0; b < s.bodies; ++b) {
    if (split.on_interface[b]) split.interface_bodies.push_back(b);
    else split.bodies[split.part_of_id[part_of_body[b]]].push_back(b);
  }
  split.clique_of.assign(s.bodies, -1);
  for (int j = 0; j < s.rows; ++j) {
    int owner = -1;
    for (const int b : s.body[j])
      if (b >= 0 && !split.on_interface[b]) owner = split.part_of_id[part_of_body[b]];
    split.owner[j] = owner;
    if (owner < 0) {
      split.interface_rows.push_back(j);
      continue;
    }
    split.rows[owner].push_back(j);
    for (const int b : s.body[j])  // K_i: the interface bodies of part i's rows
      if (b >= 0 && split.on_interface[b] && split.clique_of[b] != owner) {
        split.clique_of[b] = owner;
        split.cliques[owner].push_back(b);
      }
  }
  for (int j = 0; j < s.rows; ++j) {
    const int n = s.normal_of[j];
    if (n >= 0 && split.owner[j] != split.owner[n])
      throw std::invalid_argument("SubstructuredSystem: a friction row and its normal lie in different parts");
  }
  interface_rows_ = static_cast<int>(split.interface_rows.size());
  for (int i = 0; i < part_count; ++i) {
    Part& p = parts_[i];
    p.ok = p.refactored = false;
    p.chunks.set_count(chunks_for_rows(static_cast<int>(split.rows[i].size()), kMinPartRowsPerChunk));
    // N_i's bodies: I_i's first, then K_i's (each increasing), so that its LU eliminates K_i last.
    std::vector<int>& bodies = split.bodies[i];
    std::vector<int>& clique = split.cliques[i];
    std::sort(clique.begin(), clique.end());
    p.interior = static_cast<int>(bodies.size());
    for (int& b : clique) {  // island body -> its position among S's bodies
      bodies.push_back(b);
      b = static_cast<int>(std::lower_bound(split.interface_bodies.begin(), split.interface_bodies.end(), b) -
                           split.interface_bodies.begin());
    }
  }
  // The split so far is serial work.
  last_.work_ms = last_.critical_path_ms = wall.ms();
  // The patterns, the parts' in parallel (a large part's takes milliseconds). The interface bodies'
  // masses are S's own, not the parts'.
  body_masses(s, split.mass);
  split.part_mass = split.mass;
  for (int b : split.interface_bodies) split.part_mass[b] = Mat6::Zero();
  for_parts([&](Part& p) {
    const int i = static_cast<int>(&p - parts_.data());
    p.n.assign(s, split.bodies[i], split.rows[i], split.part_mass);
  });
  serial([&] {
    interface_.assign(s, split.interface_bodies, split.interface_rows, split.mass, split.cliques);
    // Every part's blocks of S by their slot in S, each slot's in part order.
    adds_.clear();
    for (int i = 0; i < part_count; ++i) {
      const std::vector<int>& at = split.cliques[i];
      const int k = static_cast<int>(at.size());
      for (int c = 0; c < k; ++c)
        for (int r = 0; r < k; ++r) adds_.push_back({interface_.slot(at[r], at[c]), i, 6 * r, 6 * c});
    }
    std::sort(adds_.begin(), adds_.end());
    add_start_.clear();
    for (std::size_t a = 0; a < adds_.size(); ++a)
      if (a == 0 || adds_[a][0] != adds_[a - 1][0]) add_start_.push_back(static_cast<int>(a));
    add_start_.push_back(static_cast<int>(adds_.size()));
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

bool SubstructuredSystem::factor(const Piece& piece) {
  const Timer wall;
  last_ = SubstructuredCost{};
  // S's own terms M_K + N_T are assembled beside the parts, then the parts' blocks are added.
  const bool coupled = interface_.bodies() > 0;
  for_parts([&](Part& p) { factor_part(p, piece); }, [&] {
    if (coupled) interface_.assemble(piece);
  });
  bool ok = true;
  for (const Part& p : parts_) {
    ok = ok && p.ok;
    last_.parts_refactored += p.refactored;
  }
  // The parts' blocks of S, slot by slot, each slot's in part order (parts share interface bodies).
  if (ok && coupled)
    serial([&] {
      interface_chunks_.each(static_cast<int>(add_start_.size()) - 1, [&](int g) {
        PatternFactor::Block block = interface_.block(adds_[add_start_[g]][0]);
        for (int a = add_start_[g]; a < add_start_[g + 1]; ++a)
          block += parts_[adds_[a][1]].schur.block<6, 6>(adds_[a][2], adds_[a][3]);
      }, static_cast<int>(adds_.size()));
    });
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
      for (const Part& p : parts_) {
        const std::vector<int>& at = boundary(p);
        for (std::size_t l = 0; l < at.size(); ++l) r_.segment<6>(6 * at[l]) += p.h.segment<6>(6 * (p.interior + l));
      }
      interface_.solve(r_.data());
    });
  // u_I = N_II^-1 (h_I - N_IK u_K), then the part's own impulses; beside it the interface rows'.
  for_parts(
      [&](Part& p) {
        const std::vector<int>& at = boundary(p);
        const int k = static_cast<int>(at.size());
        p.u_k.resize(6 * k);
        for (int l = 0; l < k; ++l) p.u_k.segment<6>(6 * l) = r_.segment<6>(6 * at[l]);
        p.n.back_interior(p.h, p.u_k);
        p.n.recover(g, p.h, x);
      },
      [&] { interface_.recover(g, r_, x); });
  finish_call(wall.ms());
}

}  // namespace rbpart
