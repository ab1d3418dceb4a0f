// Batch runs: groups of ranks, chains of cases with warm starts, targets by secant iterations of
// static solves, records as cases finish, and the table (CSV + HDF5) at the end.
#include "drivers/batch_runner.hpp"

#include "drivers/simulation.hpp"
#include "io/hdf5_file.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

namespace latticedyn {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string format_duration(double s) {
  char buf[64];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600, (static_cast<int>(s) % 3600) / 60);
  return buf;
}

// A measure's joints and body, resolved in the model once.
struct ResolvedMeasure {
  const BatchMeasure* spec;
  std::vector<int> joints;
  int body = -1;
};

std::vector<ResolvedMeasure> resolve_measures(const BatchSpec& spec, const Model& model) {
  std::vector<ResolvedMeasure> out;
  for (const BatchMeasure& m : spec.measures) {
    ResolvedMeasure r{&m, {}, -1};
    for (const std::string& j : m.joints) {
      const int k = model.find_joint(j);
      if (k < 0) throw InputError(m.file, m.line, m.column, "measures." + m.name, "the model has no joint '" + j + "'");
      r.joints.push_back(k);
    }
    if (m.kind == MeasureKind::axial_force) {
      r.body = model.find_body(m.body);
      if (r.body < 0) throw InputError(m.file, m.line, m.column, "measures." + m.name, "the model has no body '" + m.body + "'");
    }
    out.push_back(r);
  }
  return out;
}

std::vector<double> evaluate_measures(const std::vector<ResolvedMeasure>& measures, const ModelState& state) {
  std::vector<double> v;
  for (const ResolvedMeasure& m : measures) {
    switch (m.spec->kind) {
      case MeasureKind::position: {
        const Vec3 p = state.joint_position(m.joints[0]);
        v.insert(v.end(), {p.x(), p.y(), p.z()});
        break;
      }
      case MeasureKind::angle_above_horizontal: {
        const Vec3 d = state.joint_position(m.joints[1]) - state.joint_position(m.joints[0]);
        v.push_back(std::atan2(d.z(), std::hypot(d.x(), d.y())) * 180.0 / M_PI);
        break;
      }
      case MeasureKind::axial_force: {
        double sum = 0;
        int n = 0;
        for (int e : state.model().bodies[m.body].elements)
          if (auto f = state.axial_force(e)) {
            sum += *f;
            ++n;
          }
        v.push_back(n ? sum / n : kNaN);
        break;
      }
    }
  }
  return v;
}

// One solved model: its measures and full state (on every rank of the group).
struct Evaluation {
  bool ok = false;
  std::string error;
  int newton = 0;
  std::vector<double> measures;
  std::vector<double> state;
};

class CaseSolver {
 public:
  CaseSolver(const BatchSpec& spec, std::vector<ResolvedMeasure> measures, MPI_Comm comm)
      : spec_(spec), measures_(std::move(measures)), comm_(comm) {}

  /// The model with `overrides`, static equilibrium from `warm` (a state of the same model
  /// shape) or from the model's initial state, then the measures.
  Evaluation statics(const std::vector<KeyOverride>& overrides, const std::vector<double>& warm, bool cold_retry = true) {
    Evaluation ev;
    std::optional<Simulation> sim;
    if (!read(overrides, &sim, &ev)) return ev;
    SystemAssembler sa(sim->model, comm_);
    Vec U, V;
    PetscCallAbort(comm_, sa.create_vector(&U));
    PetscCallAbort(comm_, sa.create_vector(&V));
    PetscCallAbort(comm_, sa.initial_state(U, V));
    PetscInt n = 0;
    PetscCallAbort(comm_, VecGetSize(U, &n));
    const bool warm_start = static_cast<PetscInt>(warm.size()) == n;
    SimulationOutcome outcome;
    if (warm_start) {
      set_state(U, warm);
      sim->statics.warm_start = true;  // already loaded: one Newton solve from the neighbour
      PetscCallAbort(comm_, simulate(*sim, sa, U, V, true, false, nullptr, &outcome));
      ev.newton += outcome.statics.newton_iterations;
    }
    if (!warm_start || (!outcome.statics.converged && cold_retry)) {
      PetscCallAbort(comm_, sa.initial_state(U, V));
      sim->statics.warm_start = false;
      PetscCallAbort(comm_, simulate(*sim, sa, U, V, true, false, nullptr, &outcome));
      ev.newton += outcome.statics.newton_iterations;
    }
    ev.ok = outcome.statics.converged;
    if (!ev.ok) ev.error = outcome.statics.message;
    finish(sa, sim->statics.time, U, V, &ev);
    return ev;
  }

  /// The model's own run: statics if it asks, then its dynamics; measures at the end.
  Evaluation run(const std::vector<KeyOverride>& overrides) {
    Evaluation ev;
    std::optional<Simulation> sim;
    if (!read(overrides, &sim, &ev)) return ev;
    if (!sim->run_dynamics) {
      ev.error = spec_.model_path + ": the model has no solver.dynamics section for 'analysis: run'";
      return ev;
    }
    SystemAssembler sa(sim->model, comm_);
    Vec U, V;
    PetscCallAbort(comm_, sa.create_vector(&U));
    PetscCallAbort(comm_, sa.create_vector(&V));
    PetscCallAbort(comm_, sa.initial_state(U, V));
    SimulationOutcome outcome;
    PetscCallAbort(comm_, simulate(*sim, sa, U, V, sim->run_static, true, nullptr, &outcome));
    ev.newton = outcome.statics.newton_iterations + static_cast<int>(outcome.dynamics.newton_iterations);
    ev.ok = outcome.ok();
    if (!ev.ok) ev.error = outcome.static_run && !outcome.statics.converged ? outcome.statics.message : outcome.dynamics.message;
    const double t = outcome.dynamics_run ? outcome.dynamics.time_reached : sim->statics.time;
    finish(sa, t, U, V, &ev);
    ev.state.clear();  // a dynamic state is no start for another case
    return ev;
  }

 private:
  bool read(const std::vector<KeyOverride>& overrides, std::optional<Simulation>* sim, Evaluation* ev) {
    try {
      sim->emplace(read_simulation(spec_.model_path, overrides));
      return true;
    } catch (const std::exception& e) {  // a bad value fails this case alone
      ev->error = e.what();
      return false;
    }
  }

  void set_state(Vec U, const std::vector<double>& full) {
    PetscInt lo = 0, hi = 0;
    PetscCallAbort(comm_, VecGetOwnershipRange(U, &lo, &hi));
    PetscScalar* u = nullptr;
    PetscCallAbort(comm_, VecGetArray(U, &u));
    for (PetscInt i = lo; i < hi; ++i) u[i - lo] = full[i];
    PetscCallAbort(comm_, VecRestoreArray(U, &u));
  }

  // Measures on the group's first rank, shared; the full state on every rank of the group.
  void finish(SystemAssembler& sa, double t, Vec U, Vec V, Evaluation* ev) {
    ModelState state(sa.model(), sa.dofs());
    PetscCallAbort(comm_, sa.gather(t, U, V, nullptr, Parametrization::rotation_vector_rates, &state));
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    int count = 0;
    for (const BatchMeasure& m : spec_.measures) count += static_cast<int>(m.columns().size());
    ev->measures.assign(count, kNaN);
    if (rank == 0) ev->measures = evaluate_measures(measures_, state);
    MPI_Bcast(ev->measures.data(), count, MPI_DOUBLE, 0, comm_);
    VecScatter to_all;
    Vec all;
    PetscCallAbort(comm_, VecScatterCreateToAll(U, &to_all, &all));
    PetscCallAbort(comm_, VecScatterBegin(to_all, U, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCallAbort(comm_, VecScatterEnd(to_all, U, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscInt n = 0;
    const PetscScalar* a = nullptr;
    PetscCallAbort(comm_, VecGetSize(all, &n));
    PetscCallAbort(comm_, VecGetArrayRead(all, &a));
    ev->state.assign(a, a + n);
    PetscCallAbort(comm_, VecRestoreArrayRead(all, &a));
    PetscCallAbort(comm_, VecScatterDestroy(&to_all));
    PetscCallAbort(comm_, VecDestroy(&all));
    PetscCallAbort(comm_, VecDestroy(&U));
    PetscCallAbort(comm_, VecDestroy(&V));
  }

  const BatchSpec& spec_;
  std::vector<ResolvedMeasure> measures_;
  MPI_Comm comm_;
};

// Equilibria along a chain, as (coordinate, state): the coordinate is the adjusted value of a
// target, else the chain's parameter. The last two give the secant predictor of the next state.
struct ChainPoint {
  double s = 0.0;
  std::vector<double> state;
};

class ChainHistory {
 public:
  void add(double s, std::vector<double> state) {
    // A point next to the last one (the secant iterations closing in) replaces it, so that the
    // secant keeps a base long enough that solver round-off does not steer the extrapolation.
    const bool close = !points_.empty() &&
                       (points_.back().s == s ||
                        (points_.size() == 2 && std::abs(s - points_[1].s) < 0.1 * std::abs(points_[1].s - points_[0].s)));
    if (close) points_.pop_back();
    points_.push_back({s, std::move(state)});
    if (points_.size() > 2) points_.erase(points_.begin());
  }
  bool empty() const { return points_.empty(); }
  /// The state at s extrapolated along the secant of the last two equilibria: ropes whose rest
  /// length changes come with their stretch already moved, where the neighbour's state alone
  /// would leave a lengthened rope slack (tension only) and Newton without its stiffness.
  std::vector<double> predict(double s) const {
    if (points_.empty()) return {};
    const ChainPoint& p1 = points_.back();
    if (points_.size() < 2 || points_[0].state.size() != p1.state.size() || points_[0].s == p1.s) return p1.state;
    const ChainPoint& p0 = points_[0];
    const double w = (s - p1.s) / (p1.s - p0.s);
    std::vector<double> out(p1.state.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = p1.state[i] + w * (p1.state[i] - p0.state[i]);
    return out;
  }
  const ChainPoint& last() const { return points_.back(); }

 private:
  std::vector<ChainPoint> points_;
};

// What a chain hands from one case to the next.
struct ChainCarry {
  ChainHistory history;
  double goal = kNaN, slope = kNaN;  // target chains: the last case's goal and d(adjusted)/d(measure)
};

int measure_column(const BatchSpec& spec, const std::string& name) {
  int col = 0;
  for (const BatchMeasure& m : spec.measures) {
    if (m.name == name) return col;
    col += static_cast<int>(m.columns().size());
  }
  return -1;
}

// The case's record values: [adjusted], set values, measures.
std::vector<double> record_values(const BatchSpec& spec, const BatchCase& bc, std::optional<double> adjusted,
                                  const std::vector<double>& measures) {
  std::vector<double> v;
  if (spec.target_parameter >= 0) v.push_back(adjusted.value_or(kNaN));
  v.insert(v.end(), bc.set_values.begin(), bc.set_values.end());
  const std::size_t count = [&] {
    std::size_t n = 0;
    for (const BatchMeasure& m : spec.measures) n += m.columns().size();
    return n;
  }();
  if (measures.size() == count)
    v.insert(v.end(), measures.begin(), measures.end());
  else
    v.insert(v.end(), count, kNaN);
  return v;
}

CaseRecord solve_case(const BatchSpec& spec, const BatchCase& bc, CaseSolver& solver, ChainCarry* carry) {
  const auto t0 = std::chrono::steady_clock::now();
  CaseRecord r;
  r.index = bc.index;
  if (spec.dynamics) {
    Evaluation ev = solver.run(bc.overrides);
    r.evaluations = 1;
    r.newton_iterations = ev.newton;
    r.ok = ev.ok;
    r.error = ev.error;
    r.values = record_values(spec, bc, std::nullopt, ev.measures);
  } else if (spec.target_parameter < 0) {
    const double s = bc.values.back();
    Evaluation ev = solver.statics(bc.overrides, carry->history.predict(s));
    r.evaluations = 1;
    r.newton_iterations = ev.newton;
    r.ok = ev.ok;
    r.error = ev.error;
    r.values = record_values(spec, bc, std::nullopt, ev.measures);
    if (ev.ok) {
      r.state = ev.state;
      if (spec.warm_start) carry->history.add(s, std::move(ev.state));
    }
  } else {
    // Secant iterations on the adjusted value until the measure reaches the case's parameter.
    const BatchTarget& t = *spec.parameters[spec.target_parameter].target;
    const double goal = bc.values[spec.target_parameter];
    const int col = measure_column(spec, t.measure);
    ChainHistory history = carry->history;
    double slope = carry->slope;
    const double from = history.empty() ? t.start : history.last().s;
    double step = std::isfinite(slope) && std::isfinite(carry->goal) ? slope * (goal - carry->goal) : 0.0;
    step = std::clamp(step, -t.max_step, t.max_step);
    auto eval = [&](double a) {
      std::vector<KeyOverride> o = bc.overrides;
      KeyOverride k;
      k.path = t.adjust;
      k.value = YAML::Node(a);
      k.origin_file = spec.source;
      o.push_back(k);
      // No cold retry once there is an equilibrium: the model's own pose is far from most
      // targets; a shorter step is the cure.
      Evaluation ev = solver.statics(o, history.predict(a), history.empty());
      ++r.evaluations;
      r.newton_iterations += ev.newton;
      if (ev.ok) history.add(a, ev.state);
      return ev;
    };
    Evaluation ev = eval(from + step);
    for (int cut = 0; !ev.ok && step != 0.0 && cut < 4 && r.evaluations < t.max_evaluations; ++cut) {
      step *= 0.5;
      ev = eval(from + step);
    }
    double a = from + step;
    double m = ev.ok ? ev.measures[col] : kNaN;
    bool done = false;
    while (ev.ok && r.evaluations < t.max_evaluations) {
      const double f = m - goal;
      if (std::abs(f) <= t.tolerance) {
        done = true;
        break;
      }
      double da = std::isfinite(slope) ? -f * slope : 1e-4 * std::max(1.0, std::abs(a));  // a probe inside Newton's reach
      da = std::clamp(da, -t.max_step, t.max_step);
      Evaluation next = eval(a + da);
      for (int cut = 0; !next.ok && cut < 4 && r.evaluations < t.max_evaluations; ++cut) {
        da *= 0.5;  // a failed solve: a shorter step from the last equilibrium
        next = eval(a + da);
      }
      if (!next.ok) {
        ev = std::move(next);
        break;
      }
      const double m_next = next.measures[col];
      if (m_next != m) slope = da / (m_next - m);
      a += da;
      m = m_next;
      ev = std::move(next);
    }
    r.ok = done;
    r.slope = slope;
    if (!ev.ok) {
      r.error = ev.error;
    } else if (!done) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "target not reached in %d static solves: %s = %.9g for %.9g (%s = %.9g)",
                    r.evaluations, t.measure.c_str(), m, goal, t.adjust.c_str(), a);
      r.error = buf;
    }
    r.values = record_values(spec, bc, ev.ok ? std::optional<double>(a) : std::nullopt,
                             ev.ok ? ev.measures : std::vector<double>{});
    if (done) {
      r.state = ev.state;
      carry->history = std::move(history);  // ends with this equilibrium
      carry->goal = goal;
      carry->slope = slope;
    }
  }
  r.wall_seconds = seconds_since(t0);
  if (!r.ok && r.error.empty()) r.error = "failed";
  return r;
}

void restore_carry(const BatchSpec& spec, const BatchCase& bc, const CaseRecord& r, ChainCarry* carry) {
  if (!r.ok || r.state.empty() || !spec.warm_start) return;
  if (spec.target_parameter >= 0) {
    carry->history.add(r.values.at(0), r.state);
    carry->goal = bc.values[spec.target_parameter];
    carry->slope = r.slope;
  } else {
    carry->history.add(bc.values.back(), r.state);
  }
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void write_table(const BatchSpec& spec, const std::vector<std::string>& results, const std::map<int, CaseRecord>& records,
                 const std::filesystem::path& csv, const std::filesystem::path& h5) {
  std::vector<std::string> numeric = spec.columns;
  numeric.insert(numeric.end(), results.begin(), results.end());
  const std::size_t n = spec.cases.size();
  std::vector<std::vector<double>> cols(numeric.size() + 3, std::vector<double>(n, kNaN));
  std::vector<std::string> status(n, "not run"), label(n), error(n);
  std::vector<int> index(n);
  for (std::size_t c = 0; c < n; ++c) {
    const BatchCase& bc = spec.cases[c];
    index[c] = bc.index;
    label[c] = bc.label;
    for (std::size_t k = 0; k < bc.values.size(); ++k) cols[k][c] = bc.values[k];
    const auto it = records.find(bc.index);
    if (it == records.end()) continue;
    const CaseRecord& r = it->second;
    status[c] = r.ok ? "ok" : "failed";
    error[c] = r.error;
    for (std::size_t k = 0; k < results.size() && k < r.values.size(); ++k) cols[spec.columns.size() + k][c] = r.values[k];
    cols[numeric.size()][c] = r.evaluations;
    cols[numeric.size() + 1][c] = r.newton_iterations;
    cols[numeric.size() + 2][c] = r.wall_seconds;
  }
  std::vector<std::string> all = numeric;
  all.insert(all.end(), {"evaluations", "newton_iterations", "wall_seconds"});

  const std::filesystem::path tmp = csv.string() + ".part";
  {
    std::ofstream f(tmp);
    f << "case,label,status";
    for (const auto& c : all) f << "," << csv_text(c);
    f << ",error\n";
    char buf[40];
    for (std::size_t c = 0; c < n; ++c) {
      f << index[c] << "," << csv_text(label[c]) << "," << status[c];
      for (const auto& col : cols) {
        std::snprintf(buf, sizeof buf, ",%.17g", col[c]);
        f << buf;
      }
      f << "," << csv_text(error[c]) << "\n";
    }
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, csv);  // a reader never sees half a table

  const io::Hdf5Context ctx{h5};
  const io::QuietHdf5Errors quiet;
  const std::filesystem::path h5tmp = h5.string() + ".part";
  {
    io::Hid file = ctx.own(H5Fcreate(h5tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create the file");
    io::write_string_attribute(file.get(), "batch", spec.source, ctx);
    io::write_string_attribute(file.get(), "model", spec.model_path, ctx);
    io::Hid table = io::create_group(file.get(), "table", ctx);
    io::write_ints(table.get(), "case", index, ctx);
    io::write_strings(table.get(), "label", label, ctx);
    io::write_strings(table.get(), "status", status, ctx);
    io::write_strings(table.get(), "error", error, ctx);
    io::write_strings(table.get(), "columns", all, ctx);
    for (std::size_t k = 0; k < all.size(); ++k)
      io::write_dataset(table.get(), all[k], {n}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, cols[k].data(), ctx);
  }
  std::filesystem::rename(h5tmp, h5);
}

}  // namespace

Continuation continue_equilibrium(const std::string& model_path, const std::vector<std::string>& paths,
                                  const std::vector<double>& from, const std::vector<double>& to,
                                  const std::vector<double>& state, int steps, MPI_Comm comm) {
  BatchSpec spec;
  spec.model_path = model_path;
  spec.source = model_path;
  CaseSolver solver(spec, {}, comm);
  ChainHistory history;
  history.add(0.0, state);
  Continuation c;
  auto overrides = [&](double s) {
    std::vector<KeyOverride> o;
    for (std::size_t k = 0; k < paths.size(); ++k) {
      KeyOverride ko;
      ko.path = paths[k];
      ko.value = YAML::Node(from[k] + s * (to[k] - from[k]));
      ko.origin_file = model_path;
      o.push_back(ko);
    }
    return o;
  };
  double s = 0.0;
  // A first short step: without a secant the neighbour's state alone must be inside Newton's reach.
  double ds = std::min(1.0, 1e-3 * steps) / steps;
  int failures = 0;
  while (s < 1.0) {
    const double next = std::min(1.0, s + ds);
    Evaluation ev = solver.statics(overrides(next), history.predict(next), false);
    ++c.solves;
    c.newton_iterations += ev.newton;
    if (!ev.ok) {
      if (++failures > 12) {
        c.error = "continuation stalled at " + std::to_string(s) + " of the way: " + ev.error;
        return c;
      }
      ds *= 0.5;
      continue;
    }
    history.add(next, ev.state);
    c.state = std::move(ev.state);
    s = next;
    ds = std::min(2.0 * ds, 1.0 / steps);
  }
  c.ok = true;
  return c;
}

BatchSummary run_batch(const BatchSpec& spec, const BatchOptions& options, MPI_Comm world) {
  const auto t0 = std::chrono::steady_clock::now();
  int size = 1, rank = 0;
  MPI_Comm_size(world, &size);
  MPI_Comm_rank(world, &rank);
  const int groups = options.groups > 0 ? options.groups : size;
  if (groups > size || size % groups != 0)
    throw InputError(spec.source, 0, 0, "", std::to_string(size) + " ranks do not split into " + std::to_string(groups) +
                                                " equal groups (--groups must divide the number of ranks)");
  const int per_group = size / groups;
  const int group = rank / per_group;
  MPI_Comm gcomm;
  MPI_Comm_split(world, group, rank, &gcomm);
  int grank = 0;
  MPI_Comm_rank(gcomm, &grank);

  const std::filesystem::path dir = options.output_directory.empty() ? spec.output_directory : options.output_directory;
  const std::filesystem::path records_dir = dir / (spec.name + "_records");
  std::string problem;
  if (rank == 0) {
    std::error_code ec;
    std::filesystem::create_directories(records_dir, ec);
    if (ec) problem = "cannot create " + records_dir.string() + ": " + ec.message();
  }
  int bad = !problem.empty();
  MPI_Bcast(&bad, 1, MPI_INT, 0, world);
  if (bad) throw std::runtime_error(rank == 0 ? problem : "the output folder could not be created on rank 0");

  // The fingerprint: the batch and model files' text, so that a resume never mixes two batches.
  auto slurp = [](const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  const std::uint64_t fingerprint = fingerprint_of(slurp(spec.source) + "\n--\n" + slurp(spec.model_path));
  std::map<int, CaseRecord> previous = read_case_records(records_dir, fingerprint);
  if (options.retry_failed)
    for (auto it = previous.begin(); it != previous.end();) it = it->second.ok ? std::next(it) : previous.erase(it);

  const Simulation base = read_simulation(spec.model_path);
  CaseSolver solver(spec, resolve_measures(spec, base.model), gcomm);

  std::unique_ptr<CaseLog> log;
  if (grank == 0)
    log = std::make_unique<CaseLog>(records_dir / ("group" + std::to_string(group) + "of" + std::to_string(groups) + ".log"),
                                    fingerprint);

  // Chains go round-robin to the groups; a chain's cases run in order on one group, so the
  // results do not depend on how many groups there are.
  std::vector<std::vector<const BatchCase*>> chains(spec.chains);
  for (const BatchCase& bc : spec.cases) chains[bc.chain].push_back(&bc);
  int mine = 0, mine_done = 0, solved = 0;
  for (int c = group; c < spec.chains; c += groups)
    for (const BatchCase* bc : chains[c]) {
      ++mine;
      mine_done += previous.count(bc->index) ? 1 : 0;
    }
  const auto group_start = std::chrono::steady_clock::now();
  for (int c = group; c < spec.chains; c += groups) {
    ChainCarry carry;
    for (const BatchCase* bc : chains[c]) {
      const auto found = previous.find(bc->index);
      if (found != previous.end()) {
        restore_carry(spec, *bc, found->second, &carry);
        continue;
      }
      const CaseRecord r = solve_case(spec, *bc, solver, &carry);
      ++solved;
      ++mine_done;
      if (log) {
        log->append(r);
        if (!options.quiet) {
          const double per_case = seconds_since(group_start) / solved;
          std::fprintf(stderr, "[batch group %d/%d] case %d (%s): %s, %d solve%s, %d Newton, %.2f s; %d/%d done, ETA %s%s%s\n",
                       group + 1, groups, bc->index, bc->label.c_str(), r.ok ? "ok" : "FAILED", r.evaluations,
                       r.evaluations == 1 ? "" : "s", r.newton_iterations, r.wall_seconds, mine_done, mine,
                       format_duration(per_case * (mine - mine_done)).c_str(), r.ok ? "" : ": ", r.error.c_str());
          std::fflush(stderr);
        }
      }
    }
  }
  log.reset();
  MPI_Barrier(world);

  BatchSummary summary;
  summary.records = read_case_records(records_dir, fingerprint);
  summary.columns = spec.columns;
  const auto results = result_columns(spec);
  summary.columns.insert(summary.columns.end(), results.begin(), results.end());
  summary.cases = static_cast<int>(spec.cases.size());
  for (const auto& [i, r] : summary.records) (r.ok ? summary.ok : summary.failed) += 1;
  int skipped = static_cast<int>(previous.size());
  MPI_Allreduce(MPI_IN_PLACE, &skipped, 1, MPI_INT, MPI_MAX, world);
  summary.skipped = skipped;
  summary.csv_path = (dir / (spec.name + ".csv")).string();
  summary.h5_path = (dir / (spec.name + ".h5")).string();
  int written = 1;
  std::string why;
  if (rank == 0) {
    try {
      write_table(spec, results, summary.records, summary.csv_path, summary.h5_path);
    } catch (const std::exception& e) {
      written = 0;
      why = e.what();
    }
  }
  MPI_Bcast(&written, 1, MPI_INT, 0, world);
  if (!written) throw std::runtime_error(rank == 0 ? why : "the table could not be written on rank 0");
  summary.wall_seconds = seconds_since(t0);
  MPI_Comm_free(&gcomm);
  return summary;
}

}  // namespace latticedyn
