#include "solve/monolithic.hpp"

#include <numeric>

namespace rbpart {

void MonolithicSystem::assign(const IslandSystem& s) {
  bodies_.resize(s.bodies);
  rows_.resize(s.rows);
  std::iota(bodies_.begin(), bodies_.end(), 0);
  std::iota(rows_.begin(), rows_.end(), 0);
  body_masses(s, mass_);
  n_.assign(s, bodies_, rows_, mass_);
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
