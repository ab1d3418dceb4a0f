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
  /// One time series and how to fill its row for the current step.
  struct Output {
    io::Series series;
    std::function<void(const ModelState&, double*)> fill;
  };

  const Model& model;
  ResultWriterOptions opts;
  fs::path h5, xdmf, csv;
  io::Hdf5Context ctx;
  Hid file;
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
  void compute_step(const ModelState& state);
  void write_pending();
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
  void add(hid_t group, const std::string& name, std::vector<hsize_t> row, const char* units,
           std::function<void(const ModelState&, double*)> fill, bool single = false);
  Hid group(hid_t parent, const std::string& name) const {
    return continuing ? io::open_group(parent, name, ctx) : io::create_group(parent, name, ctx);
  }
  void open_existing();
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
  std::function<void(const ModelState&, double*)> per_cell(double (*of)(const MemberStress&)) const {
    return [this, of](const ModelState&, double* out) {
      for (const MemberStress* m : cell_members) *out++ = m ? of(*m) : std::numeric_limits<double>::quiet_NaN();
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

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("ResultWriter: cannot create directory '" + dir.string() + "': " + ec.message());
  // Written without following symbolic links: a link at a result's name is replaced by the new
  // file, its target left alone.
  for (const fs::path& p : {h5, xdmf, csv})
    if (fs::is_symlink(fs::symlink_status(p, ec))) fs::remove(p, ec);

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
  // A stale XDMF of an earlier run in this folder would point into the .h5 about to be truncated.
  fs::remove(xdmf, ec);
  if (ec) throw std::runtime_error("ResultWriter: cannot remove '" + xdmf.string() + "': " + ec.message());

  const io::QuietHdf5Errors quiet;
  // Serial HDF5 with default property lists: only the rank holding the gathered state writes.
  file = ctx.own(H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create the file");
  write_model();
  create_series();
  ctx.check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  write_probe_header();
}

// The files of the run being continued, cut back to the checkpoint: every series to its first
// `steps` entries (the datasets keep their size on disk, HDF5 does not shrink files), later
// checkpoints removed, the CSV to its header and `steps` rows; the XDMF follows at the next flush.
void ResultWriter::Impl::open_existing() {
  const ResultContinuation& c = *opts.continuation;
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) throw std::runtime_error("ResultWriter: cannot continue '" + h5.string() + "': no such file");
  const io::QuietHdf5Errors quiet;
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
  // The XDMF names steps about to be dropped: written anew with the first append.
  fs::remove(xdmf, ec);
  create_series();
  steps = static_cast<int>(keep);
  ctx.check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  continue_probes();
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
}

void ResultWriter::Impl::add(hid_t group, const std::string& name, std::vector<hsize_t> row, const char* units,
                             std::function<void(const ModelState&, double*)> fill, bool single) {
  for (hsize_t d : row)
    if (d == 0) return;  // nothing to record, and HDF5 rejects zero chunk dimensions
  if (continuing)
    outputs.push_back({io::Series::reopen(group, name, std::move(row), static_cast<hsize_t>(opts.continuation->steps),
                                          ctx, single),
                       std::move(fill)});
  else
    outputs.push_back({io::Series(group, name, std::move(row), units, ctx, single), std::move(fill)});
}

void ResultWriter::Impl::create_series() {
  const hid_t root = file.get();
  const hsize_t nt = translation.size(), nr = rotation.size(), ns = scalar.size(), nv = vectors.size();
  const hsize_t nj = model.joints.size(), ne = model.elements.size(), nc = model.constraints.size();
  const auto nm = static_cast<hsize_t>(model.num_multipliers());

  add(root, "time", {}, "s", [](const ModelState& s, double* out) { out[0] = s.time(); });

  const Hid blocks = group(root, "blocks");
  const hid_t b = blocks.get();
  add(b, "position", {nt, 3}, "m", [this](const ModelState& s, double* out) {
    for (int i : translation) copy3(s.block(i).pos, std::exchange(out, out + 3));
  });
  add(b, "velocity", {nt, 3}, "m/s", [this](const ModelState& s, double* out) {
    for (int i : translation) copy3(s.block(i).vel, std::exchange(out, out + 3));
  });
  add(b, "rotation_vector", {nr, 3}, "rad", [this](const ModelState& s, double* out) {
    for (int i : rotation) copy3(rotation_vector(s.block(i).rot), std::exchange(out, out + 3));
  });
  add(b, "rotation_matrix", {nr, 3, 3}, "1", [this](const ModelState& s, double* out) {
    for (int i : rotation)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) *out++ = s.block(i).rot(r, c);
  });
  add(b, "angular_velocity", {nr, 3}, "rad/s", [this](const ModelState& s, double* out) {
    for (int i : rotation) copy3(s.block(i).vel, std::exchange(out, out + 3));
  });
  add(b, "scalar_position", {ns}, "model units", [this](const ModelState& s, double* out) {
    for (int i : scalar) *out++ = s.block(i).pos(0);
  });
  add(b, "scalar_velocity", {ns}, "model units/s", [this](const ModelState& s, double* out) {
    for (int i : scalar) *out++ = s.block(i).vel(0);
  });
  // Free vectors, e.g. the slopes r' of ropes (absolute nodal coordinates).
  add(b, "vector", {nv, 3}, "model units", [this](const ModelState& s, double* out) {
    for (int i : vectors) copy3(s.block(i).pos, std::exchange(out, out + 3));
  });

  const Hid joints = group(root, "joints");
  add(joints.get(), "position", {nj, 3}, "m", [nj](const ModelState& s, double* out) {
    for (hsize_t j = 0; j < nj; ++j) copy3(s.joint_position(static_cast<int>(j)), out + 3 * j);
  });
  add(joints.get(), "velocity", {nj, 3}, "m/s", [nj](const ModelState& s, double* out) {
    for (hsize_t j = 0; j < nj; ++j) copy3(s.joint_velocity(static_cast<int>(j)), out + 3 * j);
  });

  const Hid constraints = group(root, "constraints");
  add(constraints.get(), "multipliers", {nm}, "N (length rows), N*m (angle rows)",
      [nc](const ModelState& s, double* out) {
        for (hsize_t c = 0; c < nc; ++c) {
          const Eigen::VectorXd l = s.multipliers(static_cast<int>(c));
          out = std::copy(l.data(), l.data() + l.size(), out);
        }
      });
  add(constraints.get(), "violation", {nc}, "m (length rows), 1 (angle rows)", [nc](const ModelState& s, double* out) {
    for (hsize_t c = 0; c < nc; ++c) out[c] = s.constraint_values(static_cast<int>(c)).cwiseAbs().maxCoeff();
  });
  // The reactions in physical terms, so no reader has to rebuild G to interpret the multipliers.
  add(constraints.get(), "position", {nc, 3}, "m", [this](const ModelState&, double* out) {
    for (const ConstraintReaction& r : reactions) copy3(r.point, std::exchange(out, out + 3));
  });
  add(constraints.get(), "reaction_force", {nc, 3}, "N", [this](const ModelState&, double* out) {
    for (const ConstraintReaction& r : reactions) copy3(r.force, std::exchange(out, out + 3));
  });
  add(constraints.get(), "reaction_moment", {nc, 3}, "N*m", [this](const ModelState&, double* out) {
    for (const ConstraintReaction& r : reactions) copy3(r.moment, std::exchange(out, out + 3));
  });

  const Hid elements = group(root, "elements");
  add(elements.get(), "axial_force", {ne}, "N",
      [this](const ModelState&, double* out) { std::copy(axial.begin(), axial.end(), out); });

  const Hid drives = group(root, "drives");
  const hsize_t nd = model.drives.size();
  add(drives.get(), "value", {nd}, "model units (m, rad, 1)", [this, nd](const ModelState& s, double* out) {
    for (hsize_t d = 0; d < nd; ++d) out[d] = model.drives[d].evaluate(s.time()).value;
  });

  add(root, "energy", {3}, "J", [this](const ModelState&, double* out) {
    out[0] = energy.kinetic;
    out[1] = energy.gravity_potential;
    out[2] = energy.strain;
  });
  add(root, "energy_total", {}, "J", [this](const ModelState&, double* out) {
    out[0] = energy.kinetic + energy.gravity_potential + energy.strain + energy.fluid;
  });
  if (!pressure_blocks().empty())
    add(root, "energy_fluid", {}, "J", [this](const ModelState&, double* out) { out[0] = energy.fluid; });
  if (flow_columns.empty() && !ledger) return;
  const Hid h = group(root, "hydraulics");
  if (!flow_columns.empty()) {
    if (!continuing) {
      std::vector<std::string> labels;
      for (const FlowColumn& f : flow_columns) labels.push_back(f.label);
      io::write_strings(h.get(), "flow_names", labels, ctx);
    }
    add(h.get(), "flow", {flow_columns.size()}, "m^3/s", [this](const ModelState&, double* out) {
      std::copy(flow_values.begin(), flow_values.end(), out);
    });
  }
  if (ledger) {
    if (!continuing)
      io::write_strings(h.get(), "energy_columns",
                        {"supplied", "dissipated", "compression", "mechanical_change", "fluid_change", "imbalance"}, ctx);
    add(h.get(), "energy", {6}, "J (works since the run's start, EnergyLedger)", [this](const ModelState&, double* out) {
      const auto row = account_row();
      std::copy(row.begin(), row.end(), out);
    });
  }
}

// The solvers' whole coordinate vector in model order (the same on any number of ranks), so a
// later model can start from any recorded step (start_state; io/recorded_state.hpp).
void ResultWriter::Impl::create_state(hsize_t size) {
  const Hid g = group(file.get(), "state");
  add(g.get(), "coordinates", {size}, "coordinate vector in model order (m, rad, model units, multipliers)",
      [](const ModelState& s, double* out) {
        const std::vector<double> q = s.coordinates_in_model_order();
        std::copy(q.begin(), q.end(), out);
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
  add(g.get(), "points", {np, 3}, "m",
      [this](const ModelState&, double* out) { std::copy(points.begin(), points.end(), out); }, true);
  add(g.get(), "axial_force", {nl}, "N", [this](const ModelState&, double* out) {
    const auto& element = viz->cell_element();
    const auto& polyline = viz->cell_polyline();
    for (std::size_t l = 0; l < element.size(); ++l) {
      const int e = element[l];
      if (e < 0)
        out[l] = 0.0;
      else if (!element_out[e].polyline_axial_forces.empty())
        out[l] = element_out[e].polyline_axial_forces.at(static_cast<std::size_t>(polyline[l]));
      else
        out[l] = axial[e];
    }
  });
  // The members' section forces and stresses, per cell like the axial force.
  add(g.get(), "section_forces", {nl, 12}, "N (N, Qy, Qz), N*m (T, My, Mz); end 1, then end 2; element frame",
      [this](const ModelState&, double* out) {
        for (const MemberStress* m : cell_members) {
          for (int k = 0; k < 2; ++k) {
            const SectionForces f = m ? m->end[static_cast<std::size_t>(k)] : SectionForces{};
            const double v[6] = {f.N, f.Qy, f.Qz, f.T, f.My, f.Mz};
            for (int i = 0; i < 6; ++i) out[6 * k + i] = m ? v[i] : std::numeric_limits<double>::quiet_NaN();
          }
          out += 12;
        }
      });
  add(g.get(), "von_mises", {nl}, "Pa", per_cell([](const MemberStress& m) { return m.von_mises; }));
  add(g.get(), "utilization", {nl}, "1 (von Mises / yield stress)",
      per_cell([](const MemberStress& m) { return m.utilization; }));
  // Magnitudes by sqrt(a^2 + b^2), not std::hypot: resultants cannot overflow, and hypot's care
  // was a tenth of the output's evaluation (four per member and step).
  add(g.get(), "bending_moment", {nl}, "N*m", per_cell([](const MemberStress& m) {
        return std::sqrt(std::max(square(m.end[0].My) + square(m.end[0].Mz), square(m.end[1].My) + square(m.end[1].Mz)));
      }));
  add(g.get(), "shear_force", {nl}, "N", per_cell([](const MemberStress& m) {
        return std::sqrt(std::max(square(m.end[0].Qy) + square(m.end[0].Qz), square(m.end[1].Qy) + square(m.end[1].Qz)));
      }));
  add(g.get(), "torque", {nl}, "N*m",
      per_cell([](const MemberStress& m) { return std::max(std::abs(m.end[0].T), std::abs(m.end[1].T)); }));
  // The joints' frames for glyphs: drawing data, in single precision like the points.
  for (int axis = 0; axis < 3; ++axis)
    add(g.get(), std::string("joint_axis_") + "xyz"[axis], {static_cast<hsize_t>(nj), 3}, "1",
        [this, axis](const ModelState&, double* out) {
          for (std::size_t j = 0; j < model.joints.size(); ++j)
            std::copy_n(joint_axes.data() + 9 * j + 3 * axis, 3, out + 3 * j);
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
  document.emplace(std::move(layout));
  for (double t : kept_times) document->add_step(t);
}

void ResultWriter::Impl::compute_step(const ModelState& state) {
  // One evaluation per element for everything recorded of it.
  const std::size_t ne = model.elements.size();
  element_out.resize(ne);
  axial.resize(ne);
  energy = ElementEnergy{};
  const ElementContext ctx = state.context();
  for (std::size_t e = 0; e < ne; ++e) {
    ElementOutput& o = element_out[e];
    model.elements[e].element->output(state.element_slots(static_cast<int>(e)), ctx, o);
    axial[e] = o.axial_force.value_or(std::numeric_limits<double>::quiet_NaN());
    energy.kinetic += o.energy.kinetic;
    energy.gravity_potential += o.energy.gravity_potential;
    energy.strain += o.energy.strain;
    energy.fluid += o.energy.fluid;
  }
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
  viz->points(state, element_out, points);
  cell_members.resize(viz->cell_element().size());
  for (std::size_t c = 0; c < cell_members.size(); ++c) cell_members[c] = cell_member(c);
  joint_axes.resize(9 * model.joints.size());
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Mat3 R = state.joint_frame_of(static_cast<int>(j)).second;
    std::copy(R.data(), R.data() + 9, joint_axes.data() + 9 * j);  // column-major: the axes in turn
  }
  reactions.resize(model.constraints.size());
  for (std::size_t c = 0; c < reactions.size(); ++c) reactions[c] = state.constraint_reaction(static_cast<int>(c));
  track_peak(state.time());
}

void ResultWriter::Impl::track_peak(double time) {
  // Members with a utilization (their material gives a yield stress) outrank those without; then
  // the larger utilization, or von Mises stress, wins.
  auto outranks = [](const MemberStress& a, const MemberPeak& b) {
    const bool ua = std::isfinite(a.utilization), ub = std::isfinite(b.utilization);
    if (ua != ub) return ua;
    return ua ? a.utilization > b.utilization : a.von_mises > b.von_mises;
  };
  for (std::size_t e = 0; e < element_out.size(); ++e) {
    const auto& members = element_out[e].members;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const MemberStress& ms = members[m];
      if (!std::isfinite(ms.von_mises) || (peak && !outranks(ms, *peak))) continue;
      peak = MemberPeak{static_cast<int>(e), static_cast<int>(m), time, ms.von_mises, ms.utilization, ms.end[0], ms.end[1]};
    }
  }
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
  if (first) w.viz = io::VizGeometry::plan(state);
  w.compute_step(state);  // throws before anything is written if the geometry changed size

  // The .h5 first (its rows kept until the next flush), then the XDMF after a flush: it only ever
  // names steps that are on disk.
  const io::QuietHdf5Errors quiet;
  const std::size_t kept = w.outputs.empty() ? 0 : w.outputs.front().series.pending_rows();
  try {
    if (first) {
      w.create_viz();
      w.create_state(static_cast<hsize_t>(state.coordinates().size()));
    }
    if (first) {
      // The rows kept between writes (see kPendingBytes) get their memory once.
      std::size_t step_bytes = 0;
      for (const auto& o : w.outputs) step_bytes += sizeof(double) * static_cast<std::size_t>(o.series.row_size());
      const std::size_t rows = kPendingBytes / std::max<std::size_t>(step_bytes, 1) + 1;
      for (auto& o : w.outputs) o.series.reserve_rows(rows);
    }
    // Every fill writes its whole row, straight into the series' pending rows.
    for (auto& o : w.outputs) o.fill(state, o.series.append_row());
  } catch (...) {
    for (auto& o : w.outputs) o.series.discard_rows_after(kept);
    w.broken = true;
    throw;
  }
  ++w.steps;
  w.unflushed = true;
  if (w.document) w.document->add_step(state.time());
  // A flush writes every dataset's current chunk and the file's metadata, and the XDMF is
  // rewritten whole: after the first few steps both happen at most once a second (and on close),
  // so a run that is killed leaves a file at most a second behind, whose XDMF names only steps
  // the .h5 has.
  const auto now = std::chrono::steady_clock::now();
  if (w.steps <= 16 || now - w.flushed >= std::chrono::seconds(1)) {
    w.write_probe_row(state);
    w.flush();
    return;
  }
  w.write_probe_row(state);
  // Rows kept longer than a few MiB go to the datasets now (not yet flushed, not yet in the
  // XDMF): the buffers are then reused in cache instead of growing into fresh pages.
  std::size_t pending = 0;
  for (const auto& o : w.outputs) pending += o.series.pending_bytes();
  if (pending > kPendingBytes) w.write_pending();
}

void ResultWriter::Impl::write_pending() {
  try {
    for (auto& o : outputs) o.series.write_pending(ctx);
  } catch (...) {
    broken = true;
    throw;
  }
}

void ResultWriter::Impl::flush(bool final) {
  write_pending();
  try {
    ctx.check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  } catch (...) {
    broken = true;
    throw;
  }
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
  try {
    latticedyn::write_checkpoint(w.file.get(), c, w.ctx);
    w.ctx.check(H5Fflush(w.file.get(), H5F_SCOPE_GLOBAL), "flush the file");
  } catch (...) {
    w.broken = true;
    throw;
  }
}

void ResultWriter::close() {
  if (!impl_ || impl_->closed) return;
  Impl& w = *impl_;
  w.closed = true;
  const io::QuietHdf5Errors quiet;
  bool ok = true;
  if ((w.unflushed || w.xdmf_stale) && !w.broken) {
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
