// The library's facade: a model loaded from YAML, its static equilibrium, its dynamics advanced
// interval by interval with external drives set by the calling program, its outputs and its state.
#pragma once

#include "assembly/model_state.hpp"
#include "core/drive_params.hpp"
#include "timestepping/linear_model.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace latticedyn {

/// PETSc, SLEPc (and MPI) for a program that uses the library. The first Runtime of a process
/// initialises them, unless the program did; it finalises what it initialised when it goes. Its arguments are
/// PETSc options (-dyn_snes_monitor, -log_view, ...), as on the command line.
class Runtime {
 public:
  Runtime();
  Runtime(int* argc, char*** argv);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

 private:
  bool owner_ = false;
};

/// A dotted key path of the model file and the YAML text that replaces its value there (as a
/// batch case's keys do), e.g. {"solver.dynamics.time_step", "0.02"} or
/// {"drives.winch", "{type: external, initial: 48}"}.
struct Override {
  std::string path;
  std::string yaml;
};

/// A static or dynamic solve that failed: what failed and where (time, Newton residual, the
/// constraint violated most). The simulator keeps the state it had before (statics) or the last
/// accepted step (dynamics) and can go on.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a static solve did.
struct StaticsSummary {
  int increments = 0;
  int newton_iterations = 0;
  double residual = 0.0;
  double max_violation = 0.0;
  std::string message;
  double wall_seconds = 0.0;
};

/// Everything a simulation continues from, in model order (DofMap::to_model_order), so that a
/// state saved from one Simulator restores into another of the same model.
struct SimulatorState {
  double time = 0.0;
  std::vector<double> coordinates, velocities, accelerations;
  std::vector<drive::ExternalSignal> external_drives;  ///< per model drive; unused for other kinds
  long steps = 0;
  double next_time_step = 0.0;
};

/// One model and its simulation, on one process. Statics and dynamics use the model file's solver
/// settings (generalized-alpha; its `solver.dynamics.time_step`, Jacobian reuse and Newton
/// tolerance). advance() continues the integrator where the last call stopped: calls of 0.5 s
/// and 0.5 s give the steps of one call of 1 s. External drives (`type: external`) take a rate
/// or an acceleration from the program at the current time. Outputs are those of the current
/// time. A Runtime must exist while Simulators are made and used.
class Simulator {
 public:
  /// Reads a model file (and its base files), the overrides applied first. Throws InputError
  /// (file, line, key, what was expected) for bad input, std::invalid_argument for a model the
  /// library cannot advance (an integrator other than generalized-alpha).
  static Simulator load(const std::string& path, const std::vector<Override>& overrides = {});
  /// The same from YAML text; `name` stands for the file in messages.
  static Simulator load_string(const std::string& yaml, const std::string& name = "model.yaml",
                               const std::vector<Override>& overrides = {});
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  const Model& model() const;
  double time() const;
  /// The model's time step (solver.dynamics.time_step).
  double time_step() const;

  /// The static equilibrium at the current time from the current state (velocities zero).
  /// Throws SolverError (the state stays as it was).
  StaticsSummary solve_statics();
  /// Advances the dynamics by `interval` simulated seconds (> 0), the last step shortened to land
  /// on the end. Throws SolverError when a step fails: the state is then the last accepted step,
  /// and the next advance restarts the integrator there.
  void advance(double interval);
  /// Steps taken since the start (or the restored state's count).
  long steps() const;

  std::vector<std::string> drive_names() const;
  /// The drives of type external, which set_drive_rate and set_drive_acceleration move.
  std::vector<std::string> external_drive_names() const;
  /// Any drive's value, rate and acceleration at the current time.
  DriveValue drive(const std::string& name) const;
  /// From now on the drive moves at `rate` (its value stays continuous, its rate jumps).
  void set_drive_rate(const std::string& name, double rate);
  /// From now on the drive accelerates at `acceleration` (value and rate stay continuous).
  void set_drive_acceleration(const std::string& name, double acceleration);

  /// Joint outputs by "body.joint" name, inertial frame.
  Vec3 joint_position(const std::string& joint) const;
  Vec3 joint_velocity(const std::string& joint) const;
  /// The joint frame's axes as columns.
  Mat3 joint_orientation(const std::string& joint) const;
  /// The axial force of each element of a body, in element order (a rope's tension, a beam's or
  /// a strut tie's normal force; NaN for an element without one), N.
  std::vector<double> axial_forces(const std::string& body) const;
  /// What a constraint does to its second joint's side (ModelState::constraint_reaction).
  ConstraintReaction constraint_reaction(const std::string& constraint) const;
  ElementEnergy energy() const;
  /// Position and velocity of each of the model's probe joints (output.probes), x y z vx vy vz
  /// per joint, as the probe CSV has them.
  std::vector<double> probes() const;
  /// The coordinate vector in model order, as results record it (/state/coordinates).
  std::vector<double> coordinates() const;

  /// The model linearised about the current state (a static equilibrium, or a state of a run: its
  /// velocities and the integrator's acceleration estimate), reduced to independent coordinates:
  /// inputs the accelerations of the external drives `inputs`, outputs the probe joints'
  /// positions and velocities (LinearModel). Dense, for models of up to a few thousand unknowns.
  LinearModel linearize(const std::vector<std::string>& inputs) const;
  /// Writes a linear model as HDF5 (io/linear_model_file.hpp).
  static void write_linear_model(const std::string& path, const LinearModel& model);
  /// The lowest natural frequencies (Hz) about the current state, which should be a static
  /// equilibrium, as `latticedyn modes` computes them (SLEPc). Throws SolverError when fewer converge.
  std::vector<double> natural_frequencies(int count) const;

  SimulatorState save_state() const;
  /// Puts the simulation back to a saved state (of this model). The integrator restarts there as
  /// after a checkpoint (its start-up steps): advances from a restored state are the same every
  /// time, bit for bit. Throws std::invalid_argument for a state of another model.
  void restore_state(const SimulatorState& state);

 private:
  struct Impl;
  explicit Simulator(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace latticedyn
