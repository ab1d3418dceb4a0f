// The XDMF description ParaView reads next to the results .h5: a temporal collection of polyline-cell
// grids whose heavy data are hyperslabs of the /viz datasets, and the atomic file replacement.
#pragma once

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace latticedyn::io {

/// A body drawn as a block of its own: its cells and the points they run through (rows of the
/// per-cell datasets and of /viz/points), and its entries of /viz/body_cells (its cells in the
/// mixed-topology layout of /viz/cells, numbered from its first point).
struct XdmfBody {
  std::string name{};
  int first_cell = 0, cells = 0, first_point = 0, points = 0, first_entry = 0, entries = 0;
};

/// What the XDMF refers to. The .h5 is addressed by file name only, so the folder can be moved.
struct XdmfLayout {
  std::string h5_name{};  ///< e.g. "results.h5"
  std::string title{};    ///< name of the temporal collection
  int points = 0;       ///< rows of /viz/points per step
  int cells = 0;        ///< polyline cells: rows of the per-cell datasets (/viz/body, /viz/von_mises, ...)
  int cell_entries = 0; ///< entries of /viz/cells (per cell its type, point count and points)
  int joints = 0;       ///< rows of /joints/position per step (0: no "joints" block)
  int constraints = 0;  ///< rows of /constraints/position per step (0: no "constraints" block)
  /// The constraints' names: with at most kMaxNamedConstraints of them, "constraints" holds one
  /// block per constraint, named after it (ParaView lists them by name); else one block of all.
  std::vector<std::string> constraint_names{};
  /// The drawn bodies: with 1 to kMaxNamedBodies of them, "members" holds one block per body,
  /// named after it, whose cells and points are the body's rows of the /viz datasets.
  std::vector<XdmfBody> bodies{};
  /// Whether "members" is split into named body blocks (then the writer provides /viz/body_cells).
  bool names_bodies() const;
};

/// The most constraints that get a block each; beyond, the XDMF would grow by a grid per constraint
/// and step for a list nobody browses.
inline constexpr int kMaxNamedConstraints = 64;
/// The same for bodies: a lattice of a body per bay draws as one block.
inline constexpr int kMaxNamedBodies = 64;

/// XDMF 2 document for ParaView's "XDMF Reader" (the Xdmf3 readers misread multi-dimensional
/// hyperslabs, see docs/output-format.md): a spatial collection (a multiblock dataset in ParaView)
/// of three temporal collections, the blocks "members" (polyline cells through /viz/points, a
/// mixed topology, with axial force, stresses, body and element; for up to kMaxNamedBodies bodies
/// whose cells are consecutive a
/// collection of one block per body, named after it), "joints" (a vertex per joint: velocity, frame axes, body) and
/// "constraints" (a vertex per constraint at its second joint: reaction force and moment; for up
/// to kMaxNamedConstraints constraints a collection of one block per constraint, named after
/// it), each with one Uniform grid per step selecting entry k of its time series. Blocks are collections
/// of their own, not steps of one, so their names stay the same at every time (ParaView makes
/// repeated grid names unique by numbering them). Attribute names carry their units
/// ("axial_force [N]"). A step's grids are formatted once, as pieces; a step adds only its time,
/// and text() or write() join the pieces for every step with its number, its time and the current
/// number of steps, which every HDF DataItem declares.
class XdmfDocument {
 public:
  explicit XdmfDocument(XdmfLayout layout);
  /// Adds the grid of the next step (entry steps() of the time series) at `time`.
  void add_step(double time);
  int steps() const { return steps_; }
  /// The complete document for the steps added so far.
  std::string text() const;
  /// Writes text() to `file` piece by piece, without holding it whole.
  void write(std::FILE* file) const;

 private:
  /// Text of one step's grid up to where the step's number, its time or the number of steps
  /// (a gap, filled in by text()) goes.
  struct Piece {
    enum Then { step, time, gap, end };
    std::string text;
    Then then = end;
  };
  /// One block's grids, the number of steps left out at `gaps` (offsets into `grids`), and the
  /// pieces every step's grid is made of.
  struct Block {
    std::string name;
    std::string grids;              // while formatting the pieces
    std::vector<std::size_t> gaps;  // the same
    std::vector<Piece> step_pieces;
    bool drawn = false;  // the layout has this block (its pieces are not all empty)
  };
  /// Formats one step's grids of every block (step number and time as given) into the blocks.
  void format_step(const std::string& step, const std::string& time_text);
  /// Passes the document to `out(const char*, std::size_t)` piece by piece.
  template <class Sink>
  void emit(Sink&& out) const;
  std::vector<Block*> blocks();
  XdmfLayout layout_;
  Block members_{"members", {}, {}, {}, false}, joints_{"joints", {}, {}, {}, false},
      constraints_{"constraints", {}, {}, {}, false};
  std::vector<Block> named_constraints_;  // one per constraint when they are named (XdmfLayout)
  std::vector<Block> named_bodies_;       // one per body when they are named
  std::vector<std::string> time_texts_;  // each step's time as written
  int steps_ = 0;
};

/// Writes `text` to path + ".tmp" and renames it over `path`: readers see the old or the new file,
/// never a partial one (rename within a directory is atomic). Throws std::runtime_error naming
/// the path and the OS reason.
void replace_file(const std::filesystem::path& path, const std::string& text);
/// The same with the content written by `write` to the open temporary file (write errors found
/// through ferror after it returns).
void replace_file(const std::filesystem::path& path, const std::function<void(std::FILE*)>& write);

/// The shortest decimal text that reads back to the same double.
std::string format_double(double x);

}  // namespace latticedyn::io
