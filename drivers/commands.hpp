// The commands of the latticedyn executable: check (validate and describe a model), static
// (equilibrium), run (equilibrium if asked, then dynamics), modes (natural frequencies). Each
// returns the process exit code.
#pragma once

#include "io/model_reader.hpp"

#include <petscsys.h>

#include <string>

namespace latticedyn {

enum ExitCode : int { kSuccess = 0, kSolverFailure = 1, kInputError = 2, kInternalError = 3 };

struct CommandOptions {
  std::string model_path;
  std::string output_directory;  ///< overrides output.directory when set
  int modes = 6;                 ///< modes: how many of the lowest natural modes
};

int command_check(const Simulation& sim, MPI_Comm comm);
int command_static(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
int command_run(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
/// Static equilibrium, then the lowest natural frequencies and modes about it (SLEPc); the modes
/// are written as the output steps 1..n (the equilibrium plus the scaled mode) and as a CSV.
int command_modes(Simulation& sim, const CommandOptions& options, MPI_Comm comm);

}  // namespace latticedyn
