#pragma once
// Runs another program (found on PATH) and collects what it prints: for the few places terralod
// drives other tools (a batch scheduler's commands).

#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

struct ProgramOutput {
  int exitStatus = 0;  ///< 128 + signal when it was killed
  std::string out, err;
};

/// Fails only when the program cannot be started (not found, not executable).
Result<ProgramOutput> runProgram(const std::vector<std::string>& argv);

}  // namespace terralod
