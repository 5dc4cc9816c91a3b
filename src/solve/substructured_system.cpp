#include "solve/substructured_system.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <array>
#include <iterator>
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
  s_ = &s;
  const int part_count = *std::max_element(part_of_body.begin(), part_of_body.end()) + 1;
  parts_ = std::vector<Part>(part_count);
  // Rows by the parts of their bodies: {i, i} a sub-system row of part i, {i, k} an interface row
  // between parts i and k (by slot).
  std::vector<std::array<int, 2>> group(s.rows);
  std::vector<std::vector<int>> bodies(part_count), rows(part_count);
  for (int b = 0; b < s.bodies; ++b) bodies[part_of_body[b]].push_back(b);
  interface_row_.clear();
  for (int j = 0; j < s.rows; ++j) {
    const int first = part_of_body[s.body[j][0]];
    group[j] = {first, s.body[j][1] < 0 ? first : part_of_body[s.body[j][1]]};
    if (group[j][0] == group[j][1]) rows[first].push_back(j);
    else interface_row_.push_back(j);
  }
  for (int j = 0; j < s.rows; ++j) {
    const int n = s.normal_of[j];
    if (n >= 0 && std::minmax(group[j][0], group[j][1]) != std::minmax(group[n][0], group[n][1]))
      throw std::invalid_argument("SubstructuredSystem: a friction row and its normal lie in different parts");
  }
  const std::vector<Mat6> mass = body_masses(s);
  for (int i = 0; i < part_count; ++i) {
    if (bodies[i].empty()) throw std::invalid_argument("SubstructuredSystem: part " + std::to_string(i) + " is empty");
    parts_[i].n.assign(s, std::move(bodies[i]), std::move(rows[i]), mass, dense_max_bodies);
  }
  // Each part's interface rows, and the bodies they act on: first as local bodies, then as
  // positions among the part's interface bodies.
  const auto position = [](const std::vector<int>& sorted, int value) {
    return static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), value) - sorted.begin());
  };
  const int ni = interface_rows();
  interface_bodies_ = 0;
  for (int t = 0; t < ni; ++t)
    for (int slot = 0; slot < 2; ++slot) {
      Part& p = parts_[group[interface_row_[t]][slot]];
      p.touch.push_back(t);
      p.slot.push_back(slot);
      p.touch_body.push_back(p.n.local_body(s.body[interface_row_[t]][slot]));
    }
  for (Part& p : parts_) {
    p.interface_bodies = p.touch_body;
    std::sort(p.interface_bodies.begin(), p.interface_bodies.end());
    p.interface_bodies.erase(std::unique(p.interface_bodies.begin(), p.interface_bodies.end()), p.interface_bodies.end());
    interface_bodies_ += static_cast<int>(p.interface_bodies.size());
    const int nt = static_cast<int>(p.touch.size());
    p.touch_normal.assign(nt, -1);
    for (int a = 0; a < nt; ++a) {
      p.touch_body[a] = position(p.interface_bodies, p.touch_body[a]);
      const int n = s.normal_of[interface_row_[p.touch[a]]];
      if (n >= 0) p.touch_normal[a] = position(p.touch, position(interface_row_, n));
    }
    p.touch_equation.assign(nt, RowEquation::Fixed);
    p.touch_tie.assign(nt, 0.0);
    p.formed = false;
  }
  // S's pattern: column t holds the interface rows of the parts row t touches.
  if (ni <= 6 * dense_max_bodies) {
    s_factor_.assign_dense(ni);
  } else {
    std::vector<int> colptr(1, 0), rowind;
    for (int t = 0; t < ni; ++t) {
      const std::vector<int>& a = parts_[group[interface_row_[t]][0]].touch;
      const std::vector<int>& b = parts_[group[interface_row_[t]][1]].touch;
      std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(rowind));
      colptr.push_back(static_cast<int>(rowind.size()));
    }
    s_factor_.assign_sparse(ni, std::move(colptr), std::move(rowind));
  }
  const auto entry = [&](int row, int column) {
    const int start = s_factor_.column_start(column);
    if (s_factor_.dense()) return start + row;
    const int* first = s_factor_.rowind().data() + start;
    const int* last = s_factor_.rowind().data() + s_factor_.column_start(column + 1);
    return start + static_cast<int>(std::lower_bound(first, last, row) - first);
  };
  diagonal_.resize(ni);
  for (int t = 0; t < ni; ++t) diagonal_[t] = entry(t, t);
  for (Part& p : parts_) {
    const int nt = static_cast<int>(p.touch.size());
    p.entry.resize(static_cast<std::size_t>(nt) * nt);
    for (int b = 0; b < nt; ++b)
      for (int a = 0; a < nt; ++a) p.entry[a + nt * b] = entry(p.touch[a], p.touch[b]);
  }
  equation_i_.assign(ni, RowEquation::Fixed);
  tie_i_.assign(ni, 0.0);
  r_.resize(ni);
  last_ = total_ = SubstructuredCost{};
}

void SubstructuredSystem::factor_part(Part& p, const Piece& piece) {
  p.refactored = !p.n.factored_for(piece);
  if (p.refactored) {
    p.formed = false;
    p.ok = p.n.factor(piece);
    if (!p.ok) return;
    // X = N^-1 U on the interface bodies' unknowns, and the rows of J_T X.
    const int k = static_cast<int>(p.interface_bodies.size());
    p.x.setZero(6 * p.n.bodies(), 6 * k);
    for (int c = 0; c < k; ++c) p.x.block<6, 6>(6 * p.interface_bodies[c], 6 * c).setIdentity();
    p.n.solve(p.x.data(), 6 * k);
    p.jx.resize(p.touch.size(), 6 * k);
    for (std::size_t a = 0; a < p.touch.size(); ++a)
      p.jx.row(a).noalias() = jac(p, a).transpose() * p.x.middleRows<6>(6 * p.interface_bodies[p.touch_body[a]]);
  }
  const int nt = static_cast<int>(p.touch.size());
  bool same = p.formed;
  for (int a = 0; a < nt && same; ++a) {
    const int j = interface_row_[p.touch[a]];
    same = piece.equation[j] == p.touch_equation[a] && piece.tie[j] == p.touch_tie[a];
  }
  if (same) return;
  // C = J_T X E_T column by column: a free row's own column, and each tie in its normal's.
  p.c.setZero(nt, nt);
  for (int a = 0; a < nt; ++a) {
    const int j = interface_row_[p.touch[a]];
    p.touch_equation[a] = piece.equation[j];
    p.touch_tie[a] = piece.tie[j];
    if (piece.equation[j] == RowEquation::Free)
      p.c.col(a).noalias() += p.jx.middleCols<6>(6 * p.touch_body[a]) * jac(p, a);
    else if (piece.equation[j] == RowEquation::Tied)
      p.c.col(p.touch_normal[a]).noalias() += p.jx.middleCols<6>(6 * p.touch_body[a]) * (piece.tie[j] * jac(p, a));
  }
  p.formed = true;
}

bool SubstructuredSystem::factor(const Piece& piece) {
  const IslandSystem& s = *s_;
  const Timer wall;
  last_ = SubstructuredCost{};
  for_parts([&](Part& p) { factor_part(p, piece); });
  bool ok = true;
  for (const Part& p : parts_) {
    ok = ok && p.ok;
    last_.parts_refactored += p.refactored;
  }
  if (ok && interface_rows() > 0)
    serial([&] {
      // S in part order; a row that is not free is an identity row.
      s_factor_.set_zero();
      double* values = s_factor_.values();
      for (int t = 0; t < interface_rows(); ++t) {
        const int j = interface_row_[t];
        equation_i_[t] = piece.equation[j];
        tie_i_[t] = piece.tie[j];
        values[diagonal_[t]] = equation_i_[t] == RowEquation::Free ? s.sigma[j] + piece.shift[j] : 1.0;
      }
      for (const Part& p : parts_) {
        const int nt = static_cast<int>(p.touch.size());
        for (int b = 0; b < nt; ++b)
          for (int a = 0; a < nt; ++a)
            if (equation_i_[p.touch[a]] == RowEquation::Free) values[p.entry[a + nt * b]] += p.c(a, b);
      }
      // A free row's coupling to its normal, -c_t x_n (interior-point steps): in S directly, once
      // (through the first part that touches the row; the normal is an interface row of it too).
      coupled_.assign(interface_rows(), 0);
      // Ties, and free rows coupled to their normal anywhere in the island, make the N_i or S non-symmetric.
      bool symmetric = std::find(piece.equation.begin(), piece.equation.end(), RowEquation::Tied) == piece.equation.end() &&
                       std::all_of(piece.tie.data(), piece.tie.data() + piece.tie.size(), [](double c) { return c == 0; });
      for (const Part& p : parts_) {
        const int nt = static_cast<int>(p.touch.size());
        for (int a = 0; a < nt; ++a) {
          const int t = p.touch[a];
          if (equation_i_[t] != RowEquation::Free || tie_i_[t] == 0 || coupled_[t]) continue;
          coupled_[t] = 1;
          values[p.entry[a + nt * p.touch_normal[a]]] -= tie_i_[t];
          symmetric = false;
        }
      }
      ok = s_factor_.factor(symmetric);
    });
  finish_call(wall.ms());
  return ok;
}

void SubstructuredSystem::solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  const Timer wall;
  last_ = SubstructuredCost{};
  x.resize(g.size());
  // v_i = N_i^-1 h'_i, and its velocity on every interface row touching the part.
  for_parts([&](Part& p) {
    p.h.setZero(6 * p.n.bodies());
    p.n.add_rhs(g, p.h);
    const int nt = static_cast<int>(p.touch.size());
    for (int a = 0; a < nt; ++a)
      if (p.touch_equation[a] != RowEquation::Free)
        p.h.segment<6>(6 * p.interface_bodies[p.touch_body[a]]) += jac(p, a) * g[interface_row_[p.touch[a]]];
    p.n.solve(p.h.data());
    p.term.resize(nt);
    for (int a = 0; a < nt; ++a) p.term[a] = jac(p, a).dot(p.h.segment<6>(6 * p.interface_bodies[p.touch_body[a]]));
  });
  // The interface impulses: S for the free ones, in part order.
  serial([&] {
    const int ni = interface_rows();
    for (int t = 0; t < ni; ++t) r_[t] = equation_i_[t] == RowEquation::Free ? g[interface_row_[t]] : 0.0;
    for (const Part& p : parts_)
      for (std::size_t a = 0; a < p.touch.size(); ++a)
        if (equation_i_[p.touch[a]] == RowEquation::Free) r_[p.touch[a]] -= p.term[a];
    if (ni > 0) s_factor_.solve(r_.data());
    for (int t = 0; t < ni; ++t) {
      const int j = interface_row_[t];
      x[j] = equation_i_[t] == RowEquation::Free ? r_[t] : g[j];
    }
    for (int t = 0; t < ni; ++t)
      if (equation_i_[t] == RowEquation::Tied) x[interface_row_[t]] += tie_i_[t] * x[s_->normal_of[interface_row_[t]]];
  });
  // u_i = v_i + X_i E_T x_I, then the part's own impulses.
  for_parts([&](Part& p) {
    p.y.setZero(p.x.cols());
    for (std::size_t a = 0; a < p.touch.size(); ++a) {
      const int j = interface_row_[p.touch[a]];
      double impulse = 0;  // of x_I's unknowns only: a Fixed row's, and a Tied row's g_t, are in h'
      if (p.touch_equation[a] == RowEquation::Free) impulse = x[j];
      else if (p.touch_equation[a] == RowEquation::Tied) impulse = p.touch_tie[a] * x[s_->normal_of[j]];
      p.y.segment<6>(6 * p.touch_body[a]) += jac(p, a) * impulse;
    }
    p.h.noalias() += p.x * p.y;
    p.n.recover(g, p.h, x);
  });
  finish_call(wall.ms());
}

}  // namespace rbpart
