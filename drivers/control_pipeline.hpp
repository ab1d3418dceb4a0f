// `latticedyn control`: the quasi-static optimal control of thesis chapter 6 end to end: mapping
// batch, surface fits both ways, optimal end-point trajectory (TAO), control table, verification run.
#pragma once

#include "io/control_reader.hpp"

#include <petscsys.h>

#include <string>

namespace latticedyn {

struct ControlOptions {
  std::string output_directory;  ///< overrides the control file's output.directory when set
  int groups = 0;                ///< rank groups of the mapping batch
};

struct ControlSummary {
  bool ok = false;
  std::string message;  ///< what failed, or the report's path
  double tracking_max = 0, tracking_rms = 0, residual_sway = 0, final_offset = 0;
};

/// Collective on `world`: the mapping batch runs on all ranks; the rest on rank 0 alone (small
/// dense work and one crane run), so the outcome does not depend on the number of ranks. Every
/// rank returns the same summary. Throws InputError for input problems.
ControlSummary run_control(const ControlSpec& spec, const ControlOptions& options, MPI_Comm world);

}  // namespace latticedyn
