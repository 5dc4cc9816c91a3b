// Constraint rows (assembly/rows.hpp): a new row is the zero row of its kind, whose bounds are
// docs/design.md#dynamics's (normal [0, inf), friction and joint (-inf, inf)), with lambda = 0
// feasible and its index set the one that lambda = 0 is in; clear() empties every field.
#include "assembly/rows.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace rbpart {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Every per-row field has one entry per row.
void expect_sizes(const Rows& rows, std::size_t n) {
  EXPECT_EQ(rows.size(), n);
  for (std::size_t size : {rows.body.size(), rows.jac.size(), rows.q.size(), rows.lo.size(), rows.hi.size(),
                           rows.sigma.size(), rows.kind.size(), rows.normal_of.size(), rows.mu.size(),
                           rows.key.size(), rows.lambda.size(), rows.state.size()})
    EXPECT_EQ(size, n);
}

TEST(Rows, NewRowsAreZeroRowsWithTheirKindsBounds) {
  Rows rows;
  const RowKind kinds[] = {RowKind::Normal, RowKind::Friction, RowKind::Joint};
  for (int i = 0; i < 3; ++i) EXPECT_EQ(rows.add(kinds[i], i, i - 1, 100 + i), i);
  expect_sizes(rows, 3);
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(rows.kind[i], kinds[i]);
    EXPECT_EQ(rows.body[i][0], i);
    EXPECT_EQ(rows.body[i][1], i - 1);
    EXPECT_EQ(rows.key[i], 100u + i);
    EXPECT_TRUE(rows.jac[i][0].isZero() && rows.jac[i][1].isZero());
    EXPECT_EQ(rows.q[i], 0.0);
    EXPECT_EQ(rows.sigma[i], 0.0);
    EXPECT_EQ(rows.mu[i], 0.0);
    EXPECT_EQ(rows.normal_of[i], -1);
    EXPECT_EQ(rows.lambda[i], 0.0);
    const bool normal = kinds[i] == RowKind::Normal;
    EXPECT_EQ(rows.lo[i], normal ? 0.0 : -kInf);
    EXPECT_EQ(rows.hi[i], kInf);
    // lambda = 0 sits at a normal row's lower bound and inside the others' bounds.
    EXPECT_EQ(rows.state[i], normal ? RowState::Lower : RowState::Free);
  }
  rows.clear();
  expect_sizes(rows, 0);
  EXPECT_EQ(rows.add(RowKind::Joint, 0, -1, 7), 0);
  expect_sizes(rows, 1);
}

}  // namespace
}  // namespace rbpart
