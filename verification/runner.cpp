// latticedyn_verify CASE.check.yaml: runs the model a verification case names and compares the
// quantities it lists with their reference values (closed forms or published numbers, named in
// the case). Prints one line per check; exit code 0 when all pass, 1 otherwise, 2 for bad input.
#include "verification/trajectory.hpp"

#include "io/input_node.hpp"
#include "io/hydraulic_readers.hpp"
#include "io/model_reader.hpp"

#include <slepcsys.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <string>

namespace latticedyn {
namespace {

struct Result {
  std::string what;
  double value = 0.0;
  std::string expectation;
  bool pass = false;
};

int component_of(const InputNode& n) {
  const std::string c = n.as_choice({"x", "y", "z"});
  return c[0] - 'x';
}

int body_element(const Model& m, const InputNode& n) {
  const int b = m.find_body(n.as_string());
  if (b < 0) n.fail("no body named '" + n.as_string() + "' in the model");
  if (m.bodies[b].elements.empty()) n.fail("body '" + n.as_string() + "' has no element");
  return m.bodies[b].elements.front();
}

int joint_of(const Model& m, const InputNode& n) {
  const int j = m.find_joint(n.as_string());
  if (j < 0) n.fail("no joint named '" + n.as_string() + "' in the model");
  return j;
}

int constraint_of(const Model& m, const InputNode& n) {
  for (std::size_t c = 0; c < m.constraints.size(); ++c)
    if (m.constraints[c].name == n.as_string()) return static_cast<int>(c);
  n.fail("no constraint named '" + n.as_string() + "' with multipliers in the model");
}

// The members of a body at the run's final state (every member of each of its elements, in order).
std::vector<MemberStress> final_members(const Trajectory& tr, int body) {
  const Model& m = tr.simulation->model;
  std::vector<MemberStress> out;
  ElementOutput o;
  for (int e : m.bodies[static_cast<std::size_t>(body)].elements) {
    m.elements[static_cast<std::size_t>(e)].element->output(tr.final_state->element_slots(e), tr.final_state->context(), o);
    out.insert(out.end(), o.members.begin(), o.members.end());
  }
  return out;
}

// Compares against {expected, abs_tol | rel_tol}.
Result compare(const InputNode& c, const std::string& what, double value) {
  const double expected = c["expected"].as_double();
  double tol = 0.0;
  char buf[160];
  if (c.has("abs_tol")) {
    tol = c["abs_tol"].as_positive();
    std::snprintf(buf, sizeof buf, "%.10g +- %.3g", expected, tol);
  } else {
    tol = c["rel_tol"].as_positive() * std::abs(expected);
    std::snprintf(buf, sizeof buf, "%.10g +- %.3g (rel %.1e)", expected, tol, c["rel_tol"].as_double());
  }
  return Result{what, value, buf, std::isfinite(value) && std::abs(value - expected) <= tol};
}

Result below(const std::string& what, double value, double max) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "<= %.3g", max);
  return Result{what, value, buf, std::isfinite(value) && value <= max};
}

// The model's initial state in new vectors (the caller destroys them).
void start(const Simulation& sim, SystemAssembler& sa, Vec* U, Vec* V) {
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(U));
  PetscCallAbort(PETSC_COMM_SELF, sa.create_vector(V));
  PetscCallAbort(PETSC_COMM_SELF, initial_state(sim, sa, *U, *V));
}

// Natural frequency (Hz) of mode `mode` (from 1) about the model's static equilibrium, on rank 0's
// own communicator (the modal solve is small and serial here).
double natural_frequency(const std::string& model_path, int mode) {
  Simulation sim = read_simulation(model_path);
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  start(sim, sa, &U, &V);
  SimulationOutcome outcome;
  std::vector<Mode> modes;
  std::string message;
  PetscCallAbort(PETSC_COMM_SELF, equilibrium_modes(sim, sa, U, V, mode, &modes, &outcome, &message));
  const double f = static_cast<int>(modes.size()) >= mode ? modes[mode - 1].frequency : NAN;
  destroy_modes(modes);
  VecDestroy(&U);
  VecDestroy(&V);
  return f;
}


// The `mode`-th positive load factor (from 1; the loads as given, not reversed) of linearized
// buckling about the model's static equilibrium under its loads, on rank 0's own communicator.
double buckling_factor(const std::string& model_path, int mode) {
  Simulation sim = read_simulation(model_path);
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  start(sim, sa, &U, &V);
  SimulationOutcome outcome;
  std::vector<BucklingMode> modes;
  std::string message;
  // Reversed loads can buckle the model as early (a symmetric structure): ask for both signs.
  PetscCallAbort(PETSC_COMM_SELF, equilibrium_buckling(sim, sa, U, V, 2 * mode + 2, &modes, &outcome, &message));
  double f = NAN;
  int positive = 0;
  for (const BucklingMode& m : modes)
    if (m.factor > 0 && ++positive == mode) {
      f = m.factor;
      break;
    }
  destroy_modes(modes);
  VecDestroy(&U);
  VecDestroy(&V);
  return f;
}

// The first limit load of the model's arc-length path (solver.path): the first local maximum of
// the load factor along it, NaN if the path has none; on rank 0's own communicator.
double limit_load(const std::string& model_path) {
  Simulation sim = read_simulation(model_path);
  SystemAssembler sa(sim.model, PETSC_COMM_SELF);
  Vec U, V;
  start(sim, sa, &U, &V);
  std::vector<double> factors;
  ArcLengthSolver solver(sa, sim.path);
  PathReport report;
  PetscCallAbort(PETSC_COMM_SELF, solver.trace(U, 0.0, [&](const PathPoint& p) {
    factors.push_back(p.load_factor);
    return PetscErrorCode(0);
  }, &report));
  VecDestroy(&U);
  VecDestroy(&V);
  for (const LimitPoint& p : limit_points(factors))
    if (p.maximum) return factors[p.index];
  return NAN;
}

// The map of a check's key (`runs`, `reference`) as overrides of the model: dotted key -> value.
std::vector<KeyOverride> overrides_of(const InputNode& map) {
  if (!map.is_map()) map.fail("expected a map of dotted model keys to values, e.g. {solver.dynamics.time_step: 0.01}");
  std::vector<KeyOverride> out;
  for (const auto& [key, value] : map.entries()) out.push_back(make_key_override(key, value.yaml(), value));
  return out;
}

// Where a joint is at the end of a run of the model with `overrides` (on rank 0 of comm), and when
// the run ended; nothing if it failed (the failure in `message`).
std::optional<Vec3> final_joint_position(const std::string& model, const std::vector<KeyOverride>& overrides,
                                         const InputNode& joint, MPI_Comm comm, double* t_reached,
                                         std::string* message) {
  Trajectory tr;
  SimulationOutcome outcome;
  PetscCallAbort(comm, run_and_record(model, comm, &tr, &outcome, "", overrides));
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  *t_reached = outcome.dynamics.time_reached;
  if (!outcome.ok()) {
    *message = outcome.statics.message + outcome.dynamics.message;
    return std::nullopt;
  }
  if (rank != 0) return Vec3::Zero();
  return tr.final_state->joint_position(joint_of(tr.simulation->model, joint));
}

// Observed order of convergence (what: observed_order): the case's model with `runs` overrides at
// each of `time_steps`, the error of a joint's final position against a run with `reference`
// overrides; log(e_i / e_i+1) / log(h_i / h_i+1) for each pair of consecutive steps, each to be
// within the tolerance of `expected`. The worst order is the value; the label lists them all.
Result observed_order(const InputNode& c, const Trajectory& tr, MPI_Comm comm) {
  c.allow_only({"what", "joint", "runs", "time_steps", "reference", "expected", "abs_tol", "rel_tol"});
  const std::string model = tr.simulation->source;
  const std::vector<double> steps = c["time_steps"].as_doubles();
  if (steps.size() < 2) c["time_steps"].fail("expected at least two time steps, largest first");
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (!(steps[i] > 0) || (i > 0 && !(steps[i] < steps[i - 1])))
      c["time_steps"].fail("expected positive time steps, each smaller than the one before");
  const std::vector<KeyOverride> runs = c.has("runs") ? overrides_of(c["runs"]) : std::vector<KeyOverride>{};
  // Several checks of one case share their reference run: kept by joint and overrides.
  struct ReferenceRun {
    std::optional<Vec3> position;
    double t = 0.0;
    std::string message;
  };
  static std::map<std::string, ReferenceRun> references;
  const std::string key = model + "|" + c["joint"].as_string() + "|" + YAML::Dump(c["reference"].yaml());
  auto found = references.find(key);
  if (found == references.end()) {
    ReferenceRun run;
    run.position = final_joint_position(model, overrides_of(c["reference"]), c["joint"], comm, &run.t, &run.message);
    found = references.emplace(key, run).first;
  }
  const double t_ref = found->second.t;
  const std::optional<Vec3> reference = found->second.position;
  std::string message = found->second.message;
  if (!reference) return Result{"observed_order: the reference run", NAN, "completes (" + message + ")", false};
  std::vector<double> errors;
  for (double h : steps) {
    std::vector<KeyOverride> o = runs;
    o.push_back(make_key_override("solver.dynamics.time_step", YAML::Node(h), c["time_steps"]));
    double t = 0.0;
    const std::optional<Vec3> x = final_joint_position(model, o, c["joint"], comm, &t, &message);
    if (!x) return Result{"observed_order: the run at h = " + std::to_string(h), NAN, "completes (" + message + ")", false};
    if (std::abs(t - t_ref) > 1e-9 * std::max(1.0, std::abs(t_ref))) c["time_steps"].fail("the runs end at different times");
    errors.push_back((*x - *reference).norm());
  }
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) return Result{};
  const double expected = c["expected"].as_double();
  std::string label = "observed_order " + c["joint"].as_string() + " (errors";
  double worst = expected;
  bool pass = true;
  Result r;
  char buf[64];
  for (double e : errors) {
    std::snprintf(buf, sizeof buf, " %.3g", e);
    label += buf;
  }
  label += "; orders";
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    const double order = std::log(errors[i] / errors[i + 1]) / std::log(steps[i] / steps[i + 1]);
    std::snprintf(buf, sizeof buf, " %.2f", order);
    label += buf;
    r = compare(c, "", order);
    pass = pass && r.pass;
    if (std::isfinite(worst) && (!std::isfinite(order) || std::abs(order - expected) > std::abs(worst - expected))) worst = order;
  }
  label += ")";
  return Result{label, worst, r.expectation, pass};
}

// Evaluates one check on rank 0 (other ranks only take part in the runs it starts).
Result evaluate(const InputNode& c, const Trajectory& tr, const std::filesystem::path& dir, MPI_Comm comm) {
  const std::string what = c["what"].as_choice({"axial_force", "displacement", "position", "multiplier", "period",
                                                 "energy_drift", "max_violation", "variation", "compare_run",
                                                 "mpi_consistency", "frequency", "buckling_factor", "limit_load",
                                                 "min_axial_force", "damping_ratio", "section_force",
                                                 "member_stress", "pressure", "energy_balance", "observed_order"});
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const Model& m = tr.simulation->model;
  if (what == "observed_order") return observed_order(c, tr, comm);
  if (what == "compare_run" || what == "mpi_consistency") {
    Trajectory other;
    SimulationOutcome outcome;
    std::string label;
    if (what == "compare_run") {
      c.allow_only({"what", "model", "joint", "until", "max_difference"});
      const std::string path = (dir / c["model"].as_string()).string();
      PetscCallAbort(comm, run_and_record(path, comm, &other, &outcome));
      label = "compare_run " + c["model"].as_string();
    } else {
      c.allow_only({"what", "max_difference"});
      if (size < 2) return Result{what, NAN, "needs mpiexec -n 2 or more", false};
      // The serial reference: the same model on rank 0 alone, on a communicator split off
      // collectively (dup'ing MPI_COMM_SELF on one rank while the others wait trips Open MPI 4.1).
      MPI_Comm solo = MPI_COMM_NULL;
      MPI_Comm_split(comm, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
      if (rank == 0) {
        PetscCallAbort(solo, run_and_record(tr.simulation->source, solo, &other, &outcome));
        MPI_Comm_free(&solo);
      }
      MPI_Barrier(comm);
      label = "mpi_consistency (" + std::to_string(size) + " ranks vs 1)";
    }
    if (rank != 0) return Result{};
    const double until = c.has("until") ? c["until"].as_double() : 1e300;
    // One joint by name (the other model may number its joints differently), or all joints of
    // two models with the same joints.
    const int joint = c.has("joint") ? joint_of(m, c["joint"]) : -1;
    const int other_joint = c.has("joint") ? joint_of(other.simulation->model, c["joint"]) : -1;
    if (joint < 0 && other.simulation->model.joints.size() != m.joints.size())
      c.fail("the two models have different joints: name the joint to compare");
    double diff = 0.0;
    std::size_t compared = 0;
    for (std::size_t k = 0; k < tr.time.size() && k < other.time.size() && tr.time[k] <= until + 1e-12; ++k) {
      if (std::abs(tr.time[k] - other.time[k]) > 1e-9) return Result{label, NAN, "same output times", false};
      if (joint >= 0) {
        diff = std::max(diff, (tr.joints[k][joint] - other.joints[k][other_joint]).norm());
      } else {
        for (std::size_t j = 0; j < tr.joints[k].size(); ++j) diff = std::max(diff, (tr.joints[k][j] - other.joints[k][j]).norm());
      }
      ++compared;
    }
    if (compared < 2 || !outcome.ok()) return Result{label, NAN, "both runs complete", false};
    return below(label + " max |dr|", diff, c["max_difference"].as_positive());
  }
  if (rank != 0) return Result{};
  if (what == "frequency") {
    c.allow_only({"what", "mode", "expected", "abs_tol", "rel_tol"});
    const int mode = c["mode"].as_int();
    if (mode < 1 || mode > 100) c["mode"].fail("expected a mode number from 1 to 100");
    return compare(c, "natural frequency of mode " + std::to_string(mode) + " (Hz)",
                   natural_frequency(tr.simulation->source, mode));
  }
  if (what == "buckling_factor") {
    // Against a closed form (expected) or against another model's factor of the same mode (the
    // full lattice against its reduction): `model` with rel_tol.
    c.allow_only({"what", "mode", "expected", "model", "abs_tol", "rel_tol"});
    const int mode = c["mode"].as_int();
    if (mode < 1 || mode > 100) c["mode"].fail("expected a mode number from 1 to 100");
    const double value = buckling_factor(tr.simulation->source, mode);
    const std::string label = "buckling load factor " + std::to_string(mode) + " (positive)";
    if (!c.has("model")) return compare(c, label, value);
    if (c.has("expected")) c["expected"].fail("give either expected or model, not both");
    const double other = buckling_factor((dir / c["model"].as_string()).string(), mode);
    const double tol = c["rel_tol"].as_positive() * std::abs(other);
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.10g (%s) +- %.3g", other, c["model"].as_string().c_str(), tol);
    return Result{label, value, buf, std::isfinite(value) && std::abs(value - other) <= tol};
  }
  if (what == "limit_load") {
    c.allow_only({"what", "expected", "abs_tol", "rel_tol"});
    return compare(c, "limit load factor (first maximum of the path)", limit_load(tr.simulation->source));
  }
  if (what == "section_force" || what == "member_stress") {
    // section_force: one resultant of one member at one end; member_stress: the largest von Mises
    // stress or utilization of a body's members (final state).
    const bool force = what == "section_force";
    if (force)
      c.allow_only({"what", "body", "member", "end", "component", "expected", "abs_tol", "rel_tol"});
    else
      c.allow_only({"what", "body", "quantity", "expected", "abs_tol", "rel_tol"});
    const int b = m.find_body(c["body"].as_string());
    if (b < 0) c["body"].fail("no body named '" + c["body"].as_string() + "' in the model");
    const std::vector<MemberStress> members = final_members(tr, b);
    if (members.empty()) c["body"].fail("body '" + c["body"].as_string() + "' has no members with section forces");
    if (!force) {
      const bool util = c["quantity"].as_choice({"von_mises", "utilization"}) == "utilization";
      double largest = -INFINITY;
      for (const MemberStress& ms : members) largest = std::max(largest, util ? ms.utilization : ms.von_mises);
      return compare(c, std::string("largest ") + (util ? "utilization" : "von Mises stress") + " of " +
                            c["body"].as_string(), largest);
    }
    const int k = c["member"].as_int();
    if (k < 1 || k > static_cast<int>(members.size()))
      c["member"].fail("expected a member from 1 to " + std::to_string(members.size()));
    const int end = c["end"].as_int();
    if (end != 1 && end != 2) c["end"].fail("expected end 1 or 2");
    const std::string comp = c["component"].as_choice({"N", "Qy", "Qz", "T", "My", "Mz"});
    const SectionForces& f = members[static_cast<std::size_t>(k - 1)].end[static_cast<std::size_t>(end - 1)];
    const double v = comp == "N" ? f.N : comp == "Qy" ? f.Qy : comp == "Qz" ? f.Qz : comp == "T" ? f.T : comp == "My" ? f.My : f.Mz;
    return compare(c, comp + " of " + c["body"].as_string() + " member " + std::to_string(k) + " at end " + std::to_string(end), v);
  }
  if (what == "min_axial_force") {
    c.allow_only({"what", "body", "min"});
    const int b = m.find_body(c["body"].as_string());
    if (b < 0) c["body"].fail("no body named '" + c["body"].as_string() + "' in the model");
    double least = INFINITY;
    for (const auto& step : tr.axial)
      for (int e : m.bodies[b].elements)
        if (std::isfinite(step[e])) least = std::min(least, step[e]);
    const double min = c["min"].as_double();
    char buf[64];
    std::snprintf(buf, sizeof buf, ">= %.3g", min);
    return Result{"least axial force of " + c["body"].as_string() + " over the run", least, buf,
                  std::isfinite(least) && least >= min};
  }
  if (what == "energy_drift") {
    c.allow_only({"what", "max"});
    return below("energy drift / max kinetic energy", tr.energy_drift(), c["max"].as_positive());
  }
  if (what == "energy_balance") {  // pumps' work = mechanical energy + heat + oil compression
    c.allow_only({"what", "max"});
    if (!tr.energy_account) c["what"].fail("the model has no hydraulic circuit: it keeps no energy account");
    return below("|energy imbalance| / largest work", std::abs(tr.energy_account->relative_imbalance()),
                 c["max"].as_positive());
  }
  if (what == "max_violation") {
    c.allow_only({"what", "max"});
    return below("max constraint violation", *std::max_element(tr.violation.begin(), tr.violation.end()), c["max"].as_positive());
  }
  if (what == "axial_force") {
    c.allow_only({"what", "body", "expected", "abs_tol", "rel_tol"});
    const auto N = tr.final_state->axial_force(body_element(m, c["body"]));
    return compare(c, "axial force " + c["body"].as_string(), N ? *N : NAN);
  }
  if (what == "multiplier") {
    c.allow_only({"what", "constraint", "row", "expected", "abs_tol", "rel_tol"});
    const int con = constraint_of(m, c["constraint"]);
    const int row = c["row"].as_int();
    if (row < 0 || row >= m.constraints[con].rows()) c["row"].fail("no such row");
    return compare(c, "multiplier " + c["constraint"].as_string() + "[" + std::to_string(row) + "]",
                   tr.final_state->multipliers(con)(row));
  }
  if (what == "pressure") {  // a hydraulic node's pressure at the end of the run
    c.allow_only({"what", "node", "expected", "abs_tol", "rel_tol"});
    const std::string node = c["node"].as_string();
    int offset = 0, found = -1;
    for (const DofBlock& b : m.blocks) {
      if (!b.fixed && b.label == std::string(kHydraulicNodeLabel) + node) found = offset;
      if (!b.fixed) offset += b.size();
    }
    if (found < 0) c["node"].fail("no free hydraulic node named '" + node + "'");
    return compare(c, "pressure " + node, tr.final_state->coordinates_in_model_order()[found]);
  }
  const int joint = joint_of(m, c["joint"]);
  const int comp = component_of(c["component"]);
  const std::string label = c["joint"].as_string() + "." + "xyz"[comp];
  if (what == "displacement") {
    c.allow_only({"what", "joint", "component", "expected", "abs_tol", "rel_tol"});
    return compare(c, "displacement " + label, tr.joints.back()[joint](comp) - tr.joints0[joint](comp));
  }
  if (what == "position") {
    c.allow_only({"what", "joint", "component", "time", "expected", "abs_tol", "rel_tol"});
    const double t = c.has("time") ? c["time"].as_double() : tr.time.back();
    double v = NAN;
    try {
      v = tr.at(joint, comp, t);
    } catch (const std::out_of_range&) {
      c["time"].fail("no recorded output at this time");
    }
    return compare(c, "position " + label + " at t = " + std::to_string(t), v);
  }
  if (what == "damping_ratio") {
    // The measured ratio against `expected`, or against Rayleigh's alpha / (2 omega) + beta omega / 2
    // at the measured frequency (for models whose frequency has no closed form).
    c.allow_only({"what", "joint", "component", "from", "expected", "rayleigh", "abs_tol", "rel_tol"});
    const double from = c.has("from") ? c["from"].as_double() : -1e300;
    double omega = NAN;
    const double zeta = tr.damping_ratio(joint, comp, from, &omega);
    std::string text = "damping ratio of " + label + (c.has("from") ? " from t = " + c["from"].as_string() + " s" : "");
    if (!c.has("rayleigh")) return compare(c, text, zeta);
    const InputNode ray = c["rayleigh"];
    ray.allow_only({"alpha", "beta"});
    const RayleighDamping d{ray.get_non_negative("alpha", 0.0), ray.get_non_negative("beta", 0.0)};
    if (c.has("expected")) c["expected"].fail("give either expected or rayleigh, not both");
    const double expected = d.ratio(omega);
    const double tol = c.has("abs_tol") ? c["abs_tol"].as_positive() : c["rel_tol"].as_positive() * expected;
    char buf[200];
    std::snprintf(buf, sizeof buf, "%.10g +- %.3g (Rayleigh at the measured %.6g Hz)", expected, tol, omega / (2 * std::numbers::pi));
    return Result{text, zeta, buf, std::isfinite(zeta) && std::abs(zeta - expected) <= tol};
  }
  if (what == "period") {
    c.allow_only({"what", "joint", "component", "from", "expected", "abs_tol", "rel_tol"});
    const double from = c.has("from") ? c["from"].as_double() : -1e300;
    return compare(c, "period of " + label + (c.has("from") ? " from t = " + c["from"].as_string() + " s" : ""),
                   tr.period(joint, comp, from));
  }
  c.allow_only({"what", "joint", "component", "max"});
  double lo = 1e300, hi = -1e300;
  for (const auto& s : tr.joints) {
    lo = std::min(lo, s[joint](comp));
    hi = std::max(hi, s[joint](comp));
  }
  return below("variation of " + label, hi - lo, c["max"].as_positive());
}

int verify(const std::string& case_path, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const InputNode root = InputNode::load_file(case_path);
  root.allow_only({"model", "reference", "checks"});
  const std::filesystem::path dir = std::filesystem::path(case_path).parent_path();
  const std::string model = (dir / root["model"].as_string()).string();
  const std::string reference = root["reference"].as_string();
  Trajectory tr;
  SimulationOutcome outcome;
  PetscCallAbort(comm, run_and_record(model, comm, &tr, &outcome));
  if (rank == 0) std::printf("case %s\nmodel %s\nreference: %s\n", case_path.c_str(), model.c_str(), reference.c_str());
  bool all = outcome.ok();
  if (!outcome.ok() && rank == 0)
    std::printf("FAIL  the run did not complete: %s%s\n", outcome.statics.message.c_str(), outcome.dynamics.message.c_str());
  for (const InputNode& c : root["checks"].items()) {
    const Result r = evaluate(c, tr, dir, comm);
    if (rank != 0) continue;
    all = all && r.pass;
    std::printf("%s  %-48s  %.10g  (expected %s)\n", r.pass ? "pass" : "FAIL", r.what.c_str(), r.value, r.expectation.c_str());
  }
  int ok = all ? 1 : 0;
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  if (rank == 0) std::printf("%s\n", ok ? "all checks pass" : "SOME CHECKS FAILED");
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace latticedyn

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: latticedyn_verify CASE.check.yaml [PETSc options]\n");
    return 2;
  }
  const std::string case_path = argv[1];
  if (SlepcInitialize(&argc, &argv, nullptr, nullptr) != 0) return 3;
  int code = 0;
  try {
    code = latticedyn::verify(case_path, PETSC_COMM_WORLD);
  } catch (const latticedyn::InputError& e) {
    std::fprintf(stderr, "latticedyn_verify: error: %s\n", e.what());
    code = 2;
  }
  SlepcFinalize();
  return code;
}
