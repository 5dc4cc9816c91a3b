#include "core/validate.hpp"
#include "refine/refine.hpp"

namespace rbpart {

void refine_partition(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition) {
  if (params.refiner == RefinerKind::None) return;
  thread_local RefineState state;  // buffers kept across calls (no allocation once warmed up)
  state.reset(graph, params, partition);
  const WeightSum input_cut = state.cut();  // counted from scratch by reset()
  switch (params.refiner) {
    case RefinerKind::Kl: refine_kernighan_lin(state); break;
    case RefinerKind::Fm: refine_fiduccia_mattheyses(state, false); break;
    case RefinerKind::FmRollback: refine_fiduccia_mattheyses(state, true); break;
    case RefinerKind::None: break;
  }
  RBPART_CHECK(state.violation());
  RBPART_CHECK(state.cut() <= input_cut ? std::string() :
               "refinement raised the edge cut from " + std::to_string(input_cut) + " to " + std::to_string(state.cut()));
}

}  // namespace rbpart
