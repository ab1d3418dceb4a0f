// What a verification run keeps: joint positions, energy and constraint violation at the model's
// output times (on rank 0), and the final state; plus the measures taken from them.
#pragma once

#include "drivers/observers.hpp"
#include "drivers/simulation.hpp"
#include "io/input_node.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace latticedyn {

struct Trajectory {
  std::unique_ptr<Simulation> simulation;  ///< the model run (the final state refers to it)
  std::unique_ptr<DofMap> dofs;
  std::vector<double> time;
  std::vector<std::vector<Vec3>> joints;  ///< [step][joint] positions
  std::vector<std::vector<Mat3>> frames;  ///< [step][joint] orientations (joint -> inertial)
  std::vector<Vec3> joints0;              ///< joint positions of the initial model state
  std::vector<double> energy, kinetic;    ///< total (kinetic + gravity + strain) and kinetic
  std::vector<double> violation;          ///< max |g| over all constraints
  std::vector<std::vector<double>> axial;  ///< [step][element] axial force, NaN where none
  std::unique_ptr<ModelState> final_state;
  /// The run's energy account at its end (models with a hydraulic circuit; EnergyLedger).
  std::optional<EnergyAccount> energy_account;
  /// Set before a run: record member_peaks (every element's output at every recorded step).
  bool record_member_peaks = false;
  std::vector<std::vector<double>> member_peaks;  ///< [element][member] largest von Mises stress over the run

  /// Linear interpolation of a joint coordinate at time t (must lie in the recorded range).
  double at(int joint, int component, double t) const;
  /// Mean period of a joint coordinate from its upward crossings of the mid value, over the
  /// outputs at t >= from.
  double period(int joint, int component, double from = -1e300) const;
  /// Damping ratio of a decaying oscillation of a joint coordinate over the outputs at t >= from:
  /// the extrema (refined by a parabola through each sampled extremum and its neighbours), the
  /// decay rate sigma from a least-squares line through the logarithms of the half-cycle ranges
  /// |x_{k+1} - x_k| (independent of where the oscillation is centred), the damped frequency from
  /// the extrema's spacing, zeta = sigma / sqrt(sigma^2 + omega_d^2) (and with omega_n the undamped
  /// circular frequency sqrt(sigma^2 + omega_d^2)). NaN with fewer than 4 extrema.
  double damping_ratio(int joint, int component, double from = -1e300, double* omega_n = nullptr) const;
  /// max |E - E0| / max kinetic energy.
  double energy_drift() const;
};

/// Records at the output interval of the model (every step for 0), like the results writer.
class TrajectoryRecorder final : public StepObserver {
 public:
  TrajectoryRecorder(SystemAssembler& sa, double interval, Trajectory* out);
  PetscErrorCode on_step(const StepInfo& info) override;
  /// Records (t, U, V) as the final state (and as a step if nothing was recorded: statics).
  PetscErrorCode finish(double t, Vec U, Vec V);

 private:
  PetscErrorCode record(double t, Vec U, Vec V, Parametrization param);
  SystemAssembler& sa_;
  ModelState state_;
  std::optional<EnergyLedger> ledger_;  // recorded every step
  double interval_, next_ = 0.0;
  double last_recorded_ = -1e300;  // on every rank: recording is collective
  Trajectory* out_;
};

/// Runs a model file (with its keys replaced by `overrides` first) on `comm` and records its
/// trajectory (valid on rank 0 of comm); with a `results_directory` also writes the run's HDF5 /
/// XDMF / probe CSV there, as `latticedyn run` would. Throws InputError for a bad model; a solver
/// failure is returned in `outcome`.
PetscErrorCode run_and_record(const std::string& model_path, MPI_Comm comm, Trajectory* trajectory,
                              SimulationOutcome* outcome, const std::string& results_directory = "",
                              const std::vector<KeyOverride>& overrides = {});

}  // namespace latticedyn
