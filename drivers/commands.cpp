// check, static and run: set up the assembler, the results writer on rank 0 and the solvers, and
// print what happened. Failures of the solvers are reported and leave the results written so far.
#include "drivers/commands.hpp"

#include "drivers/batch_runner.hpp"
#include "drivers/control_pipeline.hpp"
#include "drivers/interrupt.hpp"
#include "drivers/observers.hpp"
#include "drivers/simulation.hpp"
#include "timestepping/arc_length.hpp"
#include "timestepping/buckling_analysis.hpp"
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/modal_analysis.hpp"

#include <petscts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <utility>
#include <memory>

namespace latticedyn {

namespace {

bool is_root(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank == 0;
}

void print_root(MPI_Comm comm, const std::string& text, FILE* stream = stdout) {
  if (is_root(comm)) {
    std::fputs(text.c_str(), stream);
    std::fflush(stream);
  }
}

void error_root(MPI_Comm comm, const std::string& text) { print_root(comm, "latticedyn: error: " + text + "\n", stderr); }

std::string describe_model(const Model& m) {
  std::map<std::string, int> types;
  for (std::size_t b = 1; b < m.bodies.size(); ++b) ++types[m.bodies[b].type];
  std::string bodies;
  for (const auto& [t, n] : types) bodies += (bodies.empty() ? "" : ", ") + std::to_string(n) + " " + t;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "model '%s': %zu bodies (%s), %zu joints, %zu constraints with %d multipliers, %zu loads, %zu drives; "
                "%d free DoFs in %zu blocks\n",
                m.title.c_str(), m.bodies.size() - 1, bodies.c_str(), m.joints.size(), m.constraints.size(),
                m.num_multipliers(), m.loads.size(), m.drives.size(), m.num_free_dofs(), m.blocks.size());
  return buf;
}

// A solver type named by an option that PETSc does not know, as a message ("" if none): checked
// before the results are opened, so that a mistyped -ts_type stops the run with nothing written.
std::string unknown_solver_type(MPI_Comm comm) {
  struct Check {
    const char* option;
    std::function<PetscErrorCode(const char*)> set;
  };
  TS ts = nullptr;
  SNES snes = nullptr;
  KSP ksp = nullptr;
  PC pc = nullptr;
  SNESLineSearch ls = nullptr;
  TSAdapt adapt = nullptr;
  std::string message;
  PetscCallAbort(comm, TSCreate(comm, &ts));
  PetscCallAbort(comm, TSGetSNES(ts, &snes));
  PetscCallAbort(comm, TSGetAdapt(ts, &adapt));
  PetscCallAbort(comm, SNESGetKSP(snes, &ksp));
  PetscCallAbort(comm, SNESGetLineSearch(snes, &ls));
  PetscCallAbort(comm, KSPGetPC(ksp, &pc));
  const Check checks[] = {{"-ts_type", [&](const char* t) { return TSSetType(ts, t); }},
                          {"-ts_adapt_type", [&](const char* t) { return TSAdaptSetType(adapt, t); }},
                          {"-snes_type", [&](const char* t) { return SNESSetType(snes, t); }},
                          {"-snes_linesearch_type", [&](const char* t) { return SNESLineSearchSetType(ls, t); }},
                          {"-ksp_type", [&](const char* t) { return KSPSetType(ksp, t); }},
                          {"-pc_type", [&](const char* t) { return PCSetType(pc, t); }}};
  // PETSc's message for an unknown type is a traceback; here it is one line of ours.
  PetscCallAbort(comm, PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  for (const Check& c : checks) {
    char value[256];
    PetscBool set = PETSC_FALSE;
    if (PetscOptionsGetString(nullptr, nullptr, c.option, value, sizeof value, &set) || !set) continue;
    if (c.set(value)) {
      message = std::string("unknown solver type '") + value + "' for " + c.option + " (see its -help list)";
      break;
    }
  }
  PetscCallAbort(comm, PetscPopErrorHandler());
  PetscCallAbort(comm, TSDestroy(&ts));
  return message;
}

// latticedyn's own options whose value is restricted, as a message ("" if every one is usable):
// checked with the solver types, before anything is written.
std::string unusable_own_option(MPI_Comm comm) {
  PetscInt block_size = 6;
  PetscBool set = PETSC_FALSE;
  PetscCallAbort(comm, PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode read = PetscOptionsGetInt(nullptr, nullptr, "-dyn_block_size", &block_size, &set);
  PetscCallAbort(comm, PetscPopErrorHandler());
  const std::string expected = ": expected 6 (each node's translation and rotation in one block), 3 or 1 (no blocks)";
  if (read) return "-dyn_block_size is not a whole number" + expected;
  const auto& sizes = GeneralizedAlphaIntegrator::kBlockSizes;
  if (set && std::find(sizes.begin(), sizes.end(), block_size) == sizes.end())
    return "-dyn_block_size " + std::to_string(block_size) + expected;
  return "";
}

// The results file a run writes: <output directory>/<name>.h5.
std::filesystem::path results_file(const Simulation& sim, const CommandOptions& opt) {
  const std::string dir = opt.output_directory.empty() ? sim.output.directory : opt.output_directory;
  return std::filesystem::path(dir.empty() ? "." : dir) / (sim.output.name + ".h5");
}

// --restart FILE or FILE:STEP (STEP: digits), as the file and the step (-1: the last checkpoint).
std::pair<std::string, long> split_restart(const std::string& arg) {
  const std::size_t colon = arg.rfind(':');
  if (colon == std::string::npos || colon + 1 == arg.size() || arg.size() - colon > 16) return {arg, -1};
  for (std::size_t i = colon + 1; i < arg.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(arg[i]))) return {arg, -1};
  return {arg.substr(0, colon), std::stol(arg.substr(colon + 1))};
}

// The checkpoint a run continues from (every rank reads it), checked against the model; "" or
// what is wrong.
std::string load_checkpoint(const Simulation& sim, const std::string& restart, Checkpoint* c) {
  const auto [file, step] = split_restart(restart);
  try {
    *c = read_checkpoint(file, step);
  } catch (const std::runtime_error& e) {
    return std::string("--restart: ") + e.what();
  }
  char buf[512];
  if (c->integrator != integrator_name(sim.dynamics.integrator)) {
    std::snprintf(buf, sizeof buf, "--restart: the checkpoint was written by the %s integrator, the model asks for %s",
                  c->integrator.c_str(), integrator_name(sim.dynamics.integrator));
    return buf;
  }
  if (c->time >= sim.dynamics.t_end - 1e-9 * std::max(1.0, std::abs(c->time))) {
    std::snprintf(buf, sizeof buf,
                  "--restart: the checkpoint at t = %.9g s is not before the model's t_end = %.9g s: nothing to "
                  "continue (raise solver.dynamics.t_end)",
                  c->time, sim.dynamics.t_end);
    return buf;
  }
  return "";
}

// Creates the writer on rank 0, or with `collective` on every rank, which then write the .h5
// together; a failure (e.g. an unwritable folder) is shared with all ranks so that they stop
// together.
std::unique_ptr<ResultWriter> open_writer(const Simulation& sim, const CommandOptions& opt, MPI_Comm comm,
                                          std::string* error,
                                          std::optional<ResultContinuation> continuation = std::nullopt,
                                          const std::string& base_name = "", bool collective = false) {
  std::unique_ptr<ResultWriter> writer;
  int ok = 1;
  if (collective || is_root(comm)) {
    try {
      ResultWriterOptions o;
      o.directory = opt.output_directory.empty() ? sim.output.directory : opt.output_directory;
      o.base_name = base_name.empty() ? sim.output.name : base_name;
      o.probe_joints = sim.output.probe_joints;
      o.body_blocks = sim.output.body_blocks;
      o.continuation = continuation;
      if (collective) o.comm = comm;
      writer = std::make_unique<ResultWriter>(sim.model, o);  // collective: fails on every rank alike
    } catch (const std::exception& e) {
      *error = e.what();
      ok = 0;
    }
  }
  if (collective) return ok ? std::move(writer) : nullptr;
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  if (!ok && !is_root(comm)) *error = "the results could not be opened on rank 0";
  return writer;
}

// Whether a run on several ranks writes its results collectively (each rank its part, through
// MPI-IO) instead of gathering them to rank 0: yes unless -output_collective 0.
bool collective_output(MPI_Comm comm) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  PetscBool collective = PETSC_TRUE;
  PetscCallAbort(comm, PetscOptionsGetBool(nullptr, nullptr, "-output_collective", &collective, nullptr));
  return ranks > 1 && collective;
}

// Peak resident memory of the largest rank and of all ranks together (getrusage's high-water mark).
std::string peak_memory(MPI_Comm comm) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double mine = usage.ru_maxrss / 1024.0;  // KiB on Linux
  double largest = 0.0, total = 0.0;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  MPI_Reduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, 0, comm);
  MPI_Reduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, 0, comm);
  char buf[160];
  if (ranks > 1)
    std::snprintf(buf, sizeof buf, "peak memory: %.0f MiB on the largest of %d ranks, %.0f MiB in all\n", largest, ranks,
                  total);
  else
    std::snprintf(buf, sizeof buf, "peak memory: %.0f MiB\n", largest);
  return buf;
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// "setup: parse 4.9 s, model 4.2 s, numbering and assembly plan 0.9 s, results file 0.1 s", each
// the slowest rank's (every rank reads the whole model).
std::string setup_summary(MPI_Comm comm, const Simulation& sim, double numbering, double results) {
  double mine[4] = {sim.parse_seconds, sim.build_seconds, numbering, results}, slowest[4];
  MPI_Reduce(mine, slowest, 4, MPI_DOUBLE, MPI_MAX, 0, comm);
  char buf[256];
  std::snprintf(buf, sizeof buf, "setup: parse %.3g s, model %.3g s, numbering and assembly plan %.3g s", slowest[0],
                slowest[1], slowest[2]);
  std::string out = buf;
  if (results >= 0.0) {
    std::snprintf(buf, sizeof buf, ", results file %.3g s", slowest[3]);
    out += buf;
  }
  return out + "\n";
}

std::string where_results(const ResultWriter* w) {
  if (!w) return "";
  return "results: " + w->h5_path().string() + " (open " + w->xdmf_path().string() + " in ParaView), probes: " +
         w->csv_path().string() + "\n";
}

// Runs statics and/or dynamics with results, progress and the closing summary.
int command_solve(Simulation& sim, const CommandOptions& opt, MPI_Comm comm, bool statics, bool dynamics) {
  if (!opt.output_directory.empty()) sim.output.directory = opt.output_directory;
  print_root(comm, describe_model(sim.model));
  std::string error = unknown_solver_type(comm);
  if (error.empty()) error = unusable_own_option(comm);
  if (!error.empty()) {
    error_root(comm, error);
    return kInputError;
  }
  // A run continued from a checkpoint: no statics, time from the checkpoint, and its own results
  // file continued in place (another file: written anew from the checkpoint on).
  std::optional<Checkpoint> checkpoint;
  std::optional<ResultContinuation> continuation;
  if (!opt.restart.empty() && sim.dynamics.hydraulic_cosimulation) {
    error_root(comm, "--restart: a hydraulic co-simulation (solver.dynamics.hydraulic_coupling: cosimulation) keeps no "
                     "checkpoints to continue; run it from the start");
    return kInputError;
  }
  if (!opt.restart.empty()) {
    checkpoint.emplace();
    error = load_checkpoint(sim, opt.restart, &*checkpoint);
    if (!error.empty()) {
      error_root(comm, error);
      return kInputError;
    }
    statics = false;
    sim.dynamics.t_start = checkpoint->time;
    std::error_code ec;
    if (std::filesystem::equivalent(split_restart(opt.restart).first, results_file(sim, opt), ec))
      continuation = ResultContinuation{checkpoint->outputs_written, checkpoint->time};
    MPI_Barrier(comm);  // every rank has closed the file before rank 0 opens it to continue it
  } else if (dynamics && !sim.start_coordinates.empty()) {
    print_root(comm,
               "latticedyn: warning: start_state sets the coordinates only (velocities zero, time from the model); "
               "it is not a restart: --restart RESULTS.h5 continues a run exactly\n",
               stderr);
  }
  const auto opened = Clock::now();
  auto writer = open_writer(sim, opt, comm, &error, continuation, "", collective_output(comm));
  const double results = seconds_since(opened);
  if (!error.empty()) {
    error_root(comm, error);
    return kInputError;
  }
  const auto numbered = Clock::now();
  SystemAssembler sa(sim.model, comm);
  if (checkpoint && checkpoint->coordinates.size() != static_cast<std::size_t>(sa.dofs().global_size())) {
    error_root(comm, "--restart: the checkpoint holds " + std::to_string(checkpoint->coordinates.size()) +
                         " coordinates, the model has " + std::to_string(sa.dofs().global_size()) +
                         ": it was written for another model");
    return kInputError;
  }
  Vec U, V, A = nullptr;
  PetscCallAbort(comm, sa.create_vector(&U));
  PetscCallAbort(comm, sa.create_vector(&V));
  if (checkpoint) {
    PetscCallAbort(comm, sa.create_vector(&A));
    set_state_in_model_order(sa.dofs(), U, checkpoint->coordinates);
    set_state_in_model_order(sa.dofs(), V, checkpoint->velocities);
    set_state_in_model_order(sa.dofs(), A, checkpoint->accelerations);
  } else {
    PetscCallAbort(comm, initial_state(sim, sa, U, V));
  }
  print_root(comm, setup_summary(comm, sim, seconds_since(numbered), results));

  const double t0 = dynamics ? sim.dynamics.t_start : sim.statics.time;
  const double t1 = dynamics ? sim.dynamics.t_end : sim.statics.time;
  OutputObserver out(sa, writer.get(), sim.output.interval, t1, integrator_name(sim.dynamics.integrator));
  if (continuation) {
    out.resume(*checkpoint);
  } else if (checkpoint) {  // a new results file starts with the checkpoint's state
    StepInfo first{static_cast<int>(checkpoint->resume.step), checkpoint->time, 0.0, U, V, A,
                   checkpoint->velocities_are_rates ? Parametrization::rotation_vector_rates
                                                    : Parametrization::velocity_variables};
    PetscCallAbort(comm, out.on_step(first));
  }
  PetscReal t_stop = t1;  // -ts_max_time ends a run early: the progress line counts to it
  if (dynamics) PetscCallAbort(comm, PetscOptionsGetReal(nullptr, nullptr, "-ts_max_time", &t_stop, nullptr));
  ProgressObserver progress(comm, t0, dynamics ? std::min<double>(t1, t_stop) : t1);
  FaultInjection fault(comm);
  InterruptObserver interrupt(comm);
  ObserverList observers;
  observers.add(&out);
  observers.add(&progress);
  observers.add(&fault);
  observers.add(&interrupt);
  SimulationOutcome outcome;
  PetscCallAbort(comm, simulate(sim, sa, U, V, statics, dynamics, &observers, &outcome,
                                checkpoint ? &checkpoint->resume : nullptr, A));
  progress.done();
  // The last state is written even when a solver stopped early (for statics: the equilibrium,
  // or the last converged load level).
  const double t_last = outcome.dynamics_run ? outcome.dynamics.time_reached : t0;
  PetscCallAbort(comm, out.finish(t_last, U, V, Parametrization::rotation_vector_rates));

  std::string text;
  if (outcome.static_run) {
    char wall[64];
    std::snprintf(wall, sizeof wall, "; wall %.3g s", outcome.statics.wall_seconds);
    if (outcome.statics.converged)
      text += outcome.statics.message + wall + "\n";
    else
      error_root(comm, outcome.statics.message + wall);
  }
  if (outcome.dynamics_run) {
    const DynamicReport& r = outcome.dynamics;
    char buf[1024];
    const double simulated = r.time_reached - sim.dynamics.t_start;
    std::snprintf(buf, sizeof buf,
                  "dynamics %s: %ld steps (%ld rejected), %ld Newton iterations (%.2f per step), %ld Jacobians, %ld "
                  "rotation rescales, wall %.3g s (%.3g x real time), %d outputs in %.3g s; largest "
                  "constraint violation over the run: %s\n",
                  r.completed ? "completed" : r.interrupted ? "INTERRUPTED" : "FAILED", r.steps, r.rejected_steps, r.newton_iterations,
                  r.steps ? static_cast<double>(r.newton_iterations) / r.steps : 0.0, r.jacobians, r.rotation_rescales,
                  r.wall_seconds,
                  r.wall_seconds > 0 ? simulated / r.wall_seconds : 0.0, out.written(), out.seconds(),
                  describe_violation(sim.model, r.max_violation, r.violation_constraint).c_str());
    if (r.interrupted)
      error_root(comm, std::string(r.message) + " by " + interrupt.signal_name() + "; results written up to there");
    else if (!r.completed)
      error_root(comm, r.message);
    text += buf;
    if (!r.linear_solver.empty()) text += "linear solver: " + r.linear_solver + "\n";
    if (const EnergyAccount* a = out.energy_account()) {
      std::snprintf(buf, sizeof buf,
                    "energy account: supplied %.6g J = mechanical energy change %.6g J + dissipated %.6g J + into oil "
                    "compression %.6g J (oil energy change %.6g J) + imbalance %.3g J (%.2e of the largest term: "
                    "drives, loads, mechanical and numerical damping, time integration)\n",
                    a->supplied, a->mechanical_change, a->dissipated, a->compression, a->fluid_change, a->imbalance(),
                    a->relative_imbalance());
      text += buf;
    }
  }
  if (writer)
    if (const std::optional<MemberPeak> peak = writer->member_peak())
      text += "most utilized member: " + describe_member_peak(sim.model, *peak) + "\n";
  text += peak_memory(comm);
  if (out.checkpoints() > 0 && writer) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, "checkpoint: step %ld, t = %.9g s (`latticedyn run %s --restart %s` continues from it)\n",
                  out.last_checkpoint_step(), out.last_checkpoint_time(), sim.source.c_str(),
                  writer->h5_path().c_str());
    text += buf;
  }
  print_root(comm, text + where_results(writer.get()));
  VecDestroy(&U);
  VecDestroy(&V);
  VecDestroy(&A);
  if (outcome.dynamics_run && outcome.dynamics.interrupted) return interrupt.exit_code();
  return outcome.ok() ? kSuccess : kSolverFailure;
}

// Batches and the control pipeline: one assembly thread per rank unless -assembly_threads says
// otherwise. The ranks already fill the cores, and a case's numbers then do not depend on the
// thread count (sums in one order): identical on 1 and n ranks.
void one_thread_per_rank(MPI_Comm comm) {
  PetscBool threads_set = PETSC_FALSE;
  PetscCallAbort(comm, PetscOptionsHasName(nullptr, nullptr, "-assembly_threads", &threads_set));
  if (!threads_set) PetscCallAbort(comm, PetscOptionsSetValue(nullptr, "-assembly_threads", "1"));
}

}  // namespace

int command_check(const Simulation& sim, MPI_Comm comm) {
  const auto started = Clock::now();
  print_root(comm, describe_model(sim.model));
  // The initial state as the solvers will see it, on this process alone.
  const auto numbered = Clock::now();
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  ModelState state(sim.model, sa.dofs());
  Vec U, V;
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&U));
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(&V));
  PetscCallAbort(PETSC_COMM_SELF, initial_state(sim, sa, U, V));
  PetscCallAbort(PETSC_COMM_SELF, sa.gather(sim.run_dynamics ? sim.dynamics.t_start : sim.statics.time, U, V, nullptr,
                                            Parametrization::rotation_vector_rates, &state));
  VecDestroy(&U);
  VecDestroy(&V);
  const double numbering = seconds_since(numbered);
  const auto [violation, where] = state.max_constraint_violation();
  std::string text = setup_summary(comm, sim, numbering, -1.0) + "initial state: largest constraint violation " +
                     describe_violation(sim.model, violation, where) + "\n";
  if (violation > 1e-6)
    text += "warning: the initial state does not satisfy its constraints; the static solve or the first time steps "
            "will pull the joints together\n";
  if (sim.run_static) text += "solver: static equilibrium first\n";
  if (sim.run_dynamics) {
    char buf[256];
    const std::string method = sim.dynamics.integrator == IntegratorKind::baumgarte     ? "Baumgarte / Runge-Kutta"
                               : sim.dynamics.integrator == IntegratorKind::implicit_rk ? "implicit Runge-Kutta (" +
                                                                                               sim.dynamics.implicit_method + ")"
                               : sim.dynamics.integrator == IntegratorKind::minimum_dof
                                   ? "minimum-DoF joint coordinates (Lagrange II) / Runge-Kutta " + sim.dynamics.rk_type
                                   : "generalized-alpha";
    std::snprintf(buf, sizeof buf, "solver: %s from t = %g to %g s, time step %g\n", method.c_str(),
                  sim.dynamics.t_start, sim.dynamics.t_end, sim.dynamics.time_step);
    text += buf;
  }
  char wall[96];
  std::snprintf(wall, sizeof wall, "the model is valid (checked in %.3g s; reading it %.3g s)\n", seconds_since(started),
                sim.parse_seconds + sim.build_seconds);
  text += "output: " + sim.output.directory + "/" + sim.output.name + ".h5\n" + wall;
  print_root(comm, text);
  return kSuccess;
}

int command_static(Simulation& sim, const CommandOptions& opt, MPI_Comm comm) {
  return command_solve(sim, opt, comm, true, false);
}

namespace {

// What an analysis about the equilibrium found: a table for the terminal, rows for the CSV and
// the shapes (velocity variables, largest entry 1) to draw. The vectors stay the caller's.
struct EquilibriumModes {
  std::string table, csv_header;
  std::vector<std::string> csv_rows;
  std::vector<Vec> shapes;
  std::string shortfall;  ///< why fewer were found than asked for, or empty
};

using EquilibriumAnalysis =
    std::function<PetscErrorCode(SystemAssembler&, Vec U, Vec V, SimulationOutcome*, EquilibriumModes*)>;

// The equilibrium, then an eigenanalysis about it; writes <name>_<suffix>.h5/.xdmf (step 0 the
// equilibrium, step k shape k) and <name>_<suffix>.csv beside a run's results, not over them.
int command_equilibrium_modes(Simulation& sim, const CommandOptions& opt, MPI_Comm comm, const std::string& suffix,
                              const EquilibriumAnalysis& analyse, const std::function<void()>& release) {
  if (!opt.output_directory.empty()) sim.output.directory = opt.output_directory;
  const auto started = Clock::now();
  print_root(comm, describe_model(sim.model));
  std::string error;
  auto writer = open_writer(sim, opt, comm, &error, std::nullopt, sim.output.name + "_" + suffix);
  if (!error.empty()) {
    error_root(comm, error);
    return kInputError;
  }
  SystemAssembler sa(sim.model, comm);
  Vec U, V, W;
  PetscCallAbort(comm, sa.create_vector(&U));
  PetscCallAbort(comm, sa.create_vector(&V));
  PetscCallAbort(comm, initial_state(sim, sa, U, V));
  SimulationOutcome outcome;
  EquilibriumModes found;
  PetscCallAbort(comm, analyse(sa, U, V, &outcome, &found));
  if (!outcome.statics.converged) {
    error_root(comm, outcome.statics.message + " (the " + suffix + " need the equilibrium to linearise about)");
    VecDestroy(&U);
    VecDestroy(&V);
    return kSolverFailure;
  }
  print_root(comm, outcome.statics.message + "\n");
  const double t = sim.statics.time;
  // Output step 0: the equilibrium; step k: the equilibrium plus shape k scaled so that its largest
  // node displacement is 5 % of the model's size, for ParaView.
  ModelState state(sim.model, sa.dofs());
  PetscCallAbort(comm, sa.gather(t, U, V, nullptr, Parametrization::rotation_vector_rates, &state));
  double size = 1.0;
  if (is_root(comm)) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (std::size_t b = 0; b < sim.model.blocks.size(); ++b)
      if (sim.model.blocks[b].kind == SlotKind::translation) {
        lo = lo.cwiseMin(state.block(static_cast<int>(b)).pos);
        hi = hi.cwiseMax(state.block(static_cast<int>(b)).pos);
      }
    size = std::max(1e-6, (hi - lo).maxCoeff());
  }
  MPI_Bcast(&size, 1, MPI_DOUBLE, 0, comm);
  if (writer) writer->append(state);
  std::vector<Vec3> at_rest;
  if (is_root(comm))
    for (std::size_t b = 0; b < sim.model.blocks.size(); ++b)
      if (sim.model.blocks[b].kind == SlotKind::translation) at_rest.push_back(state.block(static_cast<int>(b)).pos);
  // The largest node displacement of a small multiple of the shape, per unit of that multiple.
  const auto largest_displacement = [&](Vec shape) {
    const double probe = 1e-6 * size;
    PetscCallAbort(comm, VecWAXPY(W, probe, shape, U));
    PetscCallAbort(comm, sa.gather(t, W, V, nullptr, Parametrization::rotation_vector_rates, &state));
    double largest = 0.0;
    if (is_root(comm)) {
      std::size_t i = 0;
      for (std::size_t b = 0; b < sim.model.blocks.size(); ++b)
        if (sim.model.blocks[b].kind == SlotKind::translation)
          largest = std::max(largest, (state.block(static_cast<int>(b)).pos - at_rest[i++]).norm());
    }
    MPI_Bcast(&largest, 1, MPI_DOUBLE, 0, comm);
    return largest / probe;
  };
  PetscCallAbort(comm, VecDuplicate(U, &W));
  for (std::size_t k = 0; k < found.shapes.size(); ++k) {
    // The shape is in velocity variables; for the drawing add it to the coordinates (rotation
    // vectors, equal to first order near the reference orientation), so that its largest node
    // displacement is 5 % of the model's size (a shape that moves no node, e.g. a spin: its
    // largest coordinate).
    const double per_unit = largest_displacement(found.shapes[k]);
    const double amplitude = 0.05 * size / (per_unit > 1e-9 ? per_unit : 1.0);
    PetscCallAbort(comm, VecWAXPY(W, amplitude, found.shapes[k], U));
    PetscCallAbort(comm, sa.gather(static_cast<double>(k + 1), W, V, nullptr, Parametrization::rotation_vector_rates, &state));
    if (writer) writer->append(state);
  }
  std::string table = found.table;
  if (writer && is_root(comm)) {
    const auto csv = writer->h5_path().parent_path() / (sim.output.name + "_" + suffix + ".csv");
    std::ofstream f(csv);
    f << found.csv_header << "\n";
    for (const std::string& row : found.csv_rows) f << row << "\n";
    table += "table: " + csv.string() + "\n";
  }
  if (!found.shortfall.empty()) table += "warning: " + found.shortfall + "\n";
  char wall[64];
  std::snprintf(wall, sizeof wall, "%s: wall %.3g s\n", suffix.c_str(), seconds_since(started));
  print_root(comm, table + "shapes: output steps 1.." + std::to_string(found.shapes.size()) +
                       " (step 0: the equilibrium), 5 % of the model's size\n" + wall + where_results(writer.get()));
  release();
  VecDestroy(&U);
  VecDestroy(&V);
  VecDestroy(&W);
  return kSuccess;
}

}  // namespace

int command_modes(Simulation& sim, const CommandOptions& opt, MPI_Comm comm) {
  std::vector<Mode> modes;
  const auto analyse = [&](SystemAssembler& sa, Vec U, Vec V, SimulationOutcome* outcome, EquilibriumModes* out) {
    PetscFunctionBeginUser;
    std::string message;
    PetscCall(equilibrium_modes(sim, sa, U, V, opt.modes, &modes, outcome, &message));
    out->table = "mode  frequency (Hz)  omega^2 (1/s^2)  damping ratio  relative residual\n";
    out->csv_header = "mode,frequency_hz,omega2,damping_ratio";
    for (std::size_t k = 0; k < modes.size(); ++k) {
      char line[160];
      std::snprintf(line, sizeof line, "%4zu  %14.6g  %15.6g  %13.4g  %.1e\n", k + 1, modes[k].frequency,
                    modes[k].omega2, modes[k].damping_ratio, modes[k].residual);
      out->table += line;
      std::snprintf(line, sizeof line, "%zu,%.10g,%.10g,%.6g", k + 1, modes[k].frequency, modes[k].omega2,
                    modes[k].damping_ratio);
      out->csv_rows.push_back(line);
      out->shapes.push_back(modes[k].vector);
    }
    if (static_cast<int>(modes.size()) < opt.modes) out->shortfall = message;
    PetscFunctionReturn(0);
  };
  return command_equilibrium_modes(sim, opt, comm, "modes", analyse, [&] { destroy_modes(modes); });
}

int command_buckling(Simulation& sim, const CommandOptions& opt, MPI_Comm comm) {
  std::vector<BucklingMode> modes;
  const auto analyse = [&](SystemAssembler& sa, Vec U, Vec V, SimulationOutcome* outcome, EquilibriumModes* out) {
    PetscFunctionBeginUser;
    std::string message;
    PetscCall(equilibrium_buckling(sim, sa, U, V, opt.modes, &modes, outcome, &message));
    out->table = "mode  load factor     relative residual\n";
    out->csv_header = "mode,load_factor";
    for (std::size_t k = 0; k < modes.size(); ++k) {
      char line[128];
      std::snprintf(line, sizeof line, "%4zu  %14.8g  %.1e%s\n", k + 1, modes[k].factor, modes[k].residual,
                    modes[k].factor < 0 ? "  (the loads reversed)" : "");
      out->table += line;
      std::snprintf(line, sizeof line, "%zu,%.10g", k + 1, modes[k].factor);
      out->csv_rows.push_back(line);
      out->shapes.push_back(modes[k].vector);
    }
    const auto critical = std::find_if(modes.begin(), modes.end(), [](const BucklingMode& m) { return m.factor > 0; });
    if (critical != modes.end()) {
      char line[160];
      std::snprintf(line, sizeof line, "critical load factor %.8g (mode %td): the loads times it buckle the model\n",
                    critical->factor, critical - modes.begin() + 1);
      out->table += line;
    }
    if (static_cast<int>(modes.size()) < opt.modes) out->shortfall = message;
    PetscFunctionReturn(0);
  };
  return command_equilibrium_modes(sim, opt, comm, "buckling", analyse, [&] { destroy_modes(modes); });
}

int command_path(Simulation& sim, const CommandOptions& opt, MPI_Comm comm) {
  if (!opt.output_directory.empty()) sim.output.directory = opt.output_directory;
  const auto started = Clock::now();
  print_root(comm, describe_model(sim.model));
  if (!sim.path.valid()) {
    error_root(comm, "solver.path: inconsistent settings");
    return kInputError;
  }
  std::string error;
  auto writer = open_writer(sim, opt, comm, &error, std::nullopt, sim.output.name + "_path");
  if (!error.empty()) {
    error_root(comm, error);
    return kInputError;
  }
  SystemAssembler sa(sim.model, comm);
  Vec U, V;
  PetscCallAbort(comm, sa.create_vector(&U));
  PetscCallAbort(comm, sa.create_vector(&V));
  PetscCallAbort(comm, initial_state(sim, sa, U, V));
  PetscCallAbort(comm, VecZeroEntries(V));
  // Output step k: path point k (step 0 the unloaded start); the CSV: the load factor and the
  // probe joints' displacements from the start.
  ModelState state(sim.model, sa.dofs());
  std::vector<Vec3> start;
  std::vector<std::string> rows;
  std::vector<double> factors;
  const auto on_point = [&](const PathPoint& p) {
    PetscFunctionBeginUser;
    PetscCall(sa.gather(static_cast<double>(p.step), p.U, V, nullptr, Parametrization::rotation_vector_rates, &state));
    if (writer) writer->append(state);
    factors.push_back(p.load_factor);
    if (is_root(comm)) {
      char cell[64];
      std::snprintf(cell, sizeof cell, "%d,%.12g,%d,%.6g", p.step, p.load_factor, p.iterations, p.arc_length);
      std::string row = cell;
      for (std::size_t k = 0; k < sim.output.probe_joints.size(); ++k) {
        const Vec3 r = state.joint_position(sim.output.probe_joints[k]);
        if (p.step == 0) start.push_back(r);
        const Vec3 u = r - start[k];
        std::snprintf(cell, sizeof cell, ",%.12g,%.12g,%.12g", u.x(), u.y(), u.z());
        row += cell;
      }
      rows.push_back(row);
      std::printf("path: step %d, load factor %.6g, %d iterations, arc %.3g\n", p.step, p.load_factor, p.iterations,
                  p.arc_length);
      std::fflush(stdout);
    }
    PetscFunctionReturn(0);
  };
  ArcLengthSolver solver(sa, sim.path);
  PathReport report;
  PetscCallAbort(comm, solver.trace(U, 0.0, on_point, &report));
  std::string text = "path: " + std::to_string(report.steps) + " points, " + std::to_string(report.newton_iterations) +
                     " Newton iterations, " + std::to_string(report.cuts) + " arcs halved; " + report.message + "\n";
  // Limit points: where the load factor turns (a local maximum or minimum along the path).
  for (const LimitPoint& p : limit_points(factors)) {
    char line[128];
    std::snprintf(line, sizeof line, "%s load factor %.8g at step %zu (a %s)\n",
                  p.maximum ? "limit point: maximum" : "limit point: minimum", factors[p.index], p.index,
                  p.maximum ? "limit load" : "snap-through's lowest point");
    text += line;
  }
  if (writer && is_root(comm)) {
    const auto csv = writer->h5_path().parent_path() / (sim.output.name + "_path.csv");
    std::ofstream f(csv);
    f << "step,load_factor,iterations,arc_length";
    for (int j : sim.output.probe_joints)
      for (const char* c : {"x", "y", "z"}) f << ",u_" << sim.model.joints[j].name << "." << c << " [m]";
    f << "\n";
    for (const std::string& row : rows) f << row << "\n";
    text += "load-displacement path: " + csv.string() + "\n";
  }
  char wall[64];
  std::snprintf(wall, sizeof wall, "path: wall %.3g s\n", seconds_since(started));
  print_root(comm, text + wall + where_results(writer.get()));
  VecDestroy(&U);
  VecDestroy(&V);
  return report.completed ? kSuccess : kSolverFailure;
}

int command_run(Simulation& sim, const CommandOptions& opt, MPI_Comm comm) {
  if (!sim.run_dynamics) {
    error_root(comm, sim.source + ": the model has no solver.dynamics section; add one (t_end, time_step) or use "
                                  "'latticedyn static'");
    return kInputError;
  }
  return command_solve(sim, opt, comm, sim.run_static, true);
}

int command_batch(const CommandOptions& opt, MPI_Comm comm) {
  const BatchSpec spec = read_batch(opt.model_path);
  one_thread_per_rank(comm);
  int size = 1;
  MPI_Comm_size(comm, &size);
  char buf[512];
  std::snprintf(buf, sizeof buf, "batch '%s': %zu cases in %d chain%s of model %s, %s analysis, %d rank%s\n",
                spec.source.c_str(), spec.cases.size(), spec.chains, spec.chains == 1 ? "" : "s", spec.model_path.c_str(),
                spec.dynamics ? "dynamic" : "static", size, size == 1 ? "" : "s");
  print_root(comm, buf);
  BatchOptions bo;
  bo.output_directory = opt.output_directory;
  bo.groups = opt.groups;
  bo.retry_failed = opt.retry_failed;
  BatchSummary s;
  try {
    s = run_batch(spec, bo, comm);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {  // the folder holds another batch, or cannot be written
    error_root(comm, e.what());
    return kInputError;
  }
  std::snprintf(buf, sizeof buf,
                "batch finished: %d cases, %d ok, %d failed, %d not run; %d taken from an earlier run; wall %.3g s\n"
                "table: %s and %s\n",
                s.cases, s.ok, s.failed, s.cases - s.ok - s.failed, s.skipped, s.wall_seconds, s.csv_path.c_str(),
                s.h5_path.c_str());
  print_root(comm, buf);
  if (s.failed > 0) {
    std::string list;
    int shown = 0;
    for (const auto& [i, r] : s.records)
      if (!r.ok && shown++ < 5) list += "  case " + std::to_string(i) + " (" + spec.cases[i].label + "): " + r.error + "\n";
    print_root(comm, "failed cases" + std::string(s.failed > 5 ? " (the first 5)" : "") + ":\n" + list, stderr);
  }
  return s.failed > 0 || s.ok < s.cases ? kSolverFailure : kSuccess;
}

int command_control(const CommandOptions& opt, MPI_Comm comm) {
  const ControlSpec spec = read_control(opt.model_path);
  one_thread_per_rank(comm);
  int size = 1;
  MPI_Comm_size(comm, &size);
  print_root(comm, "control '" + spec.source + "': mapping batch of " + std::to_string(spec.mapping.cases.size()) +
                       " cases on " + std::to_string(size) + " rank(s), then surfaces, optimal trajectory, control "
                       "table and verification run on rank 0\n");
  ControlOptions co;
  co.output_directory = opt.output_directory;
  co.groups = opt.groups;
  ControlSummary s;
  try {
    s = run_control(spec, co, comm);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    error_root(comm, e.what());
    return kInputError;
  }
  if (!s.ok) {
    error_root(comm, s.message);
    return kSolverFailure;
  }
  char buf[512];
  if (spec.verify)
    std::snprintf(buf, sizeof buf,
                  "control finished: tracking error largest %.3g m, RMS %.3g m; residual sway %.3g m; end point %.3g m "
                  "from the target\n",
                  s.tracking_max, s.tracking_rms, s.residual_sway, s.final_offset);
  else
    std::snprintf(buf, sizeof buf, "control finished (verification run skipped: verification.run is false)\n");
  print_root(comm, std::string(buf) + "report: " + s.message + " (plots: /usr/bin/python3 scripts/control_report.py " +
                       std::filesystem::path(s.message).parent_path().string() + ")\n");
  return kSuccess;
}

}  // namespace latticedyn
