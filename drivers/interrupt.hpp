// SIGINT and SIGTERM during a run: the first finishes the current step, writes the results and the
// summary and ends with 130 / 143; a second one (a second after the first) ends the process at once.
#pragma once

#include "timestepping/solver_setup.hpp"

#include <mpi.h>

#include <csignal>

namespace latticedyn {

/// Installs the handlers for its lifetime (the previous ones come back after). A step observer:
/// after every accepted step it tells the integrator to stop once any rank has had a signal.
class InterruptObserver final : public StepObserver {
 public:
  explicit InterruptObserver(MPI_Comm comm);
  ~InterruptObserver() override;
  InterruptObserver(const InterruptObserver&) = delete;
  InterruptObserver& operator=(const InterruptObserver&) = delete;

  PetscErrorCode on_step(const StepInfo&) override { return 0; }
  bool stop_requested() override;
  /// The signal that stopped the run (the largest number over the ranks), 0 if none.
  int signal() const { return signal_; }
  /// The exit code of a run stopped by signal(): 128 + its number (130 SIGINT, 143 SIGTERM).
  int exit_code() const { return 128 + signal_; }
  /// "SIGINT", "SIGTERM".
  const char* signal_name() const;

 private:
  MPI_Comm comm_;
  int signal_ = 0;
  struct sigaction old_int_ {}, old_term_ {};
};

}  // namespace latticedyn
