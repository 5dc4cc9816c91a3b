#pragma once
// The monolithic backend of the Newton solver's linear algebra (linear_system.hpp, DESIGN.md §3):
// the whole island factored in body space (body_space.hpp: N u = h over every body and row,
// factored by the block sparse LU of block_lu.hpp, tied or not).
#include "solve/body_space.hpp"
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"

#include <Eigen/Core>

#include <vector>

namespace rbpart {

class MonolithicSystem final : public LinearSystem {
 public:
  // Keeps a reference to `system`, which must outlive the solves, and builds N's pattern.
  void assign(const IslandSystem& system);
  bool factor(const Piece& piece) override;
  void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) override;

 private:
  BodySpaceSystem n_;
  Eigen::VectorXd h_;
  std::vector<int> bodies_, rows_;  // 0..n-1: N holds every body and row of the island
  std::vector<Mat6> mass_;
};

}  // namespace rbpart
