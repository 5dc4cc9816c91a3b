#pragma once
// Validate builds (CMake option RBPART_VALIDATE) re-check state that is kept incrementally — each
// partitioner's result, the refiners' gains, cut and part sizes, factorisations kept across solves —
// against a recomputation from scratch, where the state is used. A checker returns "" or the
// violation in words (check_partition, RefineState::violation, solve_violation); RBPART_CHECK throws
// std::logic_error naming file:line and the violation. In other builds the checker is not called and
// no code is emitted, but the call is still compiled, so it cannot rot.
#include <stdexcept>
#include <string>

#ifndef RBPART_VALIDATE
#define RBPART_VALIDATE 0
#endif

namespace rbpart {

inline constexpr bool kValidate = RBPART_VALIDATE;

inline void throw_violation(const std::string& violation, const char* file, int line) {
  if (!violation.empty()) throw std::logic_error(std::string(file) + ":" + std::to_string(line) + ": " + violation);
}

}  // namespace rbpart

#define RBPART_CHECK(violation)                                                                  \
  do {                                                                                           \
    if constexpr (::rbpart::kValidate) ::rbpart::throw_violation(violation, __FILE__, __LINE__); \
  } while (false)
