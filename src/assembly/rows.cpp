#include "assembly/rows.hpp"

#include <limits>

namespace rbpart {

void Rows::clear() {
  body.clear();
  jac.clear();
  q.clear();
  lo.clear();
  hi.clear();
  sigma.clear();
  kind.clear();
  normal_of.clear();
  mu.clear();
  key.clear();
  lambda.clear();
  state.clear();
}

int Rows::add(RowKind k, int body0, int body1, std::uint64_t row_key) {
  const double inf = std::numeric_limits<double>::infinity();
  body.push_back({body0, body1});
  jac.push_back({Vec6::Zero(), Vec6::Zero()});
  q.push_back(0);
  lo.push_back(k == RowKind::Normal ? 0.0 : -inf);
  hi.push_back(inf);
  sigma.push_back(0);
  kind.push_back(k);
  normal_of.push_back(-1);
  mu.push_back(0);
  key.push_back(row_key);
  lambda.push_back(0);
  state.push_back(k == RowKind::Normal ? RowState::Lower : RowState::Free);
  return static_cast<int>(q.size()) - 1;
}

}  // namespace rbpart
