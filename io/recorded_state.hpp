// Reading a recorded state back: the global coordinate vector a results file stores per output
// step (/state/coordinates), so a model can start where an earlier run or static solve ended.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace latticedyn {

struct RecordedState {
  std::vector<double> coordinates;  ///< in model order (DofMap::to_model_order), any rank count
  double time = 0.0;                ///< the step's time
  long step = 0;                    ///< the step read (0-based)
  long steps = 0;                   ///< steps in the file
};

/// A step that the file does not hold (the file itself is fine).
struct RecordedStepOutOfRange : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The coordinates of output step `step` (negative: counted from the end, -1 = the last) of a
/// latticedyn results file. Throws std::runtime_error naming the file and what is wrong (no such
/// file, not a results file, a file written before states were recorded); RecordedStepOutOfRange
/// for a step the file does not hold.
RecordedState read_recorded_state(const std::filesystem::path& file, long step);

}  // namespace latticedyn
