// MIX (docs/design.md#partition): MinDP growth while |part| < τ_mix · nmax, then the candidate of maximum
// gain,
//
//   gain(β) = C_in(β) − C_out(β) = 2 C_in(β) − deg(β),
//
// where C_in(β) counts the constraints (edge weights) between β and bodies already in the part, and C_out(β)
// = deg(β) − C_in(β) those between β and every other dynamic body (unassigned or in earlier parts);
// constraints with static bodies are not edges and do not count (docs/design.md#graph). Ties go to the lowest
// index. C_in is kept incrementally by the engine (each joining body adds its edge weights to its
// candidates), so a candidate's gain only rises within a part and it is re-queued with each rise.
#include "partition/grow.hpp"

namespace rbpart {

namespace {

struct MixRule : DegreeOrder {
  GrowState& grow;
  double switch_size;  // τ_mix · nmax
  bool by_gain = false;

  MixRule(GrowState& s, double tau_mix) : DegreeOrder(s, +1), grow(s), switch_size(tau_mix * s.nmax) {}

  std::int64_t key(int u) const {
    const GrowState::Node& c = grow.node[u];
    return by_gain ? std::int64_t{c.degree} - 2 * std::int64_t{c.conn} : seed_key(u);
  }
  bool rekeys() const { return by_gain; }
  void begin(int) { by_gain = false; }
  // Once the part is large enough, every queued candidate's key changes to its gain.
  void joined(int) {
    if (by_gain || grow.size < switch_size) return;
    by_gain = true;
    grow.heap.clear();
    for (int u : grow.candidates)
      if (grow.is_candidate(u)) grow.push(key(u), u);
  }
};

}  // namespace

void partition_island_mix(GrowState& s, const PartitionParams& params, const int* nodes, int count) {
  MixRule rule(s, params.tau_mix);
  grow_island(s, rule, nodes, count);
}

}  // namespace rbpart
