// ResultWriter: what goes into the results .h5 and in which order the three files are written, so
// that a run stopping at any point leaves files holding every completed append (HDF5 first).
#include "io/result_writer.hpp"

#include "core/rotation.hpp"
#include "io/checkpoint.hpp"
#include "io/hdf5_file.hpp"
#include "io/hydraulic_readers.hpp"
#include "io/viz_geometry.hpp"
#include "io/xdmf.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <tuple>
#include <utility>

namespace latticedyn {

namespace fs = std::filesystem;
using io::Hid;

namespace {

// 2: joint axes, constraint reactions, XDMF blocks; 3: body blocks; 4: polyline cells, the
// members' results once per member instead of once per drawn segment.
constexpr int kFormatVersion = 4;
constexpr std::size_t kPendingBytes = std::size_t{4} << 20;  // rows kept in memory between writes

double square(double x) { return x * x; }

[[noreturn]] void os_fail(const std::string& what, const fs::path& path, int err) {
  throw std::runtime_error("ResultWriter: cannot " + what + " '" + path.string() + "': " + std::strerror(err));
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

void copy3(const Vec3& v, double* out) { std::copy(v.data(), v.data() + 3, out); }

}  // namespace

struct ResultWriter::Impl {
  /// Which part of a row each rank writes when several write the file together: all of it on
  /// rank 0, an even share of its entries, or the entries of the rank's elements, their drawn
  /// cells or their drawn points (the last rank also the rigid bodies' cells and points).
  enum class Split { root, even, elements, cells, points };
  /// Fills entries [lo, hi) of a row (along its first dimension) into `out`.
  using Fill = std::function<void(const ModelState&, double* out, hsize_t lo, hsize_t hi)>;
  /// One time series and how to fill this rank's part of its row for the current step.
  struct Output {
    io::Series series;
    Fill fill;
    Split split = Split::root;
  };

  const Model& model;
  ResultWriterOptions opts;
  int rank = 0, ranks = 1;  // in opts.comm; several ranks write the .h5 collectively
  bool collective() const { return ranks > 1; }
  bool root() const { return rank == 0; }
  /// This rank's even share [begin, end) of n entries (all of them on a serial writer).
  std::pair<hsize_t, hsize_t> even_share(hsize_t n) const {
    return {n * static_cast<hsize_t>(rank) / static_cast<hsize_t>(ranks),
            n * static_cast<hsize_t>(rank + 1) / static_cast<hsize_t>(ranks)};
  }
  fs::path h5, xdmf, csv;
  io::Hdf5Context ctx;
  Hid transfer;  // MPI-IO transfer list (a writer of several ranks only)
  Hid file;
  // The elements whose results this rank evaluates and writes: [element_begin, element_end), with
  // their drawn cells and points (set at the first append).
  int element_begin = 0, element_end = 0, cell_begin = 0, cell_end = 0, point_begin = 0, point_end = 0;
  std::vector<int> translation, rotation, scalar, vectors;  // model block indices by kind
  std::vector<Output> outputs;                     // declared after `file`: closed before it
  int steps = 0;                                   // completed appends
  std::optional<io::XdmfDocument> document;        // none while nothing is drawn
  std::chrono::steady_clock::time_point flushed{};  // the last flush of the .h5
  // The XDMF is rewritten whole, and on long runs it grows to many megabytes: after the first 16
  // steps a rewrite waits 20 times as long as the last one took (rewrites cost at most 5 % of
  // the run; a 100 MB XDMF is then rewritten every few seconds instead of every second).
  std::chrono::steady_clock::time_point xdmf_written{};
  std::chrono::steady_clock::duration xdmf_pause{};
  bool xdmf_stale = false;  // steps flushed to the .h5 that the XDMF does not name yet
  bool unflushed = false;
  std::FILE* probes = nullptr;
  bool closed = false;
  bool broken = false;  // an append failed while writing the .h5
  bool continuing = false;           // opts.continuation: the files exist
  std::vector<double> kept_times;    // their kept steps' times (for the XDMF)

  // Evaluated once per append, read by several outputs.
  std::optional<io::VizGeometry> viz;
  std::vector<double> axial;    // per element, NaN without an axial force
  std::vector<ElementOutput> element_out;  // per element: energy, axial forces, drawn polylines
  ElementEnergy energy;
  std::vector<double> points;   // viz points, 3 per point
  std::vector<double> joint_axes;  // per joint its frame's columns, 9 per joint
  std::vector<ConstraintReaction> reactions;  // per constraint
  // Per drawn cell its member in element_out (or none), found once per step for the per-cell series.
  std::vector<const MemberStress*> cell_members;
  std::optional<MemberPeak> peak;  // the most utilized member over the steps appended

  Impl(const Model& m, ResultWriterOptions o);
  ~Impl();
  void write_model();
  void create_series();
  void create_viz();
  void create_state(hsize_t size);
  /// Evaluates this rank's part of a step's results (all of them on a serial writer).
  void compute_step(const ModelState& state);
  /// Sums the element energies over the ranks of a collective writer.
  void combine_energy();
  /// Writes the kept rows (and with `and_flush` flushes the .h5); collective.
  void write_pending(bool and_flush = false);
  /// Bytes of one whole step of every series (the same on every rank).
  std::size_t whole_step_bytes() const;
  /// Writes the kept rows and flushes the .h5 and the CSV, then rewrites the XDMF if due (always
  /// when `final`).
  void flush(bool final = false);
  /// Free hydraulic nodes (their pressures go into the probe CSV).
  std::vector<int> pressure_blocks() const;
  /// The flows of the elements that pass any (valves, pumps, cylinders), each as its element and
  /// its index among the element's flow_names(), in element order.
  struct FlowColumn {
    int element, index;
    std::string label;  ///< BODY.NAME
  };
  std::vector<FlowColumn> flow_columns;
  std::vector<double> flow_values;  // at the current step, one per flow column
  std::vector<double> element_flows;  // scratch
  bool ledger = false;                // EnergyLedger::applies: the energy account is recorded
  EnergyAccount account;              // as of the next append
  /// The account's works in the order of the probe CSV's columns and /hydraulics/energy.
  std::array<double, 6> account_row() const {
    return {account.supplied, account.dissipated, account.compression, account.mechanical_change,
            account.fluid_change, account.imbalance()};
  }
  void write_probe_header();
  void write_probe_row(const ModelState& state);
  void add(hid_t group, const std::string& name, std::vector<hsize_t> row, const char* units, Split split, Fill fill,
           bool single = false);
  /// Opens the .h5 on every rank of a collective writer (rank 0 has created it).
  void open_collective();
  /// Runs `work` on rank 0 (every rank of a serial writer is rank 0); a failure there is thrown on
  /// every rank, with rank 0's message.
  void on_root(const std::function<void()>& work);
  /// Throws on every rank when any failed (`error` non-empty), with the first failed rank's message.
  void agree(const std::string& error) const;
  /// Splits the elements among the ranks (first append, before anything is evaluated).
  void split_elements();
  /// Sets every series' part (first append, after every series exists).
  void set_parts();
  Hid group(hid_t parent, const std::string& name) const {
    return continuing ? io::open_group(parent, name, ctx) : io::create_group(parent, name, ctx);
  }
  void open_existing();
  /// Rank 0's part of open_existing: checks and cuts back the file (left open on a serial writer).
  void check_existing();
  std::vector<std::string> constraint_names() const {
    std::vector<std::string> names;
    for (const Constraint& c : model.constraints) names.push_back(c.name);
    return names;
  }
  void continue_probes();
  /// The member a drawn cell is, or none (rigid bodies' cells, elements without members).
  const MemberStress* cell_member(std::size_t cell) const {
    const int e = viz->cell_element()[cell];
    if (e < 0) return nullptr;
    const auto& members = element_out[static_cast<std::size_t>(e)].members;
    const auto m = static_cast<std::size_t>(viz->cell_polyline()[cell]);
    return m < members.size() ? &members[m] : nullptr;
  }
  /// Fills a per-cell dataset with one number of each cell's member (NaN without one).
  Fill per_cell(double (*of)(const MemberStress&)) const {
    return [this, of](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
      for (hsize_t c = lo; c < hi; ++c) {
        const MemberStress* m = cell_members[c];
        *out++ = m ? of(*m) : std::numeric_limits<double>::quiet_NaN();
      }
    };
  }
  void track_peak(double time);
};

std::optional<std::string> base_name_problem(const std::string& name) {
  if (name.empty()) return "expected a file base name, not an empty one";
  if (name.size() > kMaxBaseNameBytes)
    return "a file base name of at most " + std::to_string(kMaxBaseNameBytes) + " bytes (this one has " +
           std::to_string(name.size()) + ")";
  if (name[0] == '.') return "a file base name that does not start with '.' (no hidden files, no '..')";
  for (const char c : name)
    if (c == '/' || c == '\\' || c == ':' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return "a file base name without '/', '\\', ':' or control characters";
  return std::nullopt;
}

ResultWriter::Impl::Impl(const Model& m, ResultWriterOptions o) : model(m), opts(std::move(o)) {
  int mpi = 0;
  MPI_Initialized(&mpi);
  if (mpi) {
    MPI_Comm_rank(opts.comm, &rank);
    MPI_Comm_size(opts.comm, &ranks);
  }
  if (auto why = base_name_problem(opts.base_name))
    throw std::invalid_argument("ResultWriter: base name '" + opts.base_name + "': " + *why);
  for (int j : opts.probe_joints)
    if (j < 0 || j >= static_cast<int>(model.joints.size()))
      throw std::invalid_argument("ResultWriter: probe joint " + std::to_string(j) +
                                  " does not exist (the model has " + std::to_string(model.joints.size()) +
                                  " joints)");
  io::VizGeometry::check_draw_sequences(model);
  ledger = EnergyLedger::applies(model);
  for (int e = 0; e < static_cast<int>(model.elements.size()); ++e) {
    const auto names = model.elements[e].element->flow_names();
    for (int k = 0; k < static_cast<int>(names.size()); ++k)
      flow_columns.push_back({e, k, model.bodies[model.elements[e].body].name + "." + names[k]});
  }

  const fs::path dir = opts.directory.empty() ? fs::path(".") : fs::path(opts.directory);
  h5 = dir / (opts.base_name + ".h5");
  xdmf = dir / (opts.base_name + ".xdmf");
  csv = dir / (opts.base_name + "_probes.csv");
  ctx.file = h5;

  on_root([&] {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error("ResultWriter: cannot create directory '" + dir.string() + "': " + ec.message());
    // Written without following symbolic links: a link at a result's name is replaced by the new
    // file, its target left alone.
    for (const fs::path& p : {h5, xdmf, csv})
      if (fs::is_symlink(fs::symlink_status(p, ec))) fs::remove(p, ec);
  });

  for (int b = 0; b < static_cast<int>(model.blocks.size()); ++b) {
    switch (model.blocks[b].kind) {
      case SlotKind::translation: translation.push_back(b); break;
      case SlotKind::rotation: rotation.push_back(b); break;
      case SlotKind::scalar: scalar.push_back(b); break;
      case SlotKind::vector: vectors.push_back(b); break;
    }
  }

  continuing = opts.continuation.has_value();
  if (continuing) {
    open_existing();
    return;
  }
  const io::QuietHdf5Errors quiet;
  on_root([&] {
    // A stale XDMF of an earlier run in this folder would point into the .h5 about to be truncated.
    std::error_code ec;
    fs::remove(xdmf, ec);
    if (ec) throw std::runtime_error("ResultWriter: cannot remove '" + xdmf.string() + "': " + ec.message());
    file = ctx.own(H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create the file");
    // The static description holds strings of variable length, which parallel HDF5 cannot write
    // (1.10): rank 0 writes it alone before the ranks open the file together.
    write_model();
    if (collective()) ctx.check(file.reset(), "close the file");
    write_probe_header();
  });
  if (collective()) open_collective();
  create_series();
  ctx.check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file");
}

void ResultWriter::Impl::on_root(const std::function<void()>& work) {
  std::string error;
  if (root()) {
    try {
      work();
    } catch (const std::exception& e) {
      if (!collective()) throw;
      error = e.what();
      if (error.empty()) error = "ResultWriter: failed on rank 0";
    }
  }
  agree(error);
}

void ResultWriter::Impl::agree(const std::string& error) const {
  if (!collective()) {
    if (!error.empty()) throw std::runtime_error(error);
    return;
  }
  int first = error.empty() ? ranks : rank;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, opts.comm);
  if (first == ranks) return;
  int size = static_cast<int>(error.size());
  MPI_Bcast(&size, 1, MPI_INT, first, opts.comm);
  std::string message = error;
  message.resize(static_cast<std::size_t>(size));
  MPI_Bcast(message.data(), size, MPI_CHAR, first, opts.comm);
  throw std::runtime_error(first == rank || first == 0 ? message : message + " (on rank " + std::to_string(first) + ")");
}

void ResultWriter::Impl::open_collective() {
  const std::string what = "open the file on " + std::to_string(ranks) + " ranks (MPI-IO)";
  const Hid fapl = ctx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, what);
  ctx.check(H5Pset_fapl_mpio(fapl.get(), opts.comm, MPI_INFO_NULL), what);
  file = ctx.own(H5Fopen(h5.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose, what);
  // Independent transfers: a rank's part of a row is one contiguous run of the file (chunks are
  // whole rows, or several rows of a small series), so each rank writes its own directly; a
  // collective transfer would first shuffle the parts to aggregating ranks (measured no faster).
  // Metadata operations (creating and extending datasets, flushing) stay collective.
  transfer = ctx.own(H5Pcreate(H5P_DATASET_XFER), H5Pclose, what);
  ctx.check(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_INDEPENDENT), what);
  ctx.transfer = transfer.get();
  ctx.writes_whole = root();
}

// The files of the run being continued, cut back to the checkpoint: every series to its first
// `steps` entries (the datasets keep their size on disk, HDF5 does not shrink files), later
// checkpoints removed, the CSV to its header and `steps` rows; the XDMF follows at the next flush.
void ResultWriter::Impl::open_existing() {
  const ResultContinuation& c = *opts.continuation;
  const io::QuietHdf5Errors quiet;
  // Rank 0 checks the file, reads the kept steps' times and removes later checkpoints; then the
  // ranks of a collective writer open it together.
  on_root([&] { check_existing(); });
  if (collective()) open_collective();
  create_series();
  steps = static_cast<int>(c.steps);
  ctx.check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  on_root([&] { continue_probes(); });
}

void ResultWriter::Impl::check_existing() {
  const ResultContinuation& c = *opts.continuation;
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) throw std::runtime_error("ResultWriter: cannot continue '" + h5.string() + "': no such file");
  file = ctx.own(H5Fopen(h5.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, "open the file to continue it");
  // Only a file of this format can be extended: the rows of its series are this format's.
  int version = 0;
  if (H5Aexists(file.get(), "format_version") > 0) {
    const Hid attr = ctx.own(H5Aopen(file.get(), "format_version", H5P_DEFAULT), H5Aclose, "read its format_version");
    ctx.check(H5Aread(attr.get(), H5T_NATIVE_INT, &version), "read its format_version");
  }
  if (version != kFormatVersion)
    throw std::runtime_error("ResultWriter: cannot continue '" + h5.string() + "': it is of results format " +
                             std::to_string(version) + ", this latticedyn writes format " +
                             std::to_string(kFormatVersion) +
                             " (docs/output-format.md); run from the start, or continue with the latticedyn that wrote it");
  const auto keep = static_cast<hsize_t>(c.steps);
  {
    const Hid times = ctx.own(H5Dopen2(file.get(), "time", H5P_DEFAULT), H5Dclose, "open /time");
    const Hid space = ctx.own(H5Dget_space(times.get()), H5Sclose, "read /time");
    const hssize_t n = H5Sget_simple_extent_npoints(space.get());
    if (n < static_cast<hssize_t>(keep))
      throw std::runtime_error("ResultWriter: '" + h5.string() + "' holds " + std::to_string(n) +
                               " steps, fewer than the " + std::to_string(keep) + " the checkpoint counts");
    std::vector<double> all(static_cast<std::size_t>(n));
    if (n > 0) ctx.check(H5Dread(times.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), "read /time");
    kept_times.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(keep));
  }
  remove_checkpoints_after(file.get(), c.time, ctx);
  if (collective()) ctx.check(file.reset(), "close the file");
  // The XDMF names steps about to be dropped: written anew with the first append.
  fs::remove(xdmf, ec);
}

// The probe CSV cut back to its header and the kept rows, then appended to.
void ResultWriter::Impl::continue_probes() {
  std::vector<std::string> lines;
  if (std::FILE* in = std::fopen(csv.c_str(), "r")) {
    std::string line;
    for (int ch; (ch = std::fgetc(in)) != EOF;) {
      line += static_cast<char>(ch);
      if (ch == '\n') lines.push_back(std::exchange(line, {}));
      if (lines.size() > static_cast<std::size_t>(steps)) break;
    }
    std::fclose(in);
  }
  if (lines.size() != static_cast<std::size_t>(steps) + 1) {
    write_probe_header();  // missing or short: written anew from here (earlier rows are in the .h5)
    return;
  }
  probes = std::fopen(csv.c_str(), "w");
  if (!probes) os_fail("create", csv, errno);
  for (const std::string& l : lines)
    if (std::fputs(l.c_str(), probes) < 0) os_fail("write", csv, errno);
  if (std::fflush(probes) != 0) os_fail("write", csv, errno);
}

ResultWriter::Impl::~Impl() {
  if (probes) std::fclose(probes);
}

void ResultWriter::Impl::write_model() {
  const hid_t root = file.get();
  io::write_string_attribute(root, "title", model.title, ctx);
  io::write_string_attribute(root, "generator", "latticedyn", ctx);
  io::write_numeric_attribute(root, "format_version", H5T_STD_I32LE, H5T_NATIVE_INT, 1, &kFormatVersion, ctx);

  const Hid g = io::create_group(root, "model", ctx);
  const hid_t m = g.get();
  io::write_numeric_attribute(m, "gravity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 3, model.gravity.data(), ctx);
  io::write_ints(m, "translation_blocks", translation, ctx);
  io::write_ints(m, "rotation_blocks", rotation, ctx);
  io::write_ints(m, "scalar_blocks", scalar, ctx);
  io::write_ints(m, "vector_blocks", vectors, ctx);

  std::vector<std::string> labels;
  std::vector<int> kind, fixed;
  for (const DofBlock& b : model.blocks) {
    labels.push_back(b.label);
    kind.push_back(static_cast<int>(b.kind));
    fixed.push_back(b.fixed ? 1 : 0);
  }
  io::write_strings(m, "block_labels", labels, ctx);
  io::write_ints(m, "block_kind", kind, ctx);
  io::write_ints(m, "block_fixed", fixed, ctx);

  std::vector<std::string> names, types;
  for (const Body& b : model.bodies) {
    names.push_back(b.name);
    types.push_back(b.type);
  }
  io::write_strings(m, "body_names", names, ctx);
  io::write_strings(m, "body_types", types, ctx);

  names.clear();
  std::vector<int> body;
  for (const Joint& j : model.joints) {
    names.push_back(j.name);
    body.push_back(j.body);
  }
  io::write_strings(m, "joint_names", names, ctx);
  io::write_ints(m, "joint_body", body, ctx);

  names.clear();
  types.clear();
  std::vector<int> rows, first_row, joints;
  int row = 0;
  for (const Constraint& c : model.constraints) {
    names.push_back(c.name);
    types.push_back(to_string(c.type));
    rows.push_back(c.rows());
    first_row.push_back(row);
    row += c.rows();
    joints.push_back(c.joint1);
    joints.push_back(c.joint2);
  }
  io::write_strings(m, "constraint_names", names, ctx);
  io::write_strings(m, "constraint_types", types, ctx);
  io::write_ints(m, "constraint_rows", rows, ctx);
  io::write_ints(m, "constraint_first_row", first_row, ctx);
  io::write_ints(m, "constraint_joints", joints, ctx, 2);

  types.clear();
  body.clear();
  for (const ElementEntry& e : model.elements) {
    types.emplace_back(e.element->type_name());
    body.push_back(e.body);
  }
  io::write_strings(m, "element_types", types, ctx);
  io::write_ints(m, "element_body", body, ctx);

  names.clear();
  std::vector<int> load_joint;
  for (const NodalLoad& l : model.loads) {
    names.push_back(l.name);
    load_joint.push_back(l.joint);
  }
  io::write_strings(m, "load_names", names, ctx);
  io::write_ints(m, "load_joint", load_joint, ctx);
  io::write_ints(m, "probe_joints", opts.probe_joints, ctx);
  io::write_strings(m, "drive_names", model.drive_names, ctx);

  // The hydraulic series' column names (strings: written here, with the static part).
  if (flow_columns.empty() && !ledger) return;
  const Hid h = io::create_group(root, "hydraulics", ctx);
  if (!flow_columns.empty()) {
    std::vector<std::string> labels;
    for (const FlowColumn& f : flow_columns) labels.push_back(f.label);
    io::write_strings(h.get(), "flow_names", labels, ctx);
  }
  if (ledger)
    io::write_strings(h.get(), "energy_columns",
                      {"supplied", "dissipated", "compression", "mechanical_change", "fluid_change", "imbalance"}, ctx);
}

void ResultWriter::Impl::add(hid_t group, const std::string& name, std::vector<hsize_t> row, const char* units,
                             Split split, Fill fill, bool single) {
  for (hsize_t d : row)
    if (d == 0) return;  // nothing to record, and HDF5 rejects zero chunk dimensions
  if (continuing)
    outputs.push_back({io::Series::reopen(group, name, std::move(row), static_cast<hsize_t>(opts.continuation->steps),
                                          ctx, single),
                       std::move(fill), split});
  else
    outputs.push_back({io::Series(group, name, std::move(row), units, ctx, single), std::move(fill), split});
}

void ResultWriter::Impl::split_elements() {
  const int ne = static_cast<int>(model.elements.size());
  element_begin = 0;
  element_end = ne;
  cell_begin = point_begin = 0;
  cell_end = viz->num_cells();
  point_end = viz->num_points();
  if (collective()) {
    // Contiguous runs of elements of about equal work: an element's evaluation, and its members'
    // stresses and section forces once per drawn cell.
    std::vector<long> weight_before(static_cast<std::size_t>(ne) + 1, 0);
    std::vector<long> cells(static_cast<std::size_t>(ne), 0);
    for (const int e : viz->cell_element())
      if (e >= 0) ++cells[static_cast<std::size_t>(e)];
    for (int e = 0; e < ne; ++e) weight_before[e + 1] = weight_before[e] + 1 + cells[e];
    auto first_element = [&](int r) {
      const long target = weight_before.back() * r / ranks;
      return static_cast<int>(std::lower_bound(weight_before.begin(), weight_before.end(), target) - weight_before.begin());
    };
    element_begin = std::min(first_element(rank), ne);
    element_end = rank + 1 == ranks ? ne : std::min(first_element(rank + 1), ne);
    // The last rank also draws the rigid bodies, whose cells and points follow the elements'.
    cell_begin = viz->first_cell_of(element_begin);
    point_begin = viz->first_point_of(element_begin);
    if (rank + 1 < ranks) {
      cell_end = viz->first_cell_of(element_end);
      point_end = viz->first_point_of(element_end);
    }
  }
}

void ResultWriter::Impl::set_parts() {
  for (Output& o : outputs) {
    const hsize_t n = o.series.entries();
    hsize_t lo = 0, hi = n;
    switch (o.split) {
      case Split::root: hi = root() ? n : 0; break;
      case Split::even: std::tie(lo, hi) = even_share(n); break;
      case Split::elements: lo = static_cast<hsize_t>(element_begin); hi = static_cast<hsize_t>(element_end); break;
      case Split::cells: lo = static_cast<hsize_t>(cell_begin); hi = static_cast<hsize_t>(cell_end); break;
      case Split::points: lo = static_cast<hsize_t>(point_begin); hi = static_cast<hsize_t>(point_end); break;
    }
    o.series.set_part(lo, hi);
  }
}

void ResultWriter::Impl::create_series() {
  const hid_t root = file.get();
  const hsize_t nt = translation.size(), nr = rotation.size(), ns = scalar.size(), nv = vectors.size();
  const hsize_t nj = model.joints.size(), ne = model.elements.size(), nc = model.constraints.size();
  const auto nm = static_cast<hsize_t>(model.num_multipliers());

  add(root, "time", {}, "s", Split::root, [](const ModelState& s, double* out, hsize_t, hsize_t) { out[0] = s.time(); });

  // Per block kind, entries [lo, hi) of its list of blocks.
  auto per_block = [](const std::vector<int>& list, void (*put)(const BlockState&, double*&)) -> Fill {
    return [&list, put](const ModelState& s, double* out, hsize_t lo, hsize_t hi) {
      for (hsize_t k = lo; k < hi; ++k) put(s.block(list[k]), out);
    };
  };
  const Hid blocks = group(root, "blocks");
  const hid_t b = blocks.get();
  add(b, "position", {nt, 3}, "m", Split::even,
      per_block(translation, [](const BlockState& x, double*& out) { copy3(x.pos, std::exchange(out, out + 3)); }));
  add(b, "velocity", {nt, 3}, "m/s", Split::even,
      per_block(translation, [](const BlockState& x, double*& out) { copy3(x.vel, std::exchange(out, out + 3)); }));
  add(b, "rotation_vector", {nr, 3}, "rad", Split::even, per_block(rotation, [](const BlockState& x, double*& out) {
        copy3(rotation_vector(x.rot), std::exchange(out, out + 3));
      }));
  add(b, "rotation_matrix", {nr, 3, 3}, "1", Split::even, per_block(rotation, [](const BlockState& x, double*& out) {
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) *out++ = x.rot(r, c);
      }));
  add(b, "angular_velocity", {nr, 3}, "rad/s", Split::even,
      per_block(rotation, [](const BlockState& x, double*& out) { copy3(x.vel, std::exchange(out, out + 3)); }));
  add(b, "scalar_position", {ns}, "model units", Split::even,
      per_block(scalar, [](const BlockState& x, double*& out) { *out++ = x.pos(0); }));
  add(b, "scalar_velocity", {ns}, "model units/s", Split::even,
      per_block(scalar, [](const BlockState& x, double*& out) { *out++ = x.vel(0); }));
  // Free vectors, e.g. the slopes r' of ropes (absolute nodal coordinates).
  add(b, "vector", {nv, 3}, "model units", Split::even,
      per_block(vectors, [](const BlockState& x, double*& out) { copy3(x.pos, std::exchange(out, out + 3)); }));

  const Hid joints = group(root, "joints");
  add(joints.get(), "position", {nj, 3}, "m", Split::even, [](const ModelState& s, double* out, hsize_t lo, hsize_t hi) {
    for (hsize_t j = lo; j < hi; ++j) copy3(s.joint_position(static_cast<int>(j)), out + 3 * (j - lo));
  });
  add(joints.get(), "velocity", {nj, 3}, "m/s", Split::even, [](const ModelState& s, double* out, hsize_t lo, hsize_t hi) {
    for (hsize_t j = lo; j < hi; ++j) copy3(s.joint_velocity(static_cast<int>(j)), out + 3 * (j - lo));
  });

  const Hid constraints = group(root, "constraints");
  add(constraints.get(), "multipliers", {nm}, "N (length rows), N*m (angle rows)", Split::root,
      [nc](const ModelState& s, double* out, hsize_t, hsize_t) {
        for (hsize_t c = 0; c < nc; ++c) {
          const Eigen::VectorXd l = s.multipliers(static_cast<int>(c));
          out = std::copy(l.data(), l.data() + l.size(), out);
        }
      });
  add(constraints.get(), "violation", {nc}, "m (length rows), 1 (angle rows)", Split::even,
      [](const ModelState& s, double* out, hsize_t lo, hsize_t hi) {
        for (hsize_t c = lo; c < hi; ++c) *out++ = s.constraint_values(static_cast<int>(c)).cwiseAbs().maxCoeff();
      });
  // The reactions in physical terms, so no reader has to rebuild G to interpret the multipliers.
  auto per_reaction = [this](Vec3 ConstraintReaction::*of) -> Fill {
    return [this, of](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
      for (hsize_t c = lo; c < hi; ++c) copy3(reactions[c].*of, out + 3 * (c - lo));
    };
  };
  add(constraints.get(), "position", {nc, 3}, "m", Split::even, per_reaction(&ConstraintReaction::point));
  add(constraints.get(), "reaction_force", {nc, 3}, "N", Split::even, per_reaction(&ConstraintReaction::force));
  add(constraints.get(), "reaction_moment", {nc, 3}, "N*m", Split::even, per_reaction(&ConstraintReaction::moment));

  const Hid elements = group(root, "elements");
  add(elements.get(), "axial_force", {ne}, "N", Split::elements, [this](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
    std::copy(axial.begin() + static_cast<std::ptrdiff_t>(lo), axial.begin() + static_cast<std::ptrdiff_t>(hi), out);
  });

  const Hid drives = group(root, "drives");
  const hsize_t nd = model.drives.size();
  add(drives.get(), "value", {nd}, "model units (m, rad, 1)", Split::root,
      [this, nd](const ModelState& s, double* out, hsize_t, hsize_t) {
        for (hsize_t d = 0; d < nd; ++d) out[d] = model.drives[d].evaluate(s.time()).value;
      });

  add(root, "energy", {3}, "J", Split::root, [this](const ModelState&, double* out, hsize_t, hsize_t) {
    out[0] = energy.kinetic;
    out[1] = energy.gravity_potential;
    out[2] = energy.strain;
  });
  add(root, "energy_total", {}, "J", Split::root, [this](const ModelState&, double* out, hsize_t, hsize_t) {
    out[0] = energy.kinetic + energy.gravity_potential + energy.strain + energy.fluid;
  });
  if (!pressure_blocks().empty())
    add(root, "energy_fluid", {}, "J", Split::root,
        [this](const ModelState&, double* out, hsize_t, hsize_t) { out[0] = energy.fluid; });
  if (flow_columns.empty() && !ledger) return;
  const Hid h = io::open_group(root, "hydraulics", ctx);  // write_model made it
  // The flows and the energy account are evaluated on rank 0 (small hydraulic models).
  if (!flow_columns.empty())
    add(h.get(), "flow", {flow_columns.size()}, "m^3/s", Split::root,
        [this](const ModelState&, double* out, hsize_t, hsize_t) { std::copy(flow_values.begin(), flow_values.end(), out); });
  if (ledger)
    add(h.get(), "energy", {6}, "J (works since the run's start, EnergyLedger)", Split::root,
        [this](const ModelState&, double* out, hsize_t, hsize_t) {
          const auto row = account_row();
          std::copy(row.begin(), row.end(), out);
        });
}

// The solvers' whole coordinate vector in model order (the same on any number of ranks), so a
// later model can start from any recorded step (start_state; io/recorded_state.hpp).
void ResultWriter::Impl::create_state(hsize_t size) {
  const Hid g = group(file.get(), "state");
  add(g.get(), "coordinates", {size}, "coordinate vector in model order (m, rad, model units, multipliers)",
      Split::even, [](const ModelState& s, double* out, hsize_t lo, hsize_t hi) {
        const std::vector<double> q = s.coordinates_in_model_order();
        std::copy(q.begin() + static_cast<std::ptrdiff_t>(lo), q.begin() + static_cast<std::ptrdiff_t>(hi), out);
      });
}

void ResultWriter::Impl::create_viz() {
  const auto np = static_cast<hsize_t>(viz->num_points()), nl = static_cast<hsize_t>(viz->num_cells());
  if (nl == 0) return;  // nothing to draw: no /viz and no XDMF
  const Hid g = group(file.get(), "viz");
  const int nj = static_cast<int>(model.joints.size()), nc = static_cast<int>(model.constraints.size());
  if (!continuing) {
    io::write_ints(g.get(), "cells", viz->cells(), ctx);
    io::write_ints(g.get(), "cell_offsets", viz->cell_offsets(), ctx);
    io::write_ints(g.get(), "body", viz->cell_body(), ctx);
    io::write_ints(g.get(), "element", viz->cell_element(), ctx);
    io::write_ints(g.get(), "member", viz->cell_polyline(), ctx);  // the member within the element
    io::write_ints(g.get(), "lines", viz->lines(), ctx, 2);  // the cells' segments, for tools drawing lines
    io::write_ints(g.get(), "line_cell", viz->line_cell(), ctx);
    // Vertex lists (0, 1, ..., n-1) of the joints' and the constraints' point grids.
    std::vector<int> ids(static_cast<std::size_t>(std::max(nj, nc)));
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
    if (nj > 0) io::write_ints(g.get(), "joint_vertices", std::vector<int>(ids.begin(), ids.begin() + nj), ctx);
    if (nc > 0) io::write_ints(g.get(), "constraint_vertices", std::vector<int>(ids.begin(), ids.begin() + nc), ctx);
  }
  // Drawing coordinates in single precision (7 digits: 5 um on a 50 m crane), half the bytes of
  // the largest dataset; every physical quantity stays double.
  add(g.get(), "points", {np, 3}, "m", Split::points,
      [this](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
        std::copy(points.begin() + static_cast<std::ptrdiff_t>(3 * lo), points.begin() + static_cast<std::ptrdiff_t>(3 * hi), out);
      },
      true);
  add(g.get(), "axial_force", {nl}, "N", Split::cells, [this](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
    const auto& element = viz->cell_element();
    const auto& polyline = viz->cell_polyline();
    for (hsize_t l = lo; l < hi; ++l) {
      const int e = element[l];
      if (e < 0)
        *out++ = 0.0;
      else if (!element_out[e].polyline_axial_forces.empty())
        *out++ = element_out[e].polyline_axial_forces.at(static_cast<std::size_t>(polyline[l]));
      else
        *out++ = axial[e];
    }
  });
  // The members' section forces and stresses, per cell like the axial force.
  add(g.get(), "section_forces", {nl, 12}, "N (N, Qy, Qz), N*m (T, My, Mz); end 1, then end 2; element frame",
      Split::cells, [this](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
        for (hsize_t c = lo; c < hi; ++c) {
          const MemberStress* m = cell_members[c];
          for (int k = 0; k < 2; ++k) {
            const SectionForces f = m ? m->end[static_cast<std::size_t>(k)] : SectionForces{};
            const double v[6] = {f.N, f.Qy, f.Qz, f.T, f.My, f.Mz};
            for (int i = 0; i < 6; ++i) out[6 * k + i] = m ? v[i] : std::numeric_limits<double>::quiet_NaN();
          }
          out += 12;
        }
      });
  add(g.get(), "von_mises", {nl}, "Pa", Split::cells, per_cell([](const MemberStress& m) { return m.von_mises; }));
  add(g.get(), "utilization", {nl}, "1 (von Mises / yield stress)", Split::cells,
      per_cell([](const MemberStress& m) { return m.utilization; }));
  // Magnitudes by sqrt(a^2 + b^2), not std::hypot: resultants cannot overflow, and hypot's care
  // was a tenth of the output's evaluation (four per member and step).
  add(g.get(), "bending_moment", {nl}, "N*m", Split::cells, per_cell([](const MemberStress& m) {
        return std::sqrt(std::max(square(m.end[0].My) + square(m.end[0].Mz), square(m.end[1].My) + square(m.end[1].Mz)));
      }));
  add(g.get(), "shear_force", {nl}, "N", Split::cells, per_cell([](const MemberStress& m) {
        return std::sqrt(std::max(square(m.end[0].Qy) + square(m.end[0].Qz), square(m.end[1].Qy) + square(m.end[1].Qz)));
      }));
  add(g.get(), "torque", {nl}, "N*m", Split::cells,
      per_cell([](const MemberStress& m) { return std::max(std::abs(m.end[0].T), std::abs(m.end[1].T)); }));
  // The joints' frames for glyphs: drawing data, in single precision like the points.
  for (int axis = 0; axis < 3; ++axis)
    add(g.get(), std::string("joint_axis_") + "xyz"[axis], {static_cast<hsize_t>(nj), 3}, "1", Split::even,
        [this, axis](const ModelState&, double* out, hsize_t lo, hsize_t hi) {
          for (hsize_t j = lo; j < hi; ++j) std::copy_n(joint_axes.data() + 9 * j + 3 * axis, 3, out + 3 * (j - lo));
        },
        true);
  io::XdmfLayout layout{.h5_name = h5.filename().string(),
                        .title = model.title.empty() ? opts.base_name : model.title,
                        .points = viz->num_points(),
                        .cells = viz->num_cells(),
                        .cell_entries = static_cast<int>(viz->cells().size()),
                        .joints = nj,
                        .constraints = nc,
                        .constraint_names = constraint_names()};
  if (opts.body_blocks)
    for (const io::VizGeometry::BodyRange& r : viz->body_ranges())
      layout.bodies.push_back(io::XdmfBody{.name = model.bodies[r.body].name,
                                           .first_cell = r.first_cell,
                                           .cells = r.cells,
                                           .first_point = r.first_point,
                                           .points = r.points,
                                           .first_entry = r.first_entry,
                                           .entries = r.entries});
  // Each body block's cells, numbered from the body's first point (a run continued without body
  // blocks before gets them now).
  if (layout.names_bodies() && (!continuing || H5Lexists(g.get(), "body_cells", H5P_DEFAULT) <= 0)) {
    std::vector<int> local = viz->cells();
    const std::vector<int>& offsets = viz->cell_offsets();
    for (const io::XdmfBody& b : layout.bodies)
      for (int c = b.first_cell; c < b.first_cell + b.cells; ++c)
        for (int i = offsets[c] + 2; i < offsets[c + 1]; ++i) local[i] -= b.first_point;
    io::write_ints(g.get(), "body_cells", local, ctx);
  }
  if (!root()) return;  // rank 0 writes the XDMF
  document.emplace(std::move(layout));
  for (double t : kept_times) document->add_step(t);
}

void ResultWriter::Impl::compute_step(const ModelState& state) {
  // One evaluation per element for everything recorded of it; a rank of a collective writer
  // evaluates what it writes (set_parts), the rest of these arrays stays unread.
  const std::size_t ne = model.elements.size();
  element_out.resize(ne);
  axial.resize(ne, std::numeric_limits<double>::quiet_NaN());
  energy = ElementEnergy{};
  const ElementContext ctx = state.context();
  for (int e = element_begin; e < element_end; ++e) {
    ElementOutput& o = element_out[static_cast<std::size_t>(e)];
    model.elements[static_cast<std::size_t>(e)].element->output(state.element_slots(e), ctx, o);
    axial[static_cast<std::size_t>(e)] = o.axial_force.value_or(std::numeric_limits<double>::quiet_NaN());
    energy.kinetic += o.energy.kinetic;
    energy.gravity_potential += o.energy.gravity_potential;
    energy.strain += o.energy.strain;
    energy.fluid += o.energy.fluid;
  }
  if (root()) {
    flow_values.resize(flow_columns.size());
    for (std::size_t f = 0; f < flow_columns.size(); ++f) {
      const FlowColumn& c = flow_columns[f];
      if (c.index == 0) {  // an element's columns are consecutive: one evaluation gives them all
        const Element& el = *model.elements[c.element].element;
        element_flows.resize(el.flow_names().size());
        el.flows(state.element_slots(c.element), ctx, element_flows);
      }
      flow_values[f] = element_flows[c.index];
    }
  }
  viz->points(state, element_out, element_begin, element_end, rank + 1 == ranks, points);
  cell_members.resize(viz->cell_element().size());
  for (int c = cell_begin; c < cell_end; ++c) cell_members[c] = cell_member(static_cast<std::size_t>(c));
  // Joints and constraints: what this rank writes of them (Split::even).
  joint_axes.resize(9 * model.joints.size());
  for (auto [j, end] = even_share(model.joints.size()); j < end; ++j) {
    const Mat3 R = state.joint_frame_of(static_cast<int>(j)).second;
    std::copy(R.data(), R.data() + 9, joint_axes.data() + 9 * j);  // column-major: the axes in turn
  }
  reactions.resize(model.constraints.size());
  for (auto [c, end] = even_share(reactions.size()); c < end; ++c)
    reactions[c] = state.constraint_reaction(static_cast<int>(c));
}

void ResultWriter::Impl::combine_energy() {
  if (!collective()) return;
  double e[4] = {energy.kinetic, energy.gravity_potential, energy.strain, energy.fluid};
  MPI_Allreduce(MPI_IN_PLACE, e, 4, MPI_DOUBLE, MPI_SUM, opts.comm);
  energy.kinetic = e[0];
  energy.gravity_potential = e[1];
  energy.strain = e[2];
  energy.fluid = e[3];
}

namespace {

// Members with a utilization (their material gives a yield stress) outrank those without; then
// the larger utilization, or von Mises stress, wins.
bool outranks(const MemberPeak& a, const MemberPeak& b) {
  const bool ua = std::isfinite(a.utilization), ub = std::isfinite(b.utilization);
  if (ua != ub) return ua;
  return ua ? a.utilization > b.utilization : a.von_mises > b.von_mises;
}

constexpr int kPeakDoubles = 18;  // a MemberPeak sent between ranks: valid, element, member, time, 2 stresses, 12 forces

void pack(const std::optional<MemberPeak>& p, double* out) {
  std::fill(out, out + kPeakDoubles, 0.0);
  if (!p) return;
  const double head[6] = {1.0, static_cast<double>(p->element), static_cast<double>(p->member), p->time, p->von_mises,
                          p->utilization};
  std::copy(head, head + 6, out);
  for (int k = 0; k < 2; ++k) {
    const SectionForces& f = k == 0 ? p->end1 : p->end2;
    const double v[6] = {f.N, f.Qy, f.Qz, f.T, f.My, f.Mz};
    std::copy(v, v + 6, out + 6 + 6 * k);
  }
}

std::optional<MemberPeak> unpack(const double* in) {
  if (in[0] == 0.0) return std::nullopt;
  MemberPeak p{static_cast<int>(in[1]), static_cast<int>(in[2]), in[3], in[4], in[5], {}, {}};
  for (int k = 0; k < 2; ++k) {
    SectionForces& f = k == 0 ? p.end1 : p.end2;
    const double* v = in + 6 + 6 * k;
    f.N = v[0], f.Qy = v[1], f.Qz = v[2], f.T = v[3], f.My = v[4], f.Mz = v[5];
  }
  return p;
}

}  // namespace

void ResultWriter::Impl::track_peak(double time) {
  // This step's most utilized member of this rank's elements (the first in element order of equals).
  std::optional<MemberPeak> best;
  for (int e = element_begin; e < element_end; ++e) {
    const auto& members = element_out[static_cast<std::size_t>(e)].members;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const MemberStress& ms = members[m];
      if (!std::isfinite(ms.von_mises)) continue;
      const MemberPeak candidate{e, static_cast<int>(m), time, ms.von_mises, ms.utilization, ms.end[0], ms.end[1]};
      if (!best || outranks(candidate, *best)) best = candidate;
    }
  }
  std::vector<std::optional<MemberPeak>> bests{best};
  if (collective()) {  // every rank's, in rank order (= element order)
    std::vector<double> mine(kPeakDoubles), all(static_cast<std::size_t>(kPeakDoubles * ranks));
    pack(best, mine.data());
    MPI_Allgather(mine.data(), kPeakDoubles, MPI_DOUBLE, all.data(), kPeakDoubles, MPI_DOUBLE, opts.comm);
    bests.clear();
    for (int r = 0; r < ranks; ++r) bests.push_back(unpack(all.data() + kPeakDoubles * r));
  }
  for (const auto& b : bests)
    if (b && (!peak || outranks(*b, *peak))) peak = b;
}

std::vector<int> ResultWriter::Impl::pressure_blocks() const {
  std::vector<int> out;
  for (int b = 0; b < static_cast<int>(model.blocks.size()); ++b)
    if (!model.blocks[b].fixed && model.blocks[b].kind == SlotKind::scalar && model.blocks[b].label.starts_with(kHydraulicNodeLabel))
      out.push_back(b);
  return out;
}

void ResultWriter::Impl::write_probe_header() {
  probes = std::fopen(csv.c_str(), "w");
  if (!probes) os_fail("create", csv, errno);
  std::string header = "time [s]";
  for (int j : opts.probe_joints)
    for (const char* c : {".x [m]", ".y [m]", ".z [m]", ".vx [m/s]", ".vy [m/s]", ".vz [m/s]"}) {
      header += ',';
      header += csv_field(model.joints[j].name + c);
    }
  for (int b : pressure_blocks()) {
    header += ',';
    header += csv_field(model.blocks[b].label.substr(kHydraulicNodeLabel.size()) + ".p [Pa]");
  }
  for (const FlowColumn& f : flow_columns) {
    header += ',';
    header += csv_field(f.label + " [m^3/s]");
  }
  if (ledger)
    header += ",work supplied [J],work dissipated [J],work into oil compression [J],mechanical energy change [J],"
              "oil energy change [J],energy imbalance [J]";
  header += "\n";
  if (std::fputs(header.c_str(), probes) < 0 || std::fflush(probes) != 0) os_fail("write", csv, errno);
}

void ResultWriter::Impl::write_probe_row(const ModelState& state) {
  std::string row = io::format_double(state.time());
  for (int j : opts.probe_joints) {
    const Vec3 p = state.joint_position(j), v = state.joint_velocity(j);
    for (double x : {p.x(), p.y(), p.z(), v.x(), v.y(), v.z()}) {
      row += ',';
      row += io::format_double(x);
    }
  }
  for (int b : pressure_blocks()) {  // the hydraulic nodes' pressures after the probe joints
    row += ',';
    row += io::format_double(state.block(b).pos(0));
  }
  for (double q : flow_values) {  // computed by compute_step, which precedes every row
    row += ',';
    row += io::format_double(q);
  }
  if (ledger)
    for (double w : account_row()) {
      row += ',';
      row += io::format_double(w);
    }
  row += "\n";
  if (std::fputs(row.c_str(), probes) < 0) os_fail("write", csv, errno);  // flushed with the .h5
}

void ResultWriter::set_energy_account(const EnergyAccount& account) {
  if (impl_) impl_->account = account;
}

ResultWriter::ResultWriter(const Model& model, ResultWriterOptions opts)
    : impl_(std::make_unique<Impl>(model, std::move(opts))) {}

ResultWriter::~ResultWriter() {
  try {
    close();
  } catch (const std::exception& e) {
    std::cerr << e.what() << '\n';
  }
}

ResultWriter::ResultWriter(ResultWriter&&) noexcept = default;

ResultWriter& ResultWriter::operator=(ResultWriter&& other) noexcept {
  if (this != &other) {
    try {
      close();
    } catch (const std::exception& e) {
      std::cerr << e.what() << '\n';
    }
    impl_ = std::move(other.impl_);
  }
  return *this;
}

void ResultWriter::append(const ModelState& state) {
  if (!impl_ || impl_->closed) throw std::logic_error("ResultWriter::append after close()");
  Impl& w = *impl_;
  if (w.broken)
    throw std::logic_error("ResultWriter::append: an earlier append failed writing '" + w.h5.string() +
                           "'; the file holds the steps before it");
  const Model& m = state.model();
  if (m.blocks.size() != w.model.blocks.size() || m.joints.size() != w.model.joints.size() ||
      m.elements.size() != w.model.elements.size() || m.constraints.size() != w.model.constraints.size())
    throw std::invalid_argument("ResultWriter::append: the state belongs to another model");

  const bool first = !w.viz;
  if (first) {
    w.viz = io::VizGeometry::plan(state);
    w.split_elements();
  }
  // Throws before anything is written if the geometry changed size (on every rank of a
  // collective writer when it did on one).
  std::string error;
  try {
    w.compute_step(state);
  } catch (const std::exception& e) {
    if (!w.collective()) throw;
    error = e.what();
  }
  w.agree(error);
  w.combine_energy();
  w.track_peak(state.time());

  // The .h5 first (its rows kept until the next flush), then the XDMF after a flush: it only ever
  // names steps that are on disk.
  const io::QuietHdf5Errors quiet;
  const std::size_t kept = w.outputs.empty() ? 0 : w.outputs.front().series.pending_rows();
  try {
    if (first) {
      w.create_viz();
      w.create_state(static_cast<hsize_t>(state.coordinates().size()));
      // Series continued just now hold a cut-back chunk in HDF5's cache (io::Series::reopen).
      if (w.continuing && w.collective()) w.ctx.check(H5Fflush(w.file.get(), H5F_SCOPE_GLOBAL), "flush the file");
      w.set_parts();
      // The rows kept between writes (see kPendingBytes) get their memory once.
      const std::size_t rows = kPendingBytes / std::max<std::size_t>(w.whole_step_bytes(), 1) + 1;
      for (auto& o : w.outputs) o.series.reserve_rows(rows);
    }
    // Every fill writes its part of the row, straight into the series' pending rows.
    for (auto& o : w.outputs) {
      double* row = o.series.append_row();
      if (o.series.row_size() > 0) o.fill(state, row, o.series.part_begin(), o.series.part_end());  // else another rank writes it
    }
  } catch (...) {
    for (auto& o : w.outputs) o.series.discard_rows_after(kept);
    w.broken = true;
    throw;
  }
  ++w.steps;
  w.unflushed = true;
  if (w.document) w.document->add_step(state.time());
  if (w.root()) w.write_probe_row(state);
  // A flush writes every dataset's current chunk and the file's metadata, and the XDMF is
  // rewritten whole: after the first few steps both happen at most once a second (and on close),
  // so a run that is killed leaves a file at most a second behind, whose XDMF names only steps
  // the .h5 has. Rank 0's clock decides for all ranks of a collective writer.
  const auto now = std::chrono::steady_clock::now();
  int due = w.steps <= 16 || now - w.flushed >= std::chrono::seconds(1);
  if (w.collective()) MPI_Bcast(&due, 1, MPI_INT, 0, w.opts.comm);
  if (due) {
    w.flush();
    return;
  }
  // Rows kept longer than a few MiB go to the datasets now (not yet flushed, not yet in the
  // XDMF): the buffers are then reused in cache instead of growing into fresh pages. Counted in
  // whole rows, so that every rank decides alike.
  if (w.outputs.size() && w.outputs.front().series.pending_rows() * w.whole_step_bytes() > kPendingBytes) w.write_pending();
}

std::size_t ResultWriter::Impl::whole_step_bytes() const {
  std::size_t bytes = 0;
  for (const auto& o : outputs) bytes += sizeof(double) * static_cast<std::size_t>(o.series.whole_row_size());
  return bytes;
}

void ResultWriter::Impl::write_pending(bool and_flush) {
  // The ranks of a collective writer make every call together: a rank that fails one write goes
  // on with the others' calls and all fail together at the end.
  std::string error;
  for (auto& o : outputs) {
    try {
      o.series.write_pending(ctx);
    } catch (const std::exception& e) {
      if (!collective()) {
        broken = true;
        throw;
      }
      if (error.empty()) error = e.what();
    }
  }
  if (and_flush && (collective() || error.empty())) {
    const herr_t status = H5Fflush(file.get(), H5F_SCOPE_GLOBAL);
    if (status < 0 && error.empty()) {
      try {
        ctx.fail("flush the file");
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
  }
  try {
    agree(error);
  } catch (...) {
    broken = true;
    throw;
  }
}

void ResultWriter::Impl::flush(bool final) {
  write_pending(true);
  if (probes && std::fflush(probes) != 0) os_fail("write", csv, errno);
  const auto now = std::chrono::steady_clock::now();
  if (document && (final || steps <= 16 || now - xdmf_written >= xdmf_pause)) {
    io::replace_file(xdmf, [this](std::FILE* f) { document->write(f); });
    xdmf_written = std::chrono::steady_clock::now();
    xdmf_pause = 20 * (xdmf_written - now);
    xdmf_stale = false;
  } else {
    xdmf_stale = document.has_value();
  }
  flushed = std::chrono::steady_clock::now();
  unflushed = false;
}

void ResultWriter::write_checkpoint(const Checkpoint& c) {
  if (!impl_ || impl_->closed) throw std::logic_error("ResultWriter::write_checkpoint after close()");
  Impl& w = *impl_;
  if (w.broken)
    throw std::logic_error("ResultWriter::write_checkpoint: an earlier append failed writing '" + w.h5.string() + "'");
  const io::QuietHdf5Errors quiet;
  w.flush();
  // On a collective writer every rank passes the same checkpoint; rank 0 writes its vectors.
  std::string error;
  try {
    latticedyn::write_checkpoint(w.file.get(), c, w.ctx);
    w.ctx.check(H5Fflush(w.file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  } catch (const std::exception& e) {
    w.broken = true;
    if (!w.collective()) throw;
    error = e.what();
  }
  w.agree(error);
}

void ResultWriter::close() {
  if (!impl_ || impl_->closed) return;
  Impl& w = *impl_;
  w.closed = true;
  const io::QuietHdf5Errors quiet;
  bool ok = true;
  int pending = (w.unflushed || w.xdmf_stale) && !w.broken;
  if (w.collective()) MPI_Bcast(&pending, 1, MPI_INT, 0, w.opts.comm);  // only rank 0 knows of the XDMF
  if (pending) {
    try {
      w.flush(true);
    } catch (const std::exception&) {
      ok = false;
    }
  }
  for (auto& o : w.outputs) ok = o.series.close() >= 0 && ok;
  ok = w.file.reset() >= 0 && ok;
  const std::string h5_error = ok ? "" : io::hdf5_error_stack();
  const int csv_status = w.probes ? std::fclose(w.probes) : 0;
  const int csv_errno = errno;
  w.probes = nullptr;
  if (!ok) throw std::runtime_error("ResultWriter: cannot close '" + w.h5.string() + "': " + h5_error);
  if (csv_status != 0) os_fail("close", w.csv, csv_errno);
}

fs::path ResultWriter::h5_path() const { return impl_->h5; }
fs::path ResultWriter::xdmf_path() const { return impl_->xdmf; }
fs::path ResultWriter::csv_path() const { return impl_->csv; }
int ResultWriter::steps_written() const { return impl_->steps; }

std::optional<MemberPeak> ResultWriter::member_peak() const { return impl_->peak; }
bool ResultWriter::collective() const { return impl_->collective(); }

std::string describe_member_peak(const Model& model, const MemberPeak& p) {
  const ElementEntry& entry = model.elements.at(static_cast<std::size_t>(p.element));
  std::string where = "element " + std::to_string(p.element);
  if (entry.body >= 0) {
    const Body& b = model.bodies[static_cast<std::size_t>(entry.body)];
    const auto it = std::find(b.elements.begin(), b.elements.end(), p.element);
    where = "body '" + b.name + "' element " + std::to_string(it - b.elements.begin() + 1) + " of " +
            std::to_string(b.elements.size());
  }
  if (entry.element->type_name() == "super_truss") where += ", member " + std::to_string(p.member + 1);
  char buf[256];
  if (std::isfinite(p.utilization))
    std::snprintf(buf, sizeof buf, ": utilization %.3g (von Mises %.4g MPa) at t = %.6g s", p.utilization,
                  p.von_mises * 1e-6, p.time);
  else
    std::snprintf(buf, sizeof buf, ": von Mises %.4g MPa at t = %.6g s (no yield_stress given)", p.von_mises * 1e-6, p.time);
  return where + buf;
}

}  // namespace latticedyn
