// BodySpaceSystem's assembly in chunks (the substructured backend's parts): block column by block
// column, every block summed in the order of the serial run-by-run assembly, so N and everything
// solved with it are the same bit for bit in any number of chunks.
#include "solve/body_space.hpp"
#include "solve/island_chunks.hpp"
#include "solve/random_blcp.hpp"
#include "solve/random_piece.hpp"

#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

namespace rbpart {
namespace {

using namespace rbpart::testing;

TEST(BodySpaceSystem, AssemblyInChunksIsTheSerialOneBitForBit) {
  std::mt19937 rng(11);
  for (const bool ties : {false, true}) {
    IslandOptions options;
    options.rows = 600;
    options.bodies = 60;
    options.joint_fraction = 0;  // contacts only: runs of a contact's rows on two bodies or one
    RandomIsland island;
    random_contact_island(rng, options, island);
    const IslandSystem& s = island.system;
    std::vector<int> bodies(s.bodies), rows(s.rows);
    std::iota(bodies.begin(), bodies.end(), 0);
    std::iota(rows.begin(), rows.end(), 0);
    std::vector<Mat6> mass;
    body_masses(s, mass);
    const Piece piece = random_piece(s, rng, ties);
    Eigen::VectorXd g(s.rows);
    for (int j = 0; j < s.rows; ++j) g[j] = std::uniform_real_distribution<double>(-1, 1)(rng);

    BodySpaceSystem serial;
    serial.assign(s, bodies, rows, mass);
    serial.assemble(piece);
    ASSERT_TRUE(serial.factor_assembled());
    Eigen::VectorXd h = Eigen::VectorXd::Zero(6 * s.bodies);
    serial.add_rhs(g, h);
    serial.solve(h.data());
    for (const int count : {3, 16}) {
      BodySpaceSystem chunked;
      chunked.assign(s, bodies, rows, mass);
      IslandChunks chunks;
      chunks.set_count(count);
      chunked.assemble(piece, &chunks);
      ASSERT_TRUE(chunked.factor_assembled());
      Eigen::VectorXd u = Eigen::VectorXd::Zero(6 * s.bodies);
      chunked.add_rhs(g, u);
      chunked.solve(u.data());
      EXPECT_EQ(u, h) << count << " chunks, ties " << ties;
    }
  }
}

}  // namespace
}  // namespace rbpart
