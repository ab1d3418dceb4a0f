// `latticedyn batch`: the cases of a batch file over MPI_COMM_WORLD split into groups, each group
// solving its chains of cases, every finished case recorded at once; resumable; one table at the end.
#pragma once

#include "drivers/batch_log.hpp"
#include "io/batch_reader.hpp"

#include <petscsys.h>

#include <map>
#include <string>
#include <vector>

namespace latticedyn {

struct BatchOptions {
  std::string output_directory;  ///< overrides the batch file's output.directory when set
  int groups = 0;                ///< 0: one group per rank
  bool retry_failed = false;     ///< on resume, solve recorded failures again
  bool quiet = false;            ///< no per-case progress lines
};

struct BatchSummary {
  int cases = 0, ok = 0, failed = 0, skipped = 0;  ///< skipped: finished by an earlier run
  double wall_seconds = 0.0;
  std::string csv_path, h5_path;
  std::vector<std::string> columns;  ///< of the table (numbers), in order
  std::map<int, CaseRecord> records; ///< all of them, on every rank
};

/// The static equilibrium of the model with the numbers at `paths` set to `to`, continued from a
/// known equilibrium `state` of the same model with them at `from`: the values move along the
/// straight line in about `steps` parts (shorter where a solve fails), each solve starting from the
/// secant prediction of the two before. On `comm`; the state is the full vector on every rank.
struct Continuation {
  bool ok = false;
  std::vector<double> state;
  int solves = 0, newton_iterations = 0;
  std::string error;
};
Continuation continue_equilibrium(const std::string& model_path, const std::vector<std::string>& paths,
                                  const std::vector<double>& from, const std::vector<double>& to,
                                  const std::vector<double>& state, int steps, MPI_Comm comm);

/// Runs the batch collectively on `world`; every rank returns the same summary. Throws
/// InputError for a batch that cannot start (unknown joint in a measure, ranks that do not split
/// into equal groups, an output folder holding another batch).
BatchSummary run_batch(const BatchSpec& spec, const BatchOptions& options, MPI_Comm world);

}  // namespace latticedyn
