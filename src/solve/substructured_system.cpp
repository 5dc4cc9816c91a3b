#include "solve/substructured_system.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace rbpart {

template <class Fn>
void SubstructuredSystem::for_parts(Fn&& fn) {
  parallel_for_each(parts_.size(), [&](std::size_t i) {
    const Timer timer;
    fn(parts_[i]);
    parts_[i].ms = timer.ms();
  });
  double slowest = 0;
  for (const Part& p : parts_) {
    last_.work_ms += p.ms;
    slowest = std::max(slowest, p.ms);
  }
  last_.critical_path_ms += slowest;
}

template <class Fn>
void SubstructuredSystem::serial(Fn&& fn) {
  const Timer timer;
  fn();
  const double ms = timer.ms();
  last_.work_ms += ms;
  last_.critical_path_ms += ms;
}

void SubstructuredSystem::finish_call(double wall_ms) {
  last_.wall_ms = wall_ms;
  total_.work_ms += last_.work_ms;
  total_.critical_path_ms += last_.critical_path_ms;
  total_.wall_ms += last_.wall_ms;
  total_.parts_refactored += last_.parts_refactored;
}

void SubstructuredSystem::assign(const IslandSystem& s, const std::vector<int>& part_of_body, int dense_max_bodies) {
  const int part_count = *std::max_element(part_of_body.begin(), part_of_body.end()) + 1;
  parts_ = std::vector<Part>(part_count);
  // Rows by the parts of their bodies: {i, i} a sub-system row of part i, {i, k} an interface row
  // between parts i and k (by slot).
  std::vector<std::array<int, 2>> group(s.rows);
  std::vector<std::vector<int>> bodies(part_count), rows(part_count);
  std::vector<int> interface_rows;
  std::vector<char> boundary(s.bodies, 0);
  for (int b = 0; b < s.bodies; ++b) bodies[part_of_body[b]].push_back(b);
  for (int j = 0; j < s.rows; ++j) {
    const int first = part_of_body[s.body[j][0]];
    group[j] = {first, s.body[j][1] < 0 ? first : part_of_body[s.body[j][1]]};
    if (group[j][0] == group[j][1]) {
      rows[first].push_back(j);
    } else {
      interface_rows.push_back(j);
      boundary[s.body[j][0]] = boundary[s.body[j][1]] = 1;
    }
  }
  for (int j = 0; j < s.rows; ++j) {
    const int n = s.normal_of[j];
    if (n >= 0 && std::minmax(group[j][0], group[j][1]) != std::minmax(group[n][0], group[n][1]))
      throw std::invalid_argument("SubstructuredSystem: a friction row and its normal lie in different parts");
  }
  interface_rows_ = static_cast<int>(interface_rows.size());
  std::vector<int> interface_bodies;
  for (int b = 0; b < s.bodies; ++b)
    if (boundary[b]) interface_bodies.push_back(b);
  const std::vector<Mat6> mass = body_masses(s);
  std::vector<std::vector<int>> cliques(part_count);
  for (int i = 0; i < part_count; ++i) {
    Part& p = parts_[i];
    if (bodies[i].empty()) throw std::invalid_argument("SubstructuredSystem: part " + std::to_string(i) + " is empty");
    const std::vector<int> part_bodies = bodies[i];
    p.n.assign(s, std::move(bodies[i]), rows[i], mass, dense_max_bodies);
    p.position.resize(part_bodies.size());
    for (std::size_t l = 0; l < part_bodies.size(); ++l) {
      const int b = part_bodies[l];
      std::vector<int>& side = boundary[b] ? p.boundary : p.interior;
      p.position[l] = static_cast<int>(side.size());
      side.push_back(static_cast<int>(l));
      if (boundary[b]) {
        p.boundary_at.push_back(static_cast<int>(std::lower_bound(interface_bodies.begin(), interface_bodies.end(), b) -
                                                 interface_bodies.begin()));
        cliques[i].push_back(p.boundary_at.back());
      }
    }
    // N_i's blocks: the diagonal and every pair of bodies a sub-system row joins.
    std::vector<std::array<int, 2>> pairs;
    for (std::size_t l = 0; l < part_bodies.size(); ++l) pairs.push_back({static_cast<int>(l), static_cast<int>(l)});
    for (const int j : rows[i])
      if (s.body[j][1] >= 0) {
        const int a = p.n.local_body(s.body[j][0]), b = p.n.local_body(s.body[j][1]);
        pairs.push_back({a, b});
        pairs.push_back({b, a});
      }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<std::array<int, 2>> interior_pairs;
    for (const auto& [r, c] : pairs) {
      const bool r_in = !boundary[part_bodies[r]], c_in = !boundary[part_bodies[c]];
      (r_in ? (c_in ? p.ii : p.ik) : (c_in ? p.ki : p.kk)).push_back({r, c});
      if (r_in && c_in) interior_pairs.push_back({p.position[r], p.position[c]});
    }
    // Sorted by (r, c) on local bodies, which keeps the interior positions' order.
    p.n_ii.assign_blocks(static_cast<int>(p.interior.size()), interior_pairs, dense_max_bodies);
    const auto slots = [&](const std::vector<std::array<int, 2>>& blocks) {
      std::vector<PatternFactor::Slot> at;
      for (const auto& [r, c] : blocks) at.push_back(p.n.slot(r, c));
      return at;
    };
    p.ii_at = slots(p.ii);
    p.ik_at = slots(p.ik);
    p.ki_at = slots(p.ki);
    p.kk_at = slots(p.kk);
    p.ii_to.clear();
    for (const auto& [r, c] : p.ii) p.ii_to.push_back(p.n_ii.slot(p.position[r], p.position[c]));
  }
  // S carries no mass of its own: the parts' blocks hold it.
  interface_.assign(s, std::move(interface_bodies), std::move(interface_rows), std::vector<Mat6>(s.bodies, Mat6::Zero()),
                    dense_max_bodies, cliques);
  for (Part& p : parts_) {
    p.schur_at.clear();
    for (const int c : p.boundary_at)
      for (const int r : p.boundary_at) p.schur_at.push_back(interface_.slot(r, c));
  }
  r_.resize(6 * interface_.bodies());
  last_ = total_ = SubstructuredCost{};
}

void SubstructuredSystem::factor_part(Part& p, const Piece& piece) {
  p.refactored = !(p.ok && p.n.assembled_for(piece));
  if (!p.refactored) return;
  const bool tied = p.n.assemble(piece);
  const int ni = static_cast<int>(p.interior.size()), k = static_cast<int>(p.boundary.size());
  p.n_ii.set_zero();
  for (std::size_t b = 0; b < p.ii.size(); ++b) p.n_ii.block(p.ii_to[b]) = p.n.block(p.ii_at[b]);
  p.ok = ni == 0 || p.n_ii.factor(!tied);
  if (!p.ok || k == 0) return;
  p.x.setZero(6 * ni, 6 * k);
  for (std::size_t b = 0; b < p.ik.size(); ++b)
    p.x.block<6, 6>(6 * p.position[p.ik[b][0]], 6 * p.position[p.ik[b][1]]) = p.n.block(p.ik_at[b]);
  p.schur.setZero(6 * k, 6 * k);
  for (std::size_t b = 0; b < p.kk.size(); ++b)
    p.schur.block<6, 6>(6 * p.position[p.kk[b][0]], 6 * p.position[p.kk[b][1]]) = p.n.block(p.kk_at[b]);
  if (ni == 0) return;
  p.n_ii.solve(p.x.data(), 6 * k);
  // N_KI X_i block by block: N_KI holds only the blocks of rows joining a boundary body to an
  // interior one, a few per boundary body, where a dense product would run over all of I_i.
  for (std::size_t b = 0; b < p.ki.size(); ++b)
    p.schur.middleRows<6>(6 * p.position[p.ki[b][0]]).noalias() -=
        p.n.block(p.ki_at[b]) * p.x.middleRows<6>(6 * p.position[p.ki[b][1]]);
  p.ok = p.schur.allFinite();
}

bool SubstructuredSystem::factor(const Piece& piece) {
  const Timer wall;
  last_ = SubstructuredCost{};
  for_parts([&](Part& p) { factor_part(p, piece); });
  bool ok = true;
  for (const Part& p : parts_) {
    ok = ok && p.ok;
    last_.parts_refactored += p.refactored;
  }
  if (ok && interface_.bodies() > 0)
    serial([&] {
      interface_.assemble(piece);
      for (const Part& p : parts_) {
        const int k = static_cast<int>(p.boundary.size());
        for (int c = 0; c < k; ++c)
          for (int r = 0; r < k; ++r) interface_.block(p.schur_at[c * k + r]) += p.schur.block<6, 6>(6 * r, 6 * c);
      }
      // Ties, and free rows coupled to their normal, anywhere in the island make the N_i or S non-symmetric.
      const bool symmetric =
          std::find(piece.equation.begin(), piece.equation.end(), RowEquation::Tied) == piece.equation.end() &&
          std::all_of(piece.tie.data(), piece.tie.data() + piece.tie.size(), [](double c) { return c == 0; });
      ok = interface_.factor_assembled(symmetric);
    });
  finish_call(wall.ms());
  return ok;
}

void SubstructuredSystem::solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  const Timer wall;
  last_ = SubstructuredCost{};
  x.resize(g.size());
  // v_i = N_II^-1 h_I, and the part's terms of r: h_K - N_KI v_i.
  for_parts([&](Part& p) {
    p.h.setZero(6 * p.n.bodies());
    p.n.add_rhs(g, p.h);
    p.v.resize(6 * static_cast<Eigen::Index>(p.interior.size()));
    for (std::size_t l = 0; l < p.interior.size(); ++l) p.v.segment<6>(6 * l) = p.h.segment<6>(6 * p.interior[l]);
    if (!p.interior.empty()) p.n_ii.solve(p.v.data());
    p.c.resize(6 * static_cast<Eigen::Index>(p.boundary.size()));
    for (std::size_t l = 0; l < p.boundary.size(); ++l) p.c.segment<6>(6 * l) = p.h.segment<6>(6 * p.boundary[l]);
    for (std::size_t b = 0; b < p.ki.size(); ++b)
      p.c.segment<6>(6 * p.position[p.ki[b][0]]).noalias() -=
          p.n.block(p.ki_at[b]) * p.v.segment<6>(6 * p.position[p.ki[b][1]]);
  });
  // The interface bodies' velocities u_K, in part order, then the interface rows' impulses.
  if (interface_.bodies() > 0)
    serial([&] {
      r_.setZero();
      interface_.add_rhs(g, r_);
      for (const Part& p : parts_)
        for (std::size_t l = 0; l < p.boundary.size(); ++l) r_.segment<6>(6 * p.boundary_at[l]) += p.c.segment<6>(6 * l);
      interface_.solve(r_.data());
      interface_.recover(g, r_, x);
    });
  // u_I = v_i - X_i u_K, then the part's own impulses.
  for_parts([&](Part& p) {
    for (std::size_t l = 0; l < p.boundary.size(); ++l) p.c.segment<6>(6 * l) = r_.segment<6>(6 * p.boundary_at[l]);
    if (!p.boundary.empty() && !p.interior.empty()) p.v.noalias() -= p.x * p.c;
    for (std::size_t l = 0; l < p.interior.size(); ++l) p.h.segment<6>(6 * p.interior[l]) = p.v.segment<6>(6 * l);
    for (std::size_t l = 0; l < p.boundary.size(); ++l) p.h.segment<6>(6 * p.boundary[l]) = p.c.segment<6>(6 * l);
    p.n.recover(g, p.h, x);
  });
  finish_call(wall.ms());
}

}  // namespace rbpart
