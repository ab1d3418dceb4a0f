// Batch runs: groups of ranks, chains of cases with warm starts, targets by secant iterations of
// static solves, records as cases finish, and the table (CSV + HDF5) at the end.
#include "drivers/batch_runner.hpp"

#include "drivers/batch_table.hpp"
#include "drivers/case_solver.hpp"

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

// What a chain hands from one case to the next.
struct ChainCarry {
  ChainHistory history;
  double goal = kNaN, slope = kNaN;  // target chains: the last case's goal and d(adjusted)/d(measure)
};

// A target's measure is scalar: its single column is named after it.
int measure_column(const BatchSpec& spec, const std::string& name) {
  const auto cols = measure_columns(spec);
  const auto it = std::find(cols.begin(), cols.end(), name);
  return it == cols.end() ? -1 : static_cast<int>(it - cols.begin());
}

// The case's record values: [adjusted], set values, measures.
std::vector<double> record_values(const BatchSpec& spec, const BatchCase& bc, std::optional<double> adjusted,
                                  const std::vector<double>& measures) {
  std::vector<double> v;
  if (spec.target_parameter >= 0) v.push_back(adjusted.value_or(kNaN));
  v.insert(v.end(), bc.set_values.begin(), bc.set_values.end());
  const std::size_t count = measure_columns(spec).size();
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
  if (spec.target_parameter < 0) {  // one solve: the model's run, or its equilibrium
    const double s = bc.values.empty() ? 0.0 : bc.values.back();  // a case list may set nothing numeric
    Evaluation ev = spec.dynamics ? solver.run(bc.overrides) : solver.statics(bc.overrides, carry->history.predict(s));
    r.evaluations = 1;
    r.newton_iterations = ev.newton;
    r.ok = ev.ok;
    r.error = ev.error;
    r.values = record_values(spec, bc, std::nullopt, ev.measures);
    if (ev.ok && !spec.dynamics) {
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
      if (const ChainPoint* p = history.earlier()) {  // recorded, so that a resume rebuilds the history
        r.chain_s = p->s;
        r.chain_state = p->state;
      }
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
    // The history the case ended with: its recorded earlier point, then its equilibrium (records
    // from before the earlier point was kept: the chain's equilibria, the same up to round-off).
    if (!r.chain_state.empty()) {
      carry->history = ChainHistory();
      carry->history.add(r.chain_s, r.chain_state);
    }
    carry->history.add(r.values.at(0), r.state);
    carry->goal = bc.values[spec.target_parameter];
    carry->slope = r.slope;
  } else {
    carry->history.add(bc.values.empty() ? 0.0 : bc.values.back(), r.state);  // as solve_case adds it
  }
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
      write_batch_table(spec, results, summary.records, summary.csv_path, summary.h5_path);
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
