// Results of a run on disk: one HDF5 file with the time series of the model state, an XDMF file
// beside it that ParaView opens as a time series of line cells, and a CSV file of probe joints.
#pragma once

#include "assembly/energy_ledger.hpp"
#include "assembly/model_state.hpp"

#include <mpi.h>

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace latticedyn {

/// The longest output base name (bytes): with "_probes.csv" it stays under the 255 bytes a file
/// name may have.
inline constexpr std::size_t kMaxBaseNameBytes = 200;

/// Why `name` cannot be an output base name, or nothing: empty, longer than kMaxBaseNameBytes,
/// starting with '.', or holding '/', '\\', ':' (the XDMF addresses data as "file:/path") or
/// control characters. Names never leave their folder.
std::optional<std::string> base_name_problem(const std::string& name);

struct Checkpoint;

/// A results file continued by a run that resumes from one of its checkpoints.
struct ResultContinuation {
  long steps = 0;     ///< output steps kept (those written up to the checkpoint)
  double time = 0.0;  ///< the checkpoint's time: later checkpoints are removed
};

/// Where and what to write. Files: <directory>/<base_name>.h5, <base_name>.xdmf and
/// <base_name>_probes.csv.
struct ResultWriterOptions {
  std::string directory;               ///< created if missing; empty: the working directory
  std::string base_name = "results";   ///< see base_name_problem
  std::vector<int> probe_joints;       ///< model joint indices written to the CSV, in this order
  /// Set: the files exist (written for the same model) and are continued after their first
  /// `steps` output steps instead of created; later steps, CSV rows and checkpoints are dropped.
  std::optional<ResultContinuation> continuation;
  /// The XDMF's "members" as one block per body, named after it (up to io::kMaxNamedBodies
  /// bodies); else one block of all, a `body` array telling them apart. Off by default: the
  /// XDMF grows by a grid per body and output step (for the reduced crane about four times the
  /// text, its dynamics a quarter slower).
  bool body_blocks = false;
  /// The ranks writing the files. One rank (the default, MPI_COMM_SELF): it writes everything from
  /// the whole state. Several: the .h5 is written collectively through MPI-IO, each rank its share
  /// of every large series (its run of elements with their drawn cells and points, an even share
  /// of the blocks, joints and constraints), rank 0 the rest, the XDMF and the probe CSV; every
  /// rank then calls every method with the whole state (SystemAssembler::gather on all ranks).
  MPI_Comm comm = MPI_COMM_SELF;
};

/// The most utilized member over the steps written (by utilization where the materials give a
/// yield stress, else by von Mises stress): which, when and how much.
struct MemberPeak {
  int element = -1;         ///< model element index
  int member = 0;           ///< the member within it (a super truss's members; 0 otherwise)
  double time = 0.0;
  double von_mises = 0.0;   ///< Pa
  double utilization = std::numeric_limits<double>::quiet_NaN();  ///< von Mises / yield stress
  SectionForces end1, end2;  ///< its resultants then
};

/// "body 'boom' element 12 (member 7 of its super truss): utilization 0.83 (von Mises 295 MPa) at
/// t = 12.3 s" for a run's summary.
std::string describe_member_peak(const Model& model, const MemberPeak& peak);

/// Writes one output time per append(). The layout, in full, is in docs/output-format.md; in short
/// (T = steps written, every real in IEEE double, SI units):
///
///   /                        attributes title, generator = "latticedyn", format_version = 4
///   /model/...               static description: block indices, labels, names, types, counts
///   /time                    T
///   /blocks/position         T x nTrans x 3   inertial, of every translation block (fixed too)
///   /blocks/velocity         T x nTrans x 3   inertial
///   /blocks/rotation_vector  T x nRot x 3     rotation_vector(R), |phi| <= pi
///   /blocks/rotation_matrix  T x nRot x 3 x 3 R (block frame -> inertial), row-major
///   /blocks/angular_velocity T x nRot x 3     block (body) frame
///   /blocks/scalar_position, /blocks/scalar_velocity  T x nScalar
///   /joints/position, /joints/velocity        T x nJoints x 3, inertial
///   /constraints/multipliers T x nRows        all constraints' rows, in constraint order
///   /constraints/violation   T x nConstraints max |g| of each constraint
///   /constraints/position, reaction_force, reaction_moment  T x nConstraints x 3: the wrench
///                            on each constraint's second joint (ModelState::constraint_reaction)
///   /elements/axial_force    T x nElements    NaN for elements without one
///   /energy                  T x 3            kinetic, gravity potential, strain
///   /energy_total            T
///   /drives/value            T x nDrives      each drive's value (rest lengths, angles)
///   /viz/points T x nPoints x 3;  /viz/axial_force T x nCells (a cell: one drawn polyline)
///   /viz/section_forces T x nCells x 12 (N, Qy, Qz, T, My, Mz at end 1, then end 2 of the cell's
///   member, element frame), /viz/von_mises, /viz/utilization, /viz/bending_moment,
///   /viz/shear_force, /viz/torque T x nCells (the member's largest; NaN for no member)
///   /viz/joint_axis_x, _y, _z T x nJoints x 3 (the joints' frames, for glyphs)
///   /viz/cells (XDMF mixed topology: 2, n, n points per cell), /viz/cell_offsets nCells + 1,
///   /viz/body nCells, /viz/element nCells, /viz/member nCells (the member or polyline within the
///   element), /viz/lines nLines x 2 and /viz/line_cell nLines (the cells' segments),
///   /viz/joint_vertices, /viz/constraint_vertices, /viz/body_cells (each body's cells numbered
///   from its first point, for the XDMF's body blocks) (static)
///
/// A time series whose row would be empty (no constraints, no rotation blocks, ...) is not
/// created. Time series are chunked along time and extended by one entry per append; the file is
/// flushed after each of the first 16 appends and then at most once a second (and on close), the
/// XDMF replaced atomically after each flush, so a run that stops (crash, kill) leaves readable
/// files holding every append up to a second before; a solver failure closes them complete.
///
/// With one rank in ResultWriterOptions::comm the writer is serial: use it on the rank the state
/// is gathered to. With several, each method is collective over them (see there). Not
/// thread-safe. The Model must outlive the writer. A moved-from writer may only be destroyed or
/// assigned to.
class ResultWriter {
 public:
  /// Creates the directory, the HDF5 file (truncating an existing one) with its static part, and
  /// the CSV with its header (with a continuation: opens them and cuts them back). Throws std::runtime_error naming the path and the operating-system
  /// or HDF5 reason when a file cannot be created, std::invalid_argument for a bad base name,
  /// probe joint or draw sequence.
  ResultWriter(const Model& model, ResultWriterOptions opts);
  /// Calls close(); an error there is reported on std::cerr, as a destructor cannot throw.
  ~ResultWriter();
  ResultWriter(ResultWriter&&) noexcept;
  ResultWriter& operator=(ResultWriter&&) noexcept;
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  /// Writes one output time: extends every time series by one entry, flushes the HDF5 file and
  /// then replaces the XDMF when due (above), and appends (and flushes) one CSV row. The first call fixes the
  /// visualisation geometry (points per element). Throws std::runtime_error on an I/O failure or
  /// when an element's number of axis points changes (nothing is written then),
  /// std::invalid_argument for a state of another model, std::logic_error after close() or after
  /// an append that failed writing the .h5 (the files keep every step completed before it).
  void append(const ModelState& state);
  /// The energy account the next append() records, for models with a hydraulic circuit
  /// (EnergyLedger::applies): its works go into /hydraulics/energy and the probe CSV (zero until
  /// set); ignored for other models.
  void set_energy_account(const EnergyAccount& account);

  /// Writes a checkpoint (io/checkpoint.hpp) after flushing every step appended so far, so that
  /// the checkpoint and the steps it counts are on disk together. Throws as append().
  void write_checkpoint(const Checkpoint& c);

  /// Flushes and closes all files. Idempotent.
  void close();

  std::filesystem::path h5_path() const;
  std::filesystem::path xdmf_path() const;
  std::filesystem::path csv_path() const;
  /// Number of completed append() calls.
  int steps_written() const;
  /// The most utilized member over the steps appended so far; none before the first append or
  /// in a model without members. The same on every rank of a collective writer.
  std::optional<MemberPeak> member_peak() const;
  /// Whether several ranks write the files together (ResultWriterOptions::comm).
  bool collective() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace latticedyn
