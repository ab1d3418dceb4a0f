// The facade over reader, assembler, static solver and generalized-alpha integrator: one model's
// simulation kept between calls, its integrator continued from advance to advance.
#include "api/simulator.hpp"

#include "drivers/simulation.hpp"
#include "io/linear_model_file.hpp"
#include "io/model_reader.hpp"
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/linearization.hpp"
#include "timestepping/modal_analysis.hpp"
#include "timestepping/static_solver.hpp"

#include <petscsys.h>
#include <slepcsys.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <optional>

namespace latticedyn {

namespace {

/// A PETSc call of the facade: an error becomes an exception naming what was being done.
void check(PetscErrorCode status, const char* what) {
  if (status != 0) throw std::runtime_error(std::string("Simulator: PETSc failed to ") + what + " (error " + std::to_string(status) + ")");
}

std::vector<KeyOverride> key_overrides(const std::vector<Override>& overrides, const std::string& file) {
  std::vector<KeyOverride> keys;
  for (const Override& o : overrides) {
    KeyOverride k;
    k.path = o.path;
    try {
      k.value = YAML::Load(o.yaml);
    } catch (const YAML::Exception& e) {
      throw InputError(file, 1, 1, o.path, "the override's value is no YAML (" + e.msg + "): '" + o.yaml + "'");
    }
    k.origin_file = file;
    keys.push_back(std::move(k));
  }
  return keys;
}

}  // namespace

Runtime::Runtime() : Runtime(nullptr, nullptr) {}

Runtime::Runtime(int* argc, char*** argv) {
  // SLEPc (natural frequencies) needs its own initialisation; it starts PETSc unless the program
  // did, and its finalisation ends only what it started.
  PetscBool up = PETSC_FALSE;
  SlepcInitialized(&up);
  if (up) return;
  check(SlepcInitialize(argc, argv, nullptr, nullptr), "initialise");
  owner_ = true;
}

Runtime::~Runtime() {
  if (owner_) SlepcFinalize();
}

struct Simulator::Impl {
  Simulation sim;
  std::unique_ptr<SystemAssembler> sa;
  Vec U = nullptr, V = nullptr, A = nullptr;  // A: the acceleration to resume with (restore)
  double time = 0.0;
  long steps = 0;
  std::unique_ptr<GeneralizedAlphaIntegrator> integrator;  // none before the first advance and after a restart
  DynamicReport report;
  std::optional<ResumePoint> resume;  // set by restore_state: the next advance resumes there
  mutable std::optional<ModelState> state;  // the outputs' state, gathered when first asked for

  explicit Impl(Simulation s) : sim(std::move(s)) {
    if (sim.dynamics.integrator != IntegratorKind::generalized_alpha)
      throw std::invalid_argument("Simulator: model '" + sim.source +
                                  "' asks for the Baumgarte integrator; the library advances generalized-alpha models "
                                  "(solver.dynamics.integrator: generalized_alpha)");
    if (!sim.petsc_options.empty()) check(PetscOptionsInsertString(nullptr, sim.petsc_options.c_str()), "take the model's petsc_options");
    sa = std::make_unique<SystemAssembler>(sim.model, PETSC_COMM_SELF);
    for (Vec* v : {&U, &V, &A}) check(sa->create_vector(v), "create a state vector");
    check(initial_state(sim, *sa, U, V), "set the initial state");
    time = sim.run_dynamics ? sim.dynamics.t_start : sim.statics.time;
  }
  ~Impl() {
    integrator.reset();
    for (Vec* v : {&U, &V, &A}) VecDestroy(v);
  }

  void changed() { state.reset(); }
  const ModelState& current() const {
    if (!state) {
      state.emplace(sim.model, sa->dofs());
      check(sa->gather(time, U, V, nullptr, Parametrization::rotation_vector_rates, &*state), "gather the state");
    }
    return *state;
  }
  int index(int found, const char* kind, const std::string& name) const {
    if (found < 0) throw std::invalid_argument(std::string("Simulator: no ") + kind + " '" + name + "' in model '" + sim.model.title + "'");
    return found;
  }
  int joint(const std::string& name) const { return index(sim.model.find_joint(name), "joint", name); }
  int drive(const std::string& name) const {
    const auto& names = sim.model.drive_names;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return static_cast<int>(k);
    return index(-1, "drive", name);
  }
  drive::ExternalSignal& external(const std::string& name) const {
    const Drive& d = sim.model.drives[drive(name)];
    if (!d.external_signal())
      throw std::invalid_argument("Simulator: drive '" + name + "' is prescribed (" + d.describe() +
                                  "); only drives of type external take values from the program");
    return *d.external_signal();
  }
  std::vector<double> in_model_order(Vec X) const {
    std::vector<double> ordered;
    check(sa->gather_in_model_order(X, &ordered), "gather a vector");
    return ordered;
  }
};

Simulator::Simulator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

Simulator Simulator::load(const std::string& path, const std::vector<Override>& overrides) {
  return Simulator(std::make_unique<Impl>(read_simulation(path, key_overrides(overrides, path))));
}

Simulator Simulator::load_string(const std::string& yaml, const std::string& name, const std::vector<Override>& overrides) {
  return Simulator(std::make_unique<Impl>(read_simulation_from_string(yaml, name, key_overrides(overrides, name))));
}

const Model& Simulator::model() const { return impl_->sim.model; }
double Simulator::time() const { return impl_->time; }
double Simulator::time_step() const { return impl_->sim.dynamics.time_step; }
long Simulator::steps() const { return impl_->steps; }

StaticsSummary Simulator::solve_statics() {
  Impl& m = *impl_;
  StaticSettings settings = m.sim.statics;
  settings.time = m.time;
  Vec before;
  check(VecDuplicate(m.U, &before), "copy the state");
  check(VecCopy(m.U, before), "copy the state");
  StaticReport report;
  {
    StaticSolver solver(*m.sa, settings);
    check(solver.solve(m.U, &report, nullptr), "solve the statics");
  }
  if (!report.converged) {
    VecCopy(before, m.U);
    VecDestroy(&before);
    throw SolverError("Simulator: no static equilibrium at t = " + std::to_string(m.time) + " s: " + report.message);
  }
  VecDestroy(&before);
  check(VecZeroEntries(m.V), "zero the velocities");
  m.integrator.reset();  // the dynamics start afresh from the equilibrium
  m.resume.reset();
  m.changed();
  return StaticsSummary{report.increments, report.newton_iterations, report.residual_norm, report.max_violation,
                        report.message, report.wall_seconds};
}

void Simulator::advance(double interval) {
  Impl& m = *impl_;
  if (!(interval > 0.0) || !std::isfinite(interval))
    throw std::invalid_argument("Simulator::advance: expected an interval > 0 s, got " + std::to_string(interval));
  const double t_end = m.time + interval;
  m.changed();
  if (!m.integrator) {
    DynamicSettings settings = m.sim.dynamics;
    settings.t_start = m.time;
    settings.t_end = t_end;
    settings.checkpoint_interval = 0.0;
    m.integrator = std::make_unique<GeneralizedAlphaIntegrator>(*m.sa, settings);
    m.integrator->set_open_end(true);
    // From the start (or the statics) as the command line runs; after a restore or a failed step,
    // as a run continued from a checkpoint.
    const ResumePoint start = m.resume.value_or(ResumePoint{m.steps, m.sim.dynamics.time_step});
    const bool continued = m.resume || m.steps > 0;
    check(m.integrator->run(m.U, m.V, nullptr, &m.report, continued ? &start : nullptr, m.resume ? m.A : nullptr),
          "advance the dynamics");
    m.resume.reset();
  } else {
    check(m.integrator->continue_to(t_end, m.U, m.V, nullptr, &m.report), "advance the dynamics");
  }
  m.time = m.report.time_reached;
  m.steps = m.report.steps;
  if (!m.report.completed) {
    m.integrator.reset();  // the next advance restarts from the last accepted step
    throw SolverError("Simulator: " + m.report.message);
  }
  if (m.time < t_end - 1e-9 * std::max(1.0, std::abs(t_end))) {
    m.integrator.reset();
    throw SolverError("Simulator: the dynamics stopped at t = " + std::to_string(m.time) + " s, short of " +
                      std::to_string(t_end) + " s, after " + std::to_string(m.steps) +
                      " steps (solver.dynamics.max_steps = " + std::to_string(m.sim.dynamics.max_steps) + ")");
  }
}

std::vector<std::string> Simulator::drive_names() const { return impl_->sim.model.drive_names; }

std::vector<std::string> Simulator::external_drive_names() const {
  std::vector<std::string> names;
  const Model& model = impl_->sim.model;
  for (std::size_t k = 0; k < model.drives.size(); ++k)
    if (model.drives[k].external_signal()) names.push_back(model.drive_names[k]);
  return names;
}

DriveValue Simulator::drive(const std::string& name) const {
  return impl_->sim.model.drives[impl_->drive(name)].evaluate(impl_->time);
}

void Simulator::set_drive_rate(const std::string& name, double rate) {
  if (!std::isfinite(rate)) throw std::invalid_argument("Simulator::set_drive_rate: '" + name + "' needs a finite rate");
  drive::ExternalSignal& s = impl_->external(name);
  const DriveValue now = drive(name);
  s = drive::ExternalSignal{impl_->time, now.value, rate, 0.0};
}

void Simulator::set_drive_acceleration(const std::string& name, double acceleration) {
  if (!std::isfinite(acceleration))
    throw std::invalid_argument("Simulator::set_drive_acceleration: '" + name + "' needs a finite acceleration");
  drive::ExternalSignal& s = impl_->external(name);
  const DriveValue now = drive(name);
  s = drive::ExternalSignal{impl_->time, now.value, now.rate, acceleration};
}

Vec3 Simulator::joint_position(const std::string& joint) const {
  return impl_->current().joint_position(impl_->joint(joint));
}

Vec3 Simulator::joint_velocity(const std::string& joint) const {
  return impl_->current().joint_velocity(impl_->joint(joint));
}

Mat3 Simulator::joint_orientation(const std::string& joint) const {
  return impl_->current().joint_frame_of(impl_->joint(joint)).second;
}

std::vector<double> Simulator::axial_forces(const std::string& body) const {
  const int b = impl_->index(impl_->sim.model.find_body(body), "body", body);
  const ModelState& s = impl_->current();
  std::vector<double> forces;
  const auto& elements = impl_->sim.model.elements;
  for (std::size_t e = 0; e < elements.size(); ++e)
    if (elements[e].body == b) forces.push_back(s.axial_force(static_cast<int>(e)).value_or(std::nan("")));
  return forces;
}

ConstraintReaction Simulator::constraint_reaction(const std::string& constraint) const {
  const auto& constraints = impl_->sim.model.constraints;
  for (std::size_t c = 0; c < constraints.size(); ++c)
    if (constraints[c].name == constraint) return impl_->current().constraint_reaction(static_cast<int>(c));
  impl_->index(-1, "constraint", constraint);
  return {};
}

ElementEnergy Simulator::energy() const { return impl_->current().energy(); }

std::vector<double> Simulator::probes() const {
  const ModelState& s = impl_->current();
  std::vector<double> out;
  for (const int j : impl_->sim.output.probe_joints) {
    const Vec3 x = s.joint_position(j), v = s.joint_velocity(j);
    out.insert(out.end(), {x.x(), x.y(), x.z(), v.x(), v.y(), v.z()});
  }
  return out;
}

std::vector<double> Simulator::coordinates() const { return impl_->in_model_order(impl_->U); }

LinearModel Simulator::linearize(const std::vector<std::string>& inputs) const {
  const Impl& m = *impl_;
  std::vector<int> drives;
  for (const std::string& name : inputs) {
    m.external(name);  // an external drive, or a clear error
    drives.push_back(m.drive(name));
  }
  Vec A;
  check(VecDuplicate(m.U, &A), "create a vector");
  if (m.integrator) check(VecCopy(m.integrator->acceleration_estimate(), A), "copy the acceleration");
  else if (m.resume) check(VecCopy(m.A, A), "copy the acceleration");
  else check(VecZeroEntries(A), "zero the acceleration");
  try {
    LinearModel lm = latticedyn::linearize(*m.sa, m.U, m.V, A, m.time, drives, m.sim.output.probe_joints);
    VecDestroy(&A);
    return lm;
  } catch (...) {
    VecDestroy(&A);
    throw;
  }
}

void Simulator::write_linear_model(const std::string& path, const LinearModel& model) {
  io::write_linear_model(path, model);
}

std::vector<double> Simulator::natural_frequencies(int count) const {
  const Impl& m = *impl_;
  if (count < 1) throw std::invalid_argument("Simulator::natural_frequencies: expected a count >= 1, got " + std::to_string(count));
  ModalAnalysis modal(*m.sa, ModalSettings{count, 1e-10});
  std::vector<Mode> modes;
  std::string message;
  check(modal.solve(m.U, m.time, &modes, &message), "solve the eigenproblem");
  std::vector<double> hz;
  for (const Mode& mode : modes) hz.push_back(mode.frequency);
  destroy_modes(modes);
  if (static_cast<int>(hz.size()) < count) throw SolverError("Simulator: " + message);
  return hz;
}

SimulatorState Simulator::save_state() const {
  const Impl& m = *impl_;
  SimulatorState s;
  s.time = m.time;
  s.coordinates = m.in_model_order(m.U);
  s.velocities = m.in_model_order(m.V);
  // The acceleration the next step's predictor starts from: the integrator's estimate, or the one
  // a restored state brought and no step has replaced yet.
  s.accelerations = m.integrator ? m.in_model_order(m.integrator->acceleration_estimate())
                                 : (m.resume ? m.in_model_order(m.A) : std::vector<double>(s.coordinates.size(), 0.0));
  for (const Drive& d : m.sim.model.drives) s.external_drives.push_back(d.external_signal() ? *d.external_signal() : drive::ExternalSignal{});
  s.steps = m.steps;
  s.next_time_step = m.sim.dynamics.time_step;
  return s;
}

void Simulator::restore_state(const SimulatorState& s) {
  Impl& m = *impl_;
  const std::size_t n = static_cast<std::size_t>(m.sa->dofs().global_size());
  if (s.coordinates.size() != n || s.velocities.size() != n || s.accelerations.size() != n ||
      s.external_drives.size() != m.sim.model.drives.size())
    throw std::invalid_argument("Simulator::restore_state: the state has " + std::to_string(s.coordinates.size()) +
                                " coordinates and " + std::to_string(s.external_drives.size()) + " drives, model '" +
                                m.sim.model.title + "' " + std::to_string(n) + " and " +
                                std::to_string(m.sim.model.drives.size()));
  set_state_in_model_order(m.sa->dofs(), m.U, s.coordinates);
  set_state_in_model_order(m.sa->dofs(), m.V, s.velocities);
  set_state_in_model_order(m.sa->dofs(), m.A, s.accelerations);
  for (std::size_t k = 0; k < m.sim.model.drives.size(); ++k)
    if (drive::ExternalSignal* signal = m.sim.model.drives[k].external_signal()) *signal = s.external_drives[k];
  m.time = s.time;
  m.steps = s.steps;
  m.integrator.reset();
  m.resume = ResumePoint{s.steps, s.next_time_step};
  m.report = DynamicReport{};
  m.changed();
}

}  // namespace latticedyn
