// The model format's top level: gravity, materials, sections, drives, ground, bodies,
// constraints, loads, solver and output settings, in this order of dependence.
#include "io/model_reader.hpp"

#include "assembly/minimum_dof_model.hpp"

#include "io/body_readers.hpp"
#include "io/drive_reader.hpp"
#include "io/hydraulic_readers.hpp"
#include "io/lattice_readers.hpp"
#include "io/petsc_option_policy.hpp"
#include "io/reader_context.hpp"
#include "io/recorded_state.hpp"
#include "io/result_writer.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

namespace latticedyn {

namespace {

Vec3 read_gravity(const InputNode& n) {
  if (n.is_sequence()) return n.as_vec3();
  n.allow_only({"direction", "magnitude"});
  const InputNode dir = n["direction"];
  const Vec3 d = dir.as_vec3();
  if (d.norm() == 0.0) dir.fail("the gravity direction has zero length");
  return d.normalized() * n["magnitude"].as_non_negative();
}

void read_constraints(ReaderContext& ctx, const InputNode& list, std::map<std::string, InputNode>& where) {
  int index = 1;
  for (const InputNode& n : list.items()) {
    n.allow_only({"name", "type", "axis", "joints", "drive", "shared"});
    Constraint c;
    c.name = n.get_string("name", "constraint" + std::to_string(index++));
    if (where.count(c.name))
      (n.has("name") ? n["name"] : n).fail("a constraint named '" + c.name + "' exists already" +
                                           (n.has("name") ? "" : " (the automatic name of this unnamed one)"));
    const std::string type = n["type"].as_choice({"fixed", "revolute", "prismatic", "spherical"});
    c.type = type == "fixed"      ? ConstraintType::fixed
             : type == "revolute" ? ConstraintType::revolute
             : type == "prismatic" ? ConstraintType::prismatic
                                   : ConstraintType::spherical;
    const bool has_axis = c.type == ConstraintType::revolute || c.type == ConstraintType::prismatic;
    if (has_axis) {
      const std::string axis = n["axis"].as_choice({"x", "y", "z"});
      c.axis = axis[0] - 'x';
    } else if (n.has("axis")) {
      n["axis"].fail("only revolute and prismatic constraints have an axis");
    }
    const InputNode joints = n["joints"];
    const auto j = joints.items();
    if (j.size() != 2) joints.fail("expected two joints [\"body.joint\", \"body.joint\"]");
    c.joint1 = ctx.joint(j[0]);
    c.joint2 = ctx.joint(j[1]);
    if (auto d = n.get("drive")) {
      if (!has_axis) d->fail("only revolute and prismatic constraints can be driven");
      c.drive = ctx.drive(*d);
    }
    where.emplace(c.name, n);
    try {
      ctx.builder.add_constraint(c, n.get_bool("shared", false));
    } catch (const ModelError& e) {
      n.fail(e.what());
    }
  }
}

// Limits of a model's size beyond which a run is a mistake, not a model: stated, so that a file
// cannot make the reader or the solver work without end.
constexpr std::size_t kMaxLoads = 100000;
constexpr int kMaxLoadSteps = 10000;
constexpr int kMaxNewtonIterations = 10000;

void read_loads(ReaderContext& ctx, const InputNode& list) {
  int index = 1;
  std::set<std::string> names;
  const std::vector<InputNode> items = list.items();
  if (items.size() > kMaxLoads)
    list.fail("a model has at most " + std::to_string(kMaxLoads) + " loads (this one " + std::to_string(items.size()) +
              ")");
  for (const InputNode& n : items) {
    n.allow_only({"name", "joint", "force", "force_frame", "moment", "moment_frame", "drive"});
    NodalLoad l;
    l.name = n.get_string("name", "load" + std::to_string(index++));
    if (!names.insert(l.name).second)
      (n.has("name") ? n["name"] : n).fail("a load named '" + l.name + "' exists already");
    l.joint = ctx.joint(n["joint"]);
    if (!n.has("force") && !n.has("moment")) n.fail("a load needs a 'force' or a 'moment'");
    l.force = n.get_vec3("force", Vec3::Zero());
    l.moment = n.get_vec3("moment", Vec3::Zero());
    auto frame = [&](const char* key) {
      return n.has(key) && n[key].as_choice({"inertial", "body"}) == "body" ? LoadFrame::body : LoadFrame::inertial;
    };
    l.force_frame = frame("force_frame");
    l.moment_frame = frame("moment_frame");
    if (auto d = n.get("drive")) l.drive = ctx.drive(*d);
    try {
      ctx.builder.add_load(l);
    } catch (const ModelError& e) {
      n.fail(e.what());
    }
  }
}

void read_solver(const InputNode& n, Simulation& sim) {
  n.allow_only({"static", "dynamics", "path", "petsc_options"});
  sim.petsc_options = n.get_string("petsc_options", "");
  for (const PetscOptionToken& o : split_petsc_options(sim.petsc_options))
    if (auto why = refused_model_option(o)) n["petsc_options"].fail(*why);
  if (auto s = n.get("static")) {
    s->allow_only({"enabled", "load_steps", "max_iterations", "max_cuts", "rtol", "atol", "time", "regularization"});
    sim.run_static = s->get_bool("enabled", true);
    StaticSettings& st = sim.statics;
    if (auto k = s->get("load_steps")) {
      st.load_steps = k->as_int();
      if (st.load_steps < 1 || st.load_steps > kMaxLoadSteps)
        k->fail("expected 1 to " + std::to_string(kMaxLoadSteps) + " load steps");
    }
    if (auto k = s->get("max_iterations")) {
      st.max_iterations = k->as_int();
      if (st.max_iterations < 1 || st.max_iterations > kMaxNewtonIterations)
        k->fail("expected 1 to " + std::to_string(kMaxNewtonIterations) + " iterations");
    }
    if (auto k = s->get("max_cuts")) {
      st.max_cuts = k->as_int();
      if (st.max_cuts < 0 || st.max_cuts > 60) k->fail("expected 0 to 60 halvings (2^-60 of a load step)");
    }
    st.rtol = s->get_positive("rtol", st.rtol);
    st.atol = s->get_positive("atol", st.atol);
    st.time = s->get_double("time", st.time);
    st.regularization = s->get_non_negative("regularization", st.regularization);
  }
  if (auto p = n.get("path")) {
    p->allow_only({"arc_length", "max_steps", "max_load_factor", "min_load_factor", "max_iterations",
                   "target_iterations", "max_arc_factor", "tolerance", "time"});
    PathSettings& ps = sim.path;
    ps.arc_length = p->get_non_negative("arc_length", ps.arc_length);
    if (auto k = p->get("max_steps")) {
      ps.max_steps = k->as_int();
      if (ps.max_steps < 1 || ps.max_steps > 1000000) k->fail("expected 1 to 1000000 steps");
    }
    ps.max_load_factor = p->get_double("max_load_factor", ps.max_load_factor);
    ps.min_load_factor = p->get_double("min_load_factor", ps.min_load_factor);
    if (ps.min_load_factor >= ps.max_load_factor)
      (*p)[p->has("min_load_factor") ? "min_load_factor" : "max_load_factor"].fail(
          "expected min_load_factor below max_load_factor");
    if (auto k = p->get("max_iterations")) {
      ps.max_iterations = k->as_int();
      if (ps.max_iterations < 1 || ps.max_iterations > kMaxNewtonIterations)
        k->fail("expected 1 to " + std::to_string(kMaxNewtonIterations) + " iterations");
    }
    if (auto k = p->get("target_iterations")) {
      ps.target_iterations = k->as_int();
      if (ps.target_iterations < 1 || ps.target_iterations > 100) k->fail("expected 1 to 100 iterations");
    }
    ps.tolerance = p->get_positive("tolerance", ps.tolerance);
    ps.time = p->get_double("time", ps.time);
    if (auto k = p->get("max_arc_factor")) {
      ps.max_arc_factor = k->as_double();
      if (!(ps.max_arc_factor >= 1 && ps.max_arc_factor <= 1e6)) k->fail("expected 1 to 1e6 (times the first arc)");
    }
  }
  if (auto d = n.get("dynamics")) {
    d->allow_only({"integrator", "t_start", "t_end", "time_step", "rho_infinity", "adaptive", "rtol", "atol", "max_steps",
                   "baumgarte_alpha", "baumgarte_beta", "rk_type", "implicit_method", "jacobian_reuse", "newton_tolerance",
                   "hydraulic_coupling", "coupling_step"});
    sim.run_dynamics = true;
    DynamicSettings& dy = sim.dynamics;
    if (auto k = d->get("integrator")) {
      const std::string kind = k->as_choice({"generalized_alpha", "baumgarte", "implicit_rk", "minimum_dof"});
      dy.integrator = kind == "baumgarte"     ? IntegratorKind::baumgarte
                      : kind == "implicit_rk" ? IntegratorKind::implicit_rk
                      : kind == "minimum_dof" ? IntegratorKind::minimum_dof
                                              : IntegratorKind::generalized_alpha;
    }
    dy.t_start = d->get_double("t_start", 0.0);
    const InputNode t_end = (*d)["t_end"];
    dy.t_end = t_end.as_double();
    if (!(dy.t_end > dy.t_start)) t_end.fail("t_end must be later than t_start");
    dy.time_step = (*d)["time_step"].as_positive();
    if (auto k = d->get("rho_infinity")) {
      dy.rho_infinity = k->as_double();
      if (dy.rho_infinity < 0 || dy.rho_infinity > 1) k->fail("rho_infinity must lie in [0, 1]");
    }
    dy.adaptive = d->get_bool("adaptive", false);
    // Undamped index-3 generalized-alpha lets the accelerations and multipliers oscillate at the
    // step's frequency: its error estimate then never falls and adaptive steps shrink to nothing.
    if (dy.adaptive && dy.integrator == IntegratorKind::generalized_alpha && dy.rho_infinity >= 1.0)
      (*d)["adaptive"].fail("adaptive generalized-alpha needs rho_infinity below 1 (e.g. 0.9): with 1 the constraint "
                            "forces oscillate undamped and the error estimate never falls");
    dy.rtol = d->get_positive("rtol", dy.rtol);
    dy.atol = d->get_positive("atol", dy.atol);
    if (auto k = d->get("max_steps")) {
      dy.max_steps = k->as_int();
      if (dy.max_steps < 1) k->fail("expected at least 1 step");
    }
    if (auto k = d->get("jacobian_reuse")) {
      dy.jacobian_reuse = k->as_int();
      if (dy.jacobian_reuse < 1 || dy.jacobian_reuse > 1000) k->fail("expected 1 (a fresh Jacobian every Newton iteration) to 1000");
    }
    if (auto k = d->get("newton_tolerance")) {
      dy.newton_tolerance = k->as_positive();
      if (dy.newton_tolerance >= 1e-2) k->fail("expected a small positive fraction of the model's load, below 1e-2");
    }
    if (auto k = d->get("hydraulic_coupling"))
      dy.hydraulic_cosimulation = k->as_choice({"monolithic", "cosimulation"}) == "cosimulation";
    if (auto k = d->get("coupling_step")) {
      if (!dy.hydraulic_cosimulation) k->fail("coupling_step belongs to hydraulic_coupling: cosimulation");
      dy.coupling_step = k->as_positive();
      if (dy.coupling_step < dy.time_step * (1 - 1e-12))
        k->fail("expected at least the time step (" + std::to_string(dy.time_step) + " s): each part takes its steps within a coupling step");
    }
    dy.baumgarte_alpha = d->get_non_negative("baumgarte_alpha", dy.baumgarte_alpha);
    dy.baumgarte_beta = d->get_non_negative("baumgarte_beta", dy.baumgarte_beta);
    if (auto k = d->get("rk_type"))  // PETSc's TSRK schemes
      dy.rk_type = k->as_choice({"1fe", "2a", "2b", "3", "3bs", "4", "5f", "5dp", "5bs", "6vr", "7vr", "8vr"});
    // PETSc's fully implicit ARK (ESDIRK) and Rosenbrock schemes that are stiffly accurate, so
    // that the algebraic rows hold at the step's end (the others lose order on a DAE).
    if (auto k = d->get("implicit_method"))
      dy.implicit_method =
          k->as_choice({"arkimex:l2", "arkimex:3", "arkimex:4", "arkimex:5", "rosw:ra34pw2", "rosw:rodas3"});
  }
}

void read_output(const ReaderContext& ctx, const InputNode& n, Simulation& sim) {
  n.allow_only({"directory", "name", "interval", "checkpoint_interval", "probes", "body_blocks"});
  sim.output.directory = n.get_string("directory", sim.output.directory);
  if (auto k = n.get("name")) {
    sim.output.name = k->as_string();
    if (auto why = base_name_problem(sim.output.name)) k->fail(*why);
  }
  sim.output.interval = n.get_non_negative("interval", 0.0);
  // Simulated seconds between checkpoints (a restart point of the integrator); the end of a run
  // and an interruption always write one.
  sim.dynamics.checkpoint_interval = n.get_non_negative("checkpoint_interval", 0.0);
  if (auto p = n.get("probes"))
    for (const InputNode& j : p->items()) sim.output.probe_joints.push_back(ctx.joint(j));
  sim.output.body_blocks = n.get_bool("body_blocks", false);
}

// A recorded state to start from, checked here against the model so that a file from another
// model is an input error at its key, before anything is computed.
void read_start_state(const InputNode& n, Simulation& sim) {
  n.allow_only({"file", "step"});
  const InputNode file = n["file"];
  std::filesystem::path path = file.as_string();
  if (path.is_relative()) path = std::filesystem::path(file.file()).parent_path() / path;
  long step = -1;
  if (auto k = n.get("step")) step = k->as_int();
  RecordedState state;
  try {
    state = read_recorded_state(path, step);
  } catch (const RecordedStepOutOfRange& e) {
    (n.has("step") ? n["step"] : file).fail(e.what());
  } catch (const std::exception& e) {
    file.fail(e.what());
  }
  const auto expected = static_cast<std::size_t>(sim.model.num_free_dofs() + sim.model.num_multipliers());
  if (state.coordinates.size() != expected)
    file.fail("the recorded state has " + std::to_string(state.coordinates.size()) + " coordinates, this model " +
              std::to_string(expected) + ": it was written by another model");
  sim.start_coordinates = std::move(state.coordinates);
  // Next to an equilibrium already: the static solve starts as a warm one.
  sim.statics.warm_start = true;
}

// Every driven rest length stays positive from the statics' time to the end of the run: sampled
// at 10,001 points and the ends of the span (the drives are smooth between their breakpoints).
void check_rest_lengths(const ReaderContext& ctx, const Simulation& sim) {
  double t0 = sim.run_static ? sim.statics.time : sim.dynamics.t_start;
  double t1 = t0;
  if (sim.run_dynamics) {
    t0 = std::min(t0, sim.dynamics.t_start);
    t1 = std::max(t1, sim.dynamics.t_end);
  }
  constexpr int kSamples = 10000;
  for (const ReaderContext::DrivenRestLength& d : ctx.driven_rest_lengths) {
    const Drive& drive = ctx.builder.peek().drives[d.drive];
    for (int k = 0; k <= kSamples; ++k) {
      const double t = t0 + (t1 - t0) * k / kSamples;
      const double L = d.fraction * drive.evaluate(t).value;
      if (!(L > 0)) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "the drive takes the rope's rest length to %.4g m at t = %.4g s (the run spans %g to %g s); expected > 0 throughout",
                      L, t, t0, t1);
        d.key.fail(buf);
      }
    }
  }
}

Simulation read(const InputNode& root, const std::string& source) {
  if (!root.is_map()) root.fail("a model file is a map of keys (title, gravity, bodies, ...)");
  root.allow_only({"title", "gravity", "materials", "sections", "truss_sections", "truss_bodies", "drives", "ground",
                   "bodies", "constraints", "loads", "solver", "output", "start_state", "hydraulics"});
  Simulation sim;
  sim.source = source;
  const std::string stem = std::filesystem::path(source).stem().string();
  sim.output.directory = "results/" + stem;
  sim.output.name = stem.empty() || base_name_problem(stem) ? "results" : stem;

  ReaderContext ctx;
  ctx.builder.set_title(root.get_string("title", stem));
  ctx.bodies["ground"] = BodyRecord{0, "ground", {}};
  if (auto g = root.get("gravity")) ctx.builder.set_gravity(read_gravity(*g));
  if (auto m = root.get("materials"))
    for (const auto& [name, node] : m->entries()) ctx.materials[name] = read_material(node);
  if (auto s = root.get("sections"))
    for (const auto& [name, node] : s->entries()) ctx.sections[name] = read_section(node);
  if (auto t = root.get("truss_bodies")) {
    const std::string as = t->as_choice({"as_given", "lattice", "super_truss"});
    ctx.truss_bodies = as == "as_given" ? "" : as;
  }
  if (auto t = root.get("truss_sections"))
    for (const auto& [name, node] : t->entries()) ctx.truss_sections[name] = read_truss_section(ctx, node);
  if (auto d = root.get("drives"))
    for (const auto& [name, node] : d->entries()) ctx.drives[name] = ctx.builder.add_drive(name, read_drive(node));
  if (auto g = root.get("ground")) read_ground(ctx, *g);
  const std::optional<InputNode> hydraulics = root.get("hydraulics");
  if (hydraulics) read_hydraulic_nodes(ctx, *hydraulics);
  const InputNode bodies = root["bodies"];
  if (bodies.items().empty()) bodies.fail("a model needs at least one body");
  for (const InputNode& b : bodies.items()) read_body(ctx, b);

  if (hydraulics) read_hydraulic_elements(ctx, *hydraulics);
  std::map<std::string, InputNode> constraint_nodes;
  if (auto c = root.get("constraints")) read_constraints(ctx, *c, constraint_nodes);
  if (auto l = root.get("loads")) read_loads(ctx, *l);
  if (auto s = root.get("solver")) read_solver(*s, sim);
  // A closed chamber's pressure follows from the oil it has taken in, a state of the dynamics
  // that a static solve (all rates zero) cannot know.
  if (hydraulics && sim.run_static)
    root["solver"]["static"].fail("a model with a hydraulic circuit has no static solve: its pressures are states of the "
                                  "dynamics (give the nodes' starting pressures and run the dynamics)");
  if (hydraulics && sim.run_dynamics && (sim.dynamics.integrator == IntegratorKind::baumgarte ||
                                         sim.dynamics.integrator == IntegratorKind::minimum_dof))
    root["solver"]["dynamics"]["integrator"].fail("a hydraulic circuit needs generalized_alpha or implicit_rk (its "
                                                  "pressures have no mass to solve the accelerations for)");
  if (sim.run_dynamics && sim.dynamics.hydraulic_cosimulation) {
    const InputNode coupling = root["solver"]["dynamics"]["hydraulic_coupling"];
    if (!hydraulics) coupling.fail("cosimulation couples a hydraulic circuit to its mechanism: the model has no 'hydraulics'");
    if (sim.dynamics.integrator != IntegratorKind::generalized_alpha)
      coupling.fail("cosimulation steps both parts with generalized_alpha (drop the integrator key)");
    if (sim.dynamics.adaptive) coupling.fail("cosimulation takes fixed coupling steps: adaptive steps are not offered");
  }
  if (auto o = root.get("output")) read_output(ctx, *o, sim);
  check_rest_lengths(ctx, sim);

  try {
    sim.model = ctx.builder.build();
  } catch (const ModelError& e) {
    // Name the constraint the message is about, at its place in the file.
    const std::string what = e.what();
    for (const auto& [name, node] : constraint_nodes)
      if (what.find("'" + name + "'") != std::string::npos) node.fail(what);
    root.fail(what);
  }
  if (sim.model.num_free_dofs() == 0) bodies.fail("every body is fixed: the model has no degree of freedom");
  if (sim.run_dynamics && sim.dynamics.integrator == IntegratorKind::minimum_dof) {
    // Joint coordinates need a tree of rigid bodies: say which body or constraint does not fit, there.
    try {
      const MinimumDofModel tree(sim.model);
      if (tree.num_free() == 0) root["solver"]["dynamics"]["integrator"].fail("minimum_dof: every joint coordinate is driven, nothing is left to integrate");
      if (!sim.run_static && !root.get("start_state")) {  // dynamics from the model's own state: it must fit the joints
        std::vector<BlockState> blocks(sim.model.blocks.size());
        for (std::size_t b = 0; b < blocks.size(); ++b) {
          const DofBlock& blk = sim.model.blocks[b];
          blocks[b].pos = blk.position0;
          blocks[b].rot = blk.orientation0;
          blocks[b].vel = blk.velocity0;  // velocity variables: r_dot, body omega
        }
        VecX q, qdot;
        tree.coordinates_from_blocks(sim.dynamics.t_start, blocks, q, qdot);
      }
    } catch (const ModelError& e) {
      const std::string what = e.what();
      for (const auto& [name, node] : constraint_nodes)
        if (what.find("'" + name + "'") != std::string::npos) node.fail("integrator minimum_dof: " + what);
      root["solver"]["dynamics"]["integrator"].fail(what);
    }
  }
  if (auto s = root.get("start_state")) read_start_state(*s, sim);
  return sim;
}

}  // namespace

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Reads the parsed document, timing both stages (the document is released inside the second).
template <class Load>
Simulation timed_read(Load load, const std::string& name) {
  const auto start = Clock::now();
  std::optional<InputNode> doc(load());
  const double parse = seconds_since(start);
  const auto built = Clock::now();
  Simulation sim = read(*doc, name);
  doc.reset();
  sim.parse_seconds = parse;
  sim.build_seconds = seconds_since(built);
  return sim;
}

}  // namespace

Simulation read_simulation(const std::string& path) {
  return timed_read([&] { return InputNode::load_file(path); }, path);
}

Simulation read_simulation(const std::string& path, const std::vector<KeyOverride>& overrides) {
  return timed_read([&] { return InputNode::load_file(path, overrides); }, path);
}

Simulation read_simulation_from_string(const std::string& yaml, const std::string& name) {
  return timed_read([&] { return InputNode::load_string(yaml, name); }, name);
}

Simulation read_simulation_from_string(const std::string& yaml, const std::string& name,
                                       const std::vector<KeyOverride>& overrides) {
  return timed_read([&] { return InputNode::load_string(yaml, name, overrides); }, name);
}

}  // namespace latticedyn
