#include "solve/monolithic.hpp"

#include <numeric>

namespace rbpart {

void MonolithicSystem::assign(const IslandSystem& s, int dense_max_bodies) {
  std::vector<int> bodies(s.bodies), rows(s.rows);
  std::iota(bodies.begin(), bodies.end(), 0);
  std::iota(rows.begin(), rows.end(), 0);
  n_.assign(s, std::move(bodies), std::move(rows), body_masses(s), dense_max_bodies);
  h_.resize(6 * s.bodies);
}

bool MonolithicSystem::factor(const Piece& piece) { return n_.factor(piece); }

void MonolithicSystem::solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  h_.setZero();
  n_.add_rhs(g, h_);
  n_.solve(h_.data());
  x.resize(g.size());
  n_.recover(g, h_, x);
}

}  // namespace rbpart
