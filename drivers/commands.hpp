// The commands of the latticedyn executable: check (validate and describe a model), static
// (equilibrium), run (equilibrium if asked, then dynamics), modes (natural frequencies), buckling
// (load factors), path (load-displacement path through limit points). Each returns the process exit code.
#pragma once

#include "drivers/exit_codes.hpp"
#include "io/model_reader.hpp"

#include <petscsys.h>

#include <string>

namespace latticedyn {


struct CommandOptions {
  std::string model_path;
  std::string output_directory;  ///< overrides output.directory when set
  int modes = 6;                 ///< modes, buckling: how many of the lowest modes
  int groups = 0;                ///< batch: rank groups (0: one per rank)
  bool retry_failed = false;     ///< batch: solve recorded failures again on resume
  std::string restart;           ///< run: FILE or FILE:STEP, the checkpoint to continue from
};

int command_check(const Simulation& sim, MPI_Comm comm);
int command_static(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
int command_run(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
/// The cases of a batch file (io/batch_reader.hpp) over groups of ranks; a table at the end.
/// Exit code 1 when a case failed (the table records which and why).
int command_batch(const CommandOptions& options, MPI_Comm comm);
/// The quasi-static optimal control pipeline of a control file (drivers/control_pipeline.hpp).
int command_control(const CommandOptions& options, MPI_Comm comm);
/// Static equilibrium, then the lowest natural frequencies and modes about it (SLEPc); the modes
/// are written as the output steps 1..n (the equilibrium plus the scaled mode) and as a CSV.
int command_modes(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
/// Static equilibrium under the model's loads, then the smallest load factors of linearized
/// buckling (SLEPc); the buckling modes as output steps 1..n and the factors as a CSV.
int command_buckling(Simulation& sim, const CommandOptions& options, MPI_Comm comm);
/// The static equilibrium path under the model's loads scaled by a load factor, by arc length
/// through limit points (solver.path); each point an output step, the path as a CSV.
int command_path(Simulation& sim, const CommandOptions& options, MPI_Comm comm);

}  // namespace latticedyn
