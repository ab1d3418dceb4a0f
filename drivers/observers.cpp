// Output at intervals and the progress line.
#include "drivers/observers.hpp"

#include "assembly/log_events.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <thread>

namespace latticedyn {

OutputObserver::OutputObserver(SystemAssembler& sa, ResultWriter* writer, double interval, double t_end,
                               std::string integrator)
    : sa_(sa),
      writer_(writer),
      everywhere_(writer && writer->collective()),
      state_(sa.model(), sa.dofs()),
      interval_(interval),
      t_end_(t_end),
      integrator_(std::move(integrator)) {
  if (EnergyLedger::applies(sa.model())) ledger_.emplace(sa.model());
}

const EnergyAccount* OutputObserver::energy_account() const {
  return ledger_ && ledger_->started() ? &ledger_->account() : nullptr;
}

PetscErrorCode OutputObserver::record_energy(double t, Vec U, Vec V, Vec A, Parametrization param) {
  PetscFunctionBeginUser;
  PetscCall(sa_.gather(t, U, V, A, param, &state_, everywhere_));
  if (sa_.dofs().rank() == 0 && (!ledger_->started() || t > ledger_->account().time)) {
    PetscCallCXX(ledger_->record(state_));
    if (writer_) writer_->set_energy_account(ledger_->account());
  }
  PetscFunctionReturn(0);
}

void OutputObserver::resume(const Checkpoint& c) {
  written_ = static_cast<int>(c.outputs_written);
  last_written_ = c.last_output;
  next_ = c.next_output;
}

PetscErrorCode OutputObserver::write_checkpoint(const StepInfo& info) {
  Checkpoint c;
  PetscFunctionBeginUser;
  PetscCall(sa_.gather_in_model_order(info.U, &c.coordinates, everywhere_));
  PetscCall(sa_.gather_in_model_order(info.V, &c.velocities, everywhere_));
  if (info.A) PetscCall(sa_.gather_in_model_order(info.A, &c.accelerations, everywhere_));
  else c.accelerations.assign(c.coordinates.size(), 0.0);
  c.time = info.time;
  c.resume.step = info.step;
  c.resume.next_time_step = info.next_time_step;
  c.resume.newton_iterations = info.newton_iterations;
  c.resume.rejected_steps = info.rejected_steps;
  if (info.report) {
    c.resume.rotation_rescales = info.report->rotation_rescales;
    c.resume.jacobians = info.report->jacobians;
    c.resume.max_violation = info.report->max_violation;
    c.resume.violation_constraint = info.report->violation_constraint;
  }
  c.integrator = integrator_;
  c.velocities_are_rates = info.param == Parametrization::rotation_vector_rates;
  c.outputs_written = written_;
  c.last_output = last_written_;
  c.next_output = next_;
  if (writer_) PetscCallCXX(writer_->write_checkpoint(c));
  ++checkpoints_;
  checkpoint_step_ = info.step;
  checkpoint_time_ = info.time;
  PetscFunctionReturn(0);
}

PetscErrorCode OutputObserver::write(double t, Vec U, Vec V, Vec A, Parametrization param, bool gathered) {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(log_events().output, 0, 0, 0, 0));
  const auto start = std::chrono::steady_clock::now();
  if (!gathered) PetscCall(sa_.gather(t, U, V, A, param, &state_, everywhere_));
  if (writer_) PetscCallCXX(writer_->append(state_));
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  PetscCall(PetscLogEventEnd(log_events().output, 0, 0, 0, 0));
  last_written_ = t;
  ++written_;
  PetscFunctionReturn(0);
}

PetscErrorCode OutputObserver::on_step(const StepInfo& info) {
  PetscFunctionBeginUser;
  const double eps = 1e-9 * std::max(1.0, std::abs(info.time));
  const bool first = written_ == 0;
  const bool due = info.time >= next_ - eps;
  const bool last = info.time >= t_end_ - eps;
  if (ledger_) PetscCall(record_energy(info.time, info.U, info.V, info.A, info.param));
  if (first || due || last) {
    PetscCall(write(info.time, info.U, info.V, info.A, info.param, ledger_.has_value()));
    if (interval_ > 0) {
      // Next multiple of the interval after this time, so outputs stay on a regular grid.
      next_ = (std::floor((info.time + eps) / interval_) + 1) * interval_;
    }
  }
  if (info.checkpoint) PetscCall(write_checkpoint(info));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputObserver::finish(double t, Vec U, Vec V, Parametrization param) {
  PetscFunctionBeginUser;
  if (t == last_written_) PetscFunctionReturn(0);
  if (ledger_) PetscCall(record_energy(t, U, V, nullptr, param));
  PetscCall(write(t, U, V, nullptr, param, ledger_.has_value()));
  PetscFunctionReturn(0);
}

ProgressObserver::ProgressObserver(MPI_Comm comm, double t_start, double t_end)
    : t_start_(t_start), t_end_(t_end), start_(std::chrono::steady_clock::now()), last_print_(start_) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  root_ = rank == 0;
  tty_ = isatty(fileno(stderr)) != 0;
  interval_ = tty_ ? 0.5 : 5.0;
  PetscCallAbort(comm, PetscOptionsGetReal(nullptr, nullptr, "-progress_after", &after_, nullptr));
  PetscCallAbort(comm, PetscOptionsGetReal(nullptr, nullptr, "-progress_interval", &interval_, nullptr));
}

PetscErrorCode ProgressObserver::on_step(const StepInfo& info) {
  if (!root_) return 0;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  // Nothing for runs shorter than a second; the first line once a second has passed.
  if (elapsed < after_ || (shown_ && since < interval_)) return 0;
  last_print_ = now;
  const double done = (info.time - t_start_) / (t_end_ - t_start_);
  const double eta = done > 0 ? elapsed * (1 - done) / done : 0.0;
  const double newton = info.step > 0 ? static_cast<double>(info.newton_iterations) / info.step : 0.0;
  std::fprintf(stderr, "%st = %.4g / %.4g s (%5.1f%%)  step %d  dt %.2e  Newton %.2f/step  elapsed %.1f s  ETA %.1f s%s",
               tty_ ? "\r" : "", info.time, t_end_, 100 * done, info.step, info.dt, newton, elapsed, eta,
               tty_ ? "   " : "\n");
  std::fflush(stderr);
  shown_ = true;
  return 0;
}

void ProgressObserver::on_static_iteration(const StaticIterationInfo& info) {
  if (!root_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (elapsed < after_ || (shown_ && since < interval_)) return;
  last_print_ = now;
  std::fprintf(stderr, "%sstatics: load %.4g of 1 (%d increment%s in equilibrium, up to %.4g), Newton %d, residual %.2e, "
               "elapsed %.1f s%s",
               tty_ ? "\r" : "", info.load_factor, info.increments, info.increments == 1 ? "" : "s", info.reached,
               info.newton_iterations, info.residual, elapsed, tty_ ? "   " : "\n");
  std::fflush(stderr);
  shown_ = true;
}

void ObserverList::on_static_iteration(const StaticIterationInfo& info) {
  for (StepObserver* o : observers_) o->on_static_iteration(info);
}

void ProgressObserver::done() {
  if (root_ && shown_ && tty_) std::fprintf(stderr, "\n");
}

FaultInjection::FaultInjection(MPI_Comm comm) {
  PetscInt rank = -1;
  PetscMPIInt me = 0;
  MPI_Comm_rank(comm, &me);
  PetscCallAbort(comm, PetscOptionsGetInt(nullptr, nullptr, "-fault_injection_rank", &rank, nullptr));
  PetscCallAbort(comm, PetscOptionsGetReal(nullptr, nullptr, "-fault_slow_steps", &slow_, nullptr));
  fail_ = rank == me;
}

PetscErrorCode FaultInjection::on_step(const StepInfo& info) {
  PetscFunctionBeginUser;
  PetscCheck(!fail_ || info.step < 1, PETSC_COMM_SELF, PETSC_ERR_USER,
             "fault injected on this rank at step %d, t = %g s (-fault_injection_rank)", info.step, info.time);
  if (slow_ > 0) std::this_thread::sleep_for(std::chrono::duration<double>(slow_));
  PetscFunctionReturn(0);
}

PetscErrorCode ObserverList::on_step(const StepInfo& info) {
  PetscFunctionBeginUser;
  for (StepObserver* o : observers_) PetscCall(o->on_step(info));
  PetscFunctionReturn(0);
}

bool ObserverList::stop_requested() {
  bool stop = false;
  for (StepObserver* o : observers_) stop = o->stop_requested() || stop;
  return stop;
}

}  // namespace latticedyn
