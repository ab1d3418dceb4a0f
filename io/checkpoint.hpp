// Checkpoints in a results file: what continues a run exactly from an accepted step (the
// coordinates, rates, acceleration estimate, step size, counters and the output schedule).
#pragma once

#include "io/hdf5_file.hpp"
#include "timestepping/dynamic_settings.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace latticedyn {

/// One checkpoint, as /checkpoints/<step> of a results file holds it (docs/output-format.md).
/// Vectors are in model order (DofMap::to_model_order), the same on any number of ranks; the
/// velocities in the integrator's own parametrization (`velocities_are_rates`).
struct Checkpoint {
  double time = 0.0;
  ResumePoint resume;
  std::string integrator;            ///< "generalized_alpha" or "baumgarte"
  bool velocities_are_rates = true;  ///< rotation-vector rates; false: velocity variables
  std::vector<double> coordinates, velocities, accelerations;
  long outputs_written = 0;          ///< output steps in the file when it was taken
  double last_output = 0.0;          ///< time of the last of them
  double next_output = 0.0;          ///< when the next output was due
};

/// Writes `c` as the group /checkpoints/<step> of an open results file (replacing one of the
/// same step). Throws std::runtime_error naming the file and HDF5's reason.
void write_checkpoint(hid_t file, const Checkpoint& c, const io::Hdf5Context& ctx);

/// Removes the checkpoints taken after time `t` (a run continued from an earlier one rewrites
/// them).
void remove_checkpoints_after(hid_t file, double t, const io::Hdf5Context& ctx);

/// The checkpoint of step `step` of a results file; -1: the last one. Throws std::runtime_error
/// naming the file and what is wrong (no such file, not a results file, no checkpoint, no
/// checkpoint at that step: with the steps it has).
Checkpoint read_checkpoint(const std::filesystem::path& file, long step);

}  // namespace latticedyn
