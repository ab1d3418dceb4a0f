// What a run shows and keeps while it goes: results written at the output interval, a progress
// line on stderr (simulated time, steps, ETA) for runs longer than a second.
#pragma once

#include "io/checkpoint.hpp"
#include "io/result_writer.hpp"
#include "timestepping/solver_setup.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace latticedyn {

/// Gathers the state to rank 0 (to every rank for a collective writer, which every rank then
/// holds) and appends it to the results every `interval` simulated
/// seconds (every step for 0), always including the first and the last state; writes a
/// checkpoint where the integrator marks one (StepInfo::checkpoint). With a hydraulic circuit it
/// keeps the run's energy account, recording every step (the works are integrals over the steps).
class OutputObserver final : public StepObserver {
 public:
  OutputObserver(SystemAssembler& sa, ResultWriter* writer, double interval, double t_end,
                 std::string integrator = "generalized_alpha");
  PetscErrorCode on_step(const StepInfo& info) override;
  /// Writes (t, U, V) unless it was the last state written.
  PetscErrorCode finish(double t, Vec U, Vec V, Parametrization param);
  /// Goes on with the output schedule of a checkpoint whose results file the writer continues.
  void resume(const Checkpoint& c);
  int written() const { return written_; }
  /// Wall seconds this rank spent in writing outputs (gathering the state included); on rank 0,
  /// which writes, what the outputs cost the run.
  double seconds() const { return seconds_; }
  /// The energy account on rank 0 (models with a hydraulic circuit), none otherwise. A restarted
  /// run's account starts at its checkpoint.
  const EnergyAccount* energy_account() const;
  /// Checkpoints written in this run, and the step and time of the last (-1 for none).
  int checkpoints() const { return checkpoints_; }
  long last_checkpoint_step() const { return checkpoint_step_; }
  double last_checkpoint_time() const { return checkpoint_time_; }

 private:
  /// Gathers the state (unless `gathered`: it is in state_) and appends it.
  PetscErrorCode write(double t, Vec U, Vec V, Vec A, Parametrization param, bool gathered = false);
  /// Gathers the state into state_ and adds it to the energy account.
  PetscErrorCode record_energy(double t, Vec U, Vec V, Vec A, Parametrization param);
  PetscErrorCode write_checkpoint(const StepInfo& info);
  SystemAssembler& sa_;
  ResultWriter* writer_;
  bool everywhere_ = false;  // the writer is collective: the state goes to every rank
  ModelState state_;
  std::optional<EnergyLedger> ledger_;
  double interval_, t_end_;
  double next_ = 0.0, last_written_ = -1e300;
  int written_ = 0;
  double seconds_ = 0.0;
  std::string integrator_;
  int checkpoints_ = 0;
  long checkpoint_step_ = -1;
  double checkpoint_time_ = 0.0;
};

/// The progress line on stderr (rank 0): from `-progress_after` seconds of wall time on (default
/// 1), then every `-progress_interval` seconds (default 0.5 on a terminal, where the line is
/// rewritten in place, 5 in logs).
class ProgressObserver final : public StepObserver {
 public:
  static constexpr double kDefaultAfter = 1.0;     ///< -progress_after
  static constexpr double kDefaultInterval = 5.0;  ///< -progress_interval in a log (0.5 on a terminal)
  ProgressObserver(MPI_Comm comm, double t_start, double t_end);
  PetscErrorCode on_step(const StepInfo& info) override;
  /// "statics: load 0.5 (3 increments), Newton 12, residual 1.2e-03, elapsed 2.1 s".
  void on_static_iteration(const StaticIterationInfo& info) override;
  /// Ends the progress line (if one was shown).
  void done();

 private:
  bool root_ = false;
  double t_start_, t_end_;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool shown_ = false;
  bool tty_ = false;
  double after_ = kDefaultAfter, interval_ = kDefaultInterval;
};

/// Testing aids: a PETSc error raised on one rank at the first step (`-fault_injection_rank R`)
/// shows that an error on one rank ends the run on all of them instead of leaving the others
/// waiting; steps made slow (`-fault_slow_steps SECONDS` of sleep after each) leave time for a
/// second signal while the first waits for the step to end.
class FaultInjection final : public StepObserver {
 public:
  explicit FaultInjection(MPI_Comm comm);
  PetscErrorCode on_step(const StepInfo& info) override;

 private:
  bool fail_ = false;
  double slow_ = 0.0;
};

/// Forwards every step to several observers.
class ObserverList final : public StepObserver {
 public:
  void add(StepObserver* o) { observers_.push_back(o); }
  PetscErrorCode on_step(const StepInfo& info) override;
  /// Any of them (each asked: the question is collective).
  bool stop_requested() override;
  void on_static_iteration(const StaticIterationInfo& info) override;

 private:
  std::vector<StepObserver*> observers_;
};

}  // namespace latticedyn
