#include "solve/residual.hpp"

#include "solve/bounds.hpp"

#include "solve/island_system.hpp"
#include "solve/solve.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rbpart {

double scaled_natural_map_residual(const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                                   const Eigen::VectorXd& diag, const Eigen::VectorXd& lo,
                                   const Eigen::VectorXd& hi, const Eigen::VectorXd& q) {
  if (lambda.size() == 0) return 0;
  const double scale = std::max(max_abs(q), 1e-12);
  double r = 0;
  for (Eigen::Index j = 0; j < lambda.size(); ++j) {
    const double projected = std::clamp(lambda[j] - w[j] / diag[j], lo[j], std::max(lo[j], hi[j]));
    const double rj = std::abs(lambda[j] - projected) * diag[j];
    // A NaN anywhere must show, not vanish in std::max.
    if (!(rj <= r)) r = std::isnan(rj) ? std::numeric_limits<double>::infinity() : rj;
  }
  return r / scale;
}

void store_island_solution(const IslandSystem& s, const Eigen::VectorXd& lambda, const std::vector<RowState>& state,
                           Rows& rows) {
  for (int r = 0; r < s.rows; ++r) {
    const int g = s.global_rows[r];
    rows.lambda[g] = lambda[r];
    rows.state[g] = state[r];
    rows.lo[g] = s.lo[r];
    rows.hi[g] = s.hi[r];
  }
}

double island_residual(IslandSystem& s, const Eigen::VectorXd& lambda, Eigen::VectorXd& du, Eigen::VectorXd& w) {
  set_friction_bounds(s.coupling(), lambda, s.lo, s.hi);
  apply_a(s, lambda, du, w);
  w += s.q;
  return scaled_natural_map_residual(lambda, w, s.diag, s.lo, s.hi, s.q);
}

double natural_map_residual(const Rows& rows, const Bodies& bodies, const Islands& islands) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  std::vector<double> residual(islands.count(), 0.0);
  parallel_for_each(islands.count(), [&](std::size_t i) {
    IslandSystem s;
    s.gather(rows, bodies, islands, static_cast<int>(i), local_row);
    Eigen::VectorXd lambda(s.rows), w, du;
    for (int r = 0; r < s.rows; ++r) lambda[r] = rows.lambda[s.global_rows[r]];
    residual[i] = island_residual(s, lambda, du, w);
  });
  return residual.empty() ? 0.0 : *std::max_element(residual.begin(), residual.end());
}

}  // namespace rbpart
