// The commands of the latticedyn executable: check (validate and describe a model), static
// (equilibrium), run (equilibrium if asked, then dynamics). Each returns the process exit code.
#pragma once

#include "io/model_reader.hpp"

#include <petscsys.h>

#include <string>

namespace latticedyn {

enum ExitCode : int { kSuccess = 0, kSolverFailure = 1, kInputError = 2, kInternalError = 3 };

struct CommandOptions {
  std::string model_path;
  std::string output_directory;  ///< overrides output.directory when set
};

int command_check(const Simulation& sim, MPI_Comm comm);
int command_static(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
int command_run(Simulation& sim, const CommandOptions& options, MPI_Comm comm);

}  // namespace latticedyn
