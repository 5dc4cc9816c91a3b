#include "solve/sub_island.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <limits>

namespace rbpart {

namespace {

// Lower bound of max |q| (as the BLCP core's), so that q = 0 still has an absolute scale.
constexpr double kMinScale = 1e-12;
// Step 3's safeguard: Armijo's sufficient-decrease fraction, the shortest step tried, and the
// round-off allowance of f in units of eps times the magnitude of its terms.
constexpr double kArmijo = 1e-4;
constexpr double kMinStep = 1e-6;
constexpr double kRoundoff = 64;

// The sets a warm start means for the bounds, as the BLCP core reads them: lo == hi is clamped,
// and no row clamps at an infinite bound.
RowState sanitized(RowState state, double lo, double hi) {
  if (!(lo < hi)) return RowState::Lower;
  if (state == RowState::Lower && lo == -std::numeric_limits<double>::infinity()) return RowState::Free;
  if (state == RowState::Upper && hi == std::numeric_limits<double>::infinity()) return RowState::Free;
  return state;
}

}  // namespace

// --- InterfaceMatrix ------------------------------------------------------------------------------

void SubstructuredIsland::InterfaceMatrix::assign(const Eigen::VectorXd& diag) {
  diag_ = diag;
  approx_.resize(static_cast<int>(diag.size()));
  approx_.matrix().setZero();
  factorizations_ = 0;
  changed();
}

void SubstructuredIsland::InterfaceMatrix::changed() {
  approx_.finalize();
  invalidate();
}

bool SubstructuredIsland::InterfaceMatrix::factor(const std::vector<char>& free) {
  bool ok = false;
  island_.serial(kFactorPhase, [&] { ok = approx_.prepare(free) >= 0; });
  ++factorizations_;
  return ok;
}

// --- SubstructuredIsland ----------------------------------------------------------------------------

SubstructuredIsland::SubstructuredIsland() : interface_(*this) {}

void SubstructuredIsland::assign(const IslandSystem& s, const std::vector<int>& part_of_body, int parts) {
  s_ = &s;
  part_of_body_ = part_of_body;
  parts_ = std::vector<Part>(parts);

  // Interface rows: two bodies in different parts; their bodies are the interface bodies.
  std::vector<char> interface_body(s.bodies, 0);
  std::vector<char> is_interface_row(s.rows, 0);
  interface_row_.clear();
  for (int r = 0; r < s.rows; ++r) {
    const int a = s.body[r][0], b = s.body[r][1];
    if (b < 0 || part_of_body[a] == part_of_body[b]) continue;
    is_interface_row[r] = 1;
    interface_row_.push_back(r);
    interface_body[a] = interface_body[b] = 1;
  }
  interface_bodies_ = static_cast<int>(std::count(interface_body.begin(), interface_body.end(), 1));

  // Bodies of each part, interface bodies last (sub_part.hpp: W_p from the trailing block).
  body_index_.assign(s.bodies, -1);
  for (char last : {0, 1})
    for (int b = 0; b < s.bodies; ++b) {
      if (interface_body[b] != last) continue;
      Part& p = parts_[part_of_body[b]];
      body_index_[b] = static_cast<int>(p.bodies.size());
      p.bodies.push_back(b);
      p.k += last;
    }
  for (int r = 0; r < s.rows; ++r)
    if (!is_interface_row[r]) parts_[part_of_body[s.body[r][0]]].rows.push_back(r);
  auto interface_position = [&](const Part& p, int b) {
    return body_index_[b] - (static_cast<int>(p.bodies.size()) - p.k);
  };
  for (int t = 0; t < interface_rows(); ++t)
    for (int slot = 0; slot < 2; ++slot) {
      const int b = s.body[interface_row_[t]][slot];
      Part& p = parts_[part_of_body[b]];
      p.touch.push_back(t);
      p.touch_slot.push_back(slot);
      p.touch_body.push_back(interface_position(p, b));
    }

  mass_ = body_masses(s);
  tied_.assign(s);

  for (Part& p : parts_) {
    const int n = static_cast<int>(p.rows.size()), nt = static_cast<int>(p.touch.size());
    for (int j = 0; j < n; ++j)
      for (int slot = 0; slot < 2; ++slot) {
        const int b = s.body[p.rows[j]][slot];
        if (b >= 0 && interface_body[b]) p.coupling.push_back({j, slot, interface_position(p, b)});
      }
    p.a.assign(s, p.rows, p.bodies, body_index_, mass_);
    p.q.resize(n);
    for (int j = 0; j < n; ++j) p.q[j] = s.q[p.rows[j]];
    p.lo.resize(n);
    p.hi.resize(n);
    p.lambda.resize(n);
    p.state.resize(n);
    p.trial_lambda.resize(n);
    p.trial_state.resize(n);
    p.used.resize(n);
    p.used_free.resize(n);
    p.free.resize(n);
    p.contribution_valid = false;
    p.x.resize(n);
    p.b.resize(n);
    p.qc.setZero(nt);
    p.y.resize(nt);
    p.u.resize(6 * p.k);
    p.v.resize(6 * p.k);
  }

  const int ni = interface_rows();
  q_i_.resize(ni);
  sigma_i_.resize(ni);
  Eigen::VectorXd diag(ni);
  for (int t = 0; t < ni; ++t) {
    q_i_[t] = s.q[interface_row_[t]];
    sigma_i_[t] = s.sigma[interface_row_[t]];
    diag[t] = s.diag[interface_row_[t]];
  }
  q_tilde_.resize(ni);
  lo_i_.resize(ni);
  hi_i_.resize(ni);
  lambda_i_.resize(ni);
  g_i_.resize(ni);
  state_i_.resize(ni);
  free_i_.assign(ni, 0);
  current_i_.resize(ni);
  step_i_.resize(ni);
  trial_i_.resize(ni);
  w_i_.resize(ni);
  island_lambda_.resize(s.rows);
  interface_.assign(diag);
  serial_ms_.fill(0);
  accounted_ms_ = span_ms_ = 0;
  loop_iterations_ = interface_iterations_ = 0;
  interface_newton_ = false;
  invalidate();
}

template <class Fn>
void SubstructuredIsland::for_parts(SubPhase phase, Fn&& fn) {
  const Timer wall;
  parallel_for_each(parts_.size(), [&](std::size_t i) {
    Part& p = parts_[i];
    const double factor_before = p.a.factor_ms();
    const Timer timer;
    fn(p);
    p.item_ms = timer.ms();
    const double factor = p.a.factor_ms() - factor_before;
    p.phase_ms[kFactorPhase] += factor;
    p.phase_ms[phase] += p.item_ms - factor;
  });
  double slowest = 0;
  for (const Part& p : parts_) slowest = std::max(slowest, p.item_ms);
  span_ms_ += slowest;
  accounted_ms_ += wall.ms();
}

bool SubstructuredIsland::factor_part(Part& p, const std::vector<char>& free) {
  if (p.a.prepare(free) < 0) return false;
  if (p.contribution_valid && free == p.contribution_free) return true;
  // W_p on the interface bodies, then C = J_T W_p J_T^T over the interface rows T touching p
  // (lower triangle: T is in increasing interface order, as S~'s rows).
  const IslandSystem& s = *s_;
  p.contribution_free = free;
  p.contribution_valid = true;
  p.contribution_changed = true;
  p.a.effective_inverse_mass(p.k, p.w);
  const int nt = static_cast<int>(p.touch.size());
  p.h.resize(nt, 6 * p.k);
  for (int a = 0; a < nt; ++a)
    p.h.row(a).noalias() =
        s.jac[interface_row_[p.touch[a]]][p.touch_slot[a]].transpose() * p.w.middleRows<6>(6 * p.touch_body[a]);
  p.c.resize(nt, nt);
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b <= a; ++b)
      p.c(a, b) = p.h.row(a).segment<6>(6 * p.touch_body[b]).dot(s.jac[interface_row_[p.touch[b]]][p.touch_slot[b]]);
  return true;
}

void SubstructuredIsland::form_rhs_term(Part& p) {
  // lambda^: clamped rows on their bounds, lambda^_F = -A_FF^-1 (q_F + A_FC lambda_C), exactly.
  const IslandSystem& s = *s_;
  const int n = static_cast<int>(p.rows.size());
  for (int j = 0; j < n; ++j)
    p.x[j] = p.used[j] == RowState::Free ? 0.0 : p.used[j] == RowState::Upper ? p.hi[j] : p.lo[j];
  p.a.multiply(p.x, p.b);
  for (int j = 0; j < n; ++j) p.b[j] = p.used_free[j] ? -(p.q[j] + p.b[j]) : 0.0;
  p.a.solve_exact(p.b);
  for (int j = 0; j < n; ++j)
    if (p.used_free[j]) p.x[j] = p.b[j];
  // Its term of q~: A_{I,p} lambda^ = J_{I,p} (M^-1 J_p^T lambda^) on the interface bodies.
  p.u.setZero();
  for (const auto& [j, slot, kb] : p.coupling) p.u.segment<6>(6 * kb) += s.mjac[p.rows[j]][slot] * p.x[j];
  for (std::size_t a = 0; a < p.touch.size(); ++a)
    p.qc[a] = s.jac[interface_row_[p.touch[a]]][p.touch_slot[a]].dot(p.u.segment<6>(6 * p.touch_body[a]));
}

void SubstructuredIsland::assemble_schur() {
  if (std::none_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.contribution_changed; })) return;
  Eigen::MatrixXd& approx = interface_.approximation();
  const int ni = interface_rows();
  for (int c = 0; c < ni; ++c) approx.col(c).tail(ni - c).setZero();
  approx.diagonal() = sigma_i_;
  for (Part& p : parts_) {
    const int nt = static_cast<int>(p.touch.size());
    for (int b = 0; b < nt; ++b)
      for (int a = b; a < nt; ++a) approx(p.touch[a], p.touch[b]) += p.c(a, b);
    p.contribution_changed = false;
  }
  interface_.changed();
}

void SubstructuredIsland::interface_velocity(const Part& p, const Eigen::VectorXd& x, const std::vector<char>* mask,
                                             Eigen::VectorXd& u) const {
  const IslandSystem& s = *s_;
  u.setZero(6 * p.k);
  for (std::size_t a = 0; a < p.touch.size(); ++a) {
    const int t = p.touch[a];
    if (mask && !(*mask)[t]) continue;
    u.segment<6>(6 * p.touch_body[a]) += s.mjac[interface_row_[t]][p.touch_slot[a]] * x[t];
  }
}

void SubstructuredIsland::schur_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  // (S x) = Sigma_I x + sum_p J_{I,p} (u_p - M^-1 J_F^T A_FF^-1 J_F u_p), u_p = M^-1 J_{I,p}^T x.
  const IslandSystem& s = *s_;
  for_parts(kInterfacePhase, [&](Part& p) {
    interface_velocity(p, x, nullptr, p.u);
    p.b.setZero();
    for (const auto& [j, slot, kb] : p.coupling)
      if (p.used_free[j]) p.b[j] += s.jac[p.rows[j]][slot].dot(p.u.segment<6>(6 * kb));
    p.a.solve_exact(p.b);
    p.v = p.u;
    for (const auto& [j, slot, kb] : p.coupling)
      if (p.used_free[j]) p.v.segment<6>(6 * kb) -= s.mjac[p.rows[j]][slot] * p.b[j];
    for (std::size_t a = 0; a < p.touch.size(); ++a)
      p.y[a] = s.jac[interface_row_[p.touch[a]]][p.touch_slot[a]].dot(p.v.segment<6>(6 * p.touch_body[a]));
  });
  y = sigma_i_.cwiseProduct(x);
  for (const Part& p : parts_)
    for (std::size_t a = 0; a < p.touch.size(); ++a) y[p.touch[a]] += p.y[a];
}

bool SubstructuredIsland::solve_parts(const Eigen::VectorXd& x) {
  const IslandSystem& s = *s_;
  for_parts(kSubsystemPhase, [&](Part& p) {
    interface_velocity(p, x, nullptr, p.u);
    p.shifted_q = p.q;
    for (const auto& [j, slot, kb] : p.coupling) p.shifted_q[j] += s.jac[p.rows[j]][slot].dot(p.u.segment<6>(6 * kb));
    p.settings.tolerance = p.settings_tolerance / std::max(max_abs(p.shifted_q), kMinScale);
    p.trial_lambda = p.lambda;
    p.trial_state = p.state;
    const BlcpResult r = solve_blcp(p.a, p.shifted_q, p.lo, p.hi, p.trial_lambda, p.trial_state, p.settings, p.ws);
    p.iterations += r.iterations;
    p.newton = p.newton || r.newton;
    p.ok = r.converged;
  });
  return std::all_of(parts_.begin(), parts_.end(), [](const Part& p) { return p.ok; });
}

double SubstructuredIsland::objective(const Eigen::VectorXd& x, double& roundoff) {
  const IslandSystem& s = *s_;
  for (const Part& p : parts_)
    for (std::size_t j = 0; j < p.rows.size(); ++j) island_lambda_[p.rows[j]] = p.trial_lambda[j];
  for (int t = 0; t < interface_rows(); ++t) island_lambda_[interface_row_[t]] = x[t];
  apply_a(s, island_lambda_, du_, w_);
  w_ += s.q;
  double f = 0;
  roundoff = 0;
  for (int r = 0; r < s.rows; ++r) {
    f += 0.5 * island_lambda_[r] * (w_[r] + s.q[r]);
    roundoff += std::abs(island_lambda_[r]) * (std::abs(w_[r] - s.q[r]) + std::abs(s.q[r]));
  }
  roundoff *= kRoundoff * std::numeric_limits<double>::epsilon();
  return f;
}

bool SubstructuredIsland::solve_fixed(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, Eigen::VectorXd& lambda,
                                      std::vector<RowState>& state, const BlcpSettings& settings,
                                      int max_iterations, int max_halvings) {
  const IslandSystem& s = *s_;
  // The parts refactor below: the island-level factor of the coupled step is void.
  invalidate();
  // One absolute feasibility tolerance for every sub-problem: the monolithic solve's.
  const double tolerance = settings.tolerance * std::max(max_abs(s.q), kMinScale);

  for (Part& p : parts_) {
    for (std::size_t j = 0; j < p.rows.size(); ++j) {
      const int r = p.rows[j];
      p.lo[j] = lo[r];
      p.hi[j] = hi[r];
      p.lambda[j] = lambda[r];
      p.state[j] = state[r];
      p.used[j] = sanitized(state[r], lo[r], hi[r]);
      p.used_free[j] = p.used[j] == RowState::Free;
    }
    p.refresh = true;
    p.settings = settings;
    p.settings_tolerance = tolerance;
  }
  for (int t = 0; t < interface_rows(); ++t) {
    const int r = interface_row_[t];
    lo_i_[t] = lo[r];
    hi_i_[t] = hi[r];
    current_i_[t] = lambda[r];
    state_i_[t] = state[r];
  }
  BlcpSettings interface_settings = settings;
  // phi and w_I at the accepted lambda_I; none before the first step, which is taken in full.
  bool accepted_any = false;
  double phi = 0;
  int halvings = 0;

  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    ++loop_iterations_;
    // 1. Factors for the current sets (cached when unchanged); blocks of S and terms of q~ where
    //    the sets or the bounds changed.
    for_parts(kSchurPhase, [&](Part& p) {
      p.ok = factor_part(p, p.used_free);
      if (p.ok && p.refresh) form_rhs_term(p);
      p.refresh = false;
    });
    if (std::any_of(parts_.begin(), parts_.end(), [](const Part& p) { return !p.ok; })) return false;
    serial(kSchurPhase, [&] {
      assemble_schur();
      q_tilde_ = q_i_;
      for (const Part& p : parts_)
        for (std::size_t a = 0; a < p.touch.size(); ++a) q_tilde_[p.touch[a]] += p.qc[a];
    });
    // 2. The interface BLCP.
    bool interface_ok = false;
    serial(kInterfacePhase, [&] {
      lambda_i_ = current_i_;
      interface_settings.tolerance = tolerance / std::max(max_abs(q_tilde_), kMinScale);
      const BlcpResult r =
          solve_blcp(interface_, q_tilde_, lo_i_, hi_i_, lambda_i_, state_i_, interface_settings, interface_ws_);
      interface_iterations_ += r.iterations;
      interface_newton_ = interface_newton_ || r.newton;
      interface_ok = r.converged;
    });
    if (!interface_ok) return false;
    // 3. Every part's BLCP with q_p + A_{p,I} lambda_I, along the step to the interface's answer
    //    while phi does not decrease enough (the slope w_I . step is <= 0, see the header).
    step_i_ = lambda_i_ - current_i_;
    const double slope = accepted_any ? w_i_.dot(step_i_) : 0.0;
    for (double t = 1;; t *= 0.5) {
      if (t < kMinStep || (t < 1 && ++halvings > max_halvings)) return false;
      if (t == 1) trial_i_ = lambda_i_;
      else trial_i_ = current_i_ + t * step_i_;
      if (!solve_parts(trial_i_)) return false;
      // 4. A full step that changes no part's sets: S and q~ were those of the final sets.
      const bool settled = t == 1 && std::all_of(parts_.begin(), parts_.end(),
                                                 [](const Part& p) { return p.trial_state == p.used; });
      if (settled) {
        for (const Part& p : parts_)
          for (std::size_t j = 0; j < p.rows.size(); ++j) {
            lambda[p.rows[j]] = p.trial_lambda[j];
            state[p.rows[j]] = p.trial_state[j];
          }
        for (int k = 0; k < interface_rows(); ++k) {
          lambda[interface_row_[k]] = lambda_i_[k];
          state[interface_row_[k]] = state_i_[k];
        }
        return true;
      }
      double roundoff = 0, f = 0;
      serial(kSubsystemPhase, [&] { f = objective(trial_i_, roundoff); });
      if (accepted_any && !(f <= phi + kArmijo * t * slope + roundoff)) continue;
      // Accepted: the trial answer becomes the current one; parts whose sets changed redo step 1.
      accepted_any = true;
      phi = f;
      current_i_ = trial_i_;
      for (int k = 0; k < interface_rows(); ++k) w_i_[k] = w_[interface_row_[k]];
      for (Part& p : parts_) {
        p.lambda.swap(p.trial_lambda);
        p.state.swap(p.trial_state);
        if (p.state == p.used) continue;
        p.used = p.state;
        for (std::size_t j = 0; j < p.used.size(); ++j) p.used_free[j] = p.used[j] == RowState::Free;
        p.refresh = true;
      }
      break;
    }
  }
  return false;
}

void SubstructuredIsland::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) { apply_a(*s_, x, du_, y); }

bool SubstructuredIsland::factor(const std::vector<char>& free) {
  for_parts(kSchurPhase, [&](Part& p) {
    for (std::size_t j = 0; j < p.rows.size(); ++j) p.free[j] = free[p.rows[j]];
    p.ok = factor_part(p, p.free);
  });
  if (std::any_of(parts_.begin(), parts_.end(), [](const Part& p) { return !p.ok; })) return false;
  serial(kSchurPhase, [&] { assemble_schur(); });
  for (int t = 0; t < interface_rows(); ++t) free_i_[t] = free[interface_row_[t]];
  return interface_.prepare(free_i_) >= 0;
}

void SubstructuredIsland::solve(Eigen::VectorXd& x) {
  // Block elimination on the free rows: y_p = A_pp^-1 x_p; S~ d = x_I - sum_p A_{I,p} y_p;
  // x_p = y_p - A_pp^-1 A_{p,I} d. Not exact (Woodbury, S~): the coupled step refines against A.
  const IslandSystem& s = *s_;
  for_parts(kCoupledPhase, [&](Part& p) {
    const std::vector<char>& f = p.a.free();
    for (std::size_t j = 0; j < p.rows.size(); ++j) p.x[j] = f[j] ? x[p.rows[j]] : 0.0;
    p.a.solve(p.x);
    p.u.setZero();
    for (const auto& [j, slot, kb] : p.coupling)
      if (f[j]) p.u.segment<6>(6 * kb) += s.mjac[p.rows[j]][slot] * p.x[j];
    for (std::size_t a = 0; a < p.touch.size(); ++a)
      p.y[a] = s.jac[interface_row_[p.touch[a]]][p.touch_slot[a]].dot(p.u.segment<6>(6 * p.touch_body[a]));
  });
  serial(kCoupledPhase, [&] {
    for (int t = 0; t < interface_rows(); ++t) g_i_[t] = free_i_[t] ? x[interface_row_[t]] : 0.0;
    for (const Part& p : parts_)
      for (std::size_t a = 0; a < p.touch.size(); ++a)
        if (free_i_[p.touch[a]]) g_i_[p.touch[a]] -= p.y[a];
    interface_.solve(g_i_);
    for (int t = 0; t < interface_rows(); ++t)
      if (free_i_[t]) x[interface_row_[t]] = g_i_[t];
  });
  for_parts(kCoupledPhase, [&](Part& p) {
    const std::vector<char>& f = p.a.free();
    interface_velocity(p, g_i_, &free_i_, p.u);
    p.b.setZero();
    for (const auto& [j, slot, kb] : p.coupling)
      if (f[j]) p.b[j] += s.jac[p.rows[j]][slot].dot(p.u.segment<6>(6 * kb));
    p.a.solve(p.b);
    for (std::size_t j = 0; j < p.rows.size(); ++j)
      if (f[j]) x[p.rows[j]] = p.x[j] - p.b[j];
  });
}

SubIslandStats SubstructuredIsland::stats(double wall_ms) const {
  SubIslandStats out;
  out.phase_ms = serial_ms_;
  out.critical_ms = wall_ms - accounted_ms_ + span_ms_;
  out.other_ms = wall_ms - accounted_ms_;
  out.loop_iterations = loop_iterations_;
  out.blcp_iterations = interface_iterations_;
  out.factorizations = interface_.factorizations();
  out.newton = interface_newton_;
  for (const Part& p : parts_) {
    for (int k = 0; k < kPhaseCount; ++k) out.phase_ms[k] += p.phase_ms[k];
    out.blcp_iterations += p.iterations;
    out.factorizations += p.a.factorizations();
    out.newton = out.newton || p.newton;
  }
  return out;
}

}  // namespace rbpart
