#pragma once
// Errors: bad user input (exit status 2, one line naming the problem) vs internal failure (exit 1).
#include <stdexcept>
#include <string>

namespace rbpart {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rbpart
