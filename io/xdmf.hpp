// The XDMF description ParaView reads next to the results .h5: a temporal collection of line-cell
// grids whose heavy data are hyperslabs of the /viz datasets, and the atomic file replacement.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace latticedyn::io {

/// What the XDMF refers to. The .h5 is addressed by file name only, so the folder can be moved.
struct XdmfLayout {
  std::string h5_name;  ///< e.g. "results.h5"
  std::string title;    ///< name of the temporal collection
  int points = 0;       ///< rows of /viz/points per step
  int lines = 0;        ///< rows of /viz/lines
};

/// XDMF 2 document for ParaView's "XDMF Reader" (the Xdmf3 readers misread multi-dimensional
/// hyperslabs, see docs/output-format.md): a temporal collection with one Uniform grid per step,
/// step k selecting entry k of /viz/points, /viz/displacement and /viz/axial_force, plus the
/// static /viz/lines, /viz/body and /viz/element. Each grid is formatted once; text() only
/// splices in the current number of steps, which every HDF DataItem declares.
class XdmfDocument {
 public:
  explicit XdmfDocument(XdmfLayout layout) : layout_(std::move(layout)) {}
  /// Adds the grid of the next step (entry steps() of the time series) at `time`.
  void add_step(double time);
  int steps() const { return steps_; }
  /// The complete document for the steps added so far.
  std::string text() const;

 private:
  XdmfLayout layout_;
  std::string grids_;              // all grids, the number of steps left out at gaps_
  std::vector<std::size_t> gaps_;  // offsets into grids_ where the number of steps belongs
  int steps_ = 0;
};

/// Writes `text` to path + ".tmp" and renames it over `path`: readers see the old or the new file,
/// never a partial one (rename within a directory is atomic). Throws std::runtime_error naming
/// the path and the OS reason.
void replace_file(const std::filesystem::path& path, const std::string& text);

/// The shortest decimal text that reads back to the same double.
std::string format_double(double x);

}  // namespace latticedyn::io
