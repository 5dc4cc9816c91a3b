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

void Rows::resize(std::size_t n) {
  body.resize(n);
  jac.resize(n);
  q.resize(n);
  lo.resize(n);
  hi.resize(n);
  sigma.resize(n);
  kind.resize(n);
  normal_of.resize(n);
  mu.resize(n);
  key.resize(n);
  lambda.resize(n);
  state.resize(n);
}

void Rows::set(int r, RowKind k, int body0, int body1, std::uint64_t row_key) {
  const double inf = std::numeric_limits<double>::infinity();
  body[r] = {body0, body1};
  jac[r] = {Vec6::Zero(), Vec6::Zero()};
  q[r] = 0;
  lo[r] = k == RowKind::Normal ? 0.0 : -inf;
  hi[r] = inf;
  sigma[r] = 0;
  kind[r] = k;
  normal_of[r] = -1;
  mu[r] = 0;
  key[r] = row_key;
  lambda[r] = 0;
  state[r] = k == RowKind::Normal ? RowState::Lower : RowState::Free;
}

int Rows::add(RowKind k, int body0, int body1, std::uint64_t row_key) {
  const int r = static_cast<int>(size());
  resize(size() + 1);
  set(r, k, body0, body1, row_key);
  return r;
}

}  // namespace rbpart
