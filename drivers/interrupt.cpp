// Signal handlers that only set a flag; the run polls it after each step.
#include "drivers/interrupt.hpp"

#include <time.h>
#include <unistd.h>

namespace latticedyn {

namespace {

volatile std::sig_atomic_t g_received = 0;
timespec g_first{};  // when the first signal came

double seconds_since(const timespec& t0) {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe
  return static_cast<double>(now.tv_sec - t0.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec - t0.tv_nsec);
}

extern "C" void on_signal(int signo) {
  if (g_received != 0) {
    // The same signal again within a second is the same request delivered twice (Ctrl-C reaches
    // both mpiexec, which forwards it, and the ranks; `timeout` signals the child and its group).
    if (seconds_since(g_first) < 1.0) return;
    // A second request: no more waiting for the step to end.
    std::signal(signo, SIG_DFL);
    std::raise(signo);
    return;
  }
  clock_gettime(CLOCK_MONOTONIC, &g_first);
  g_received = signo;
  static const char kNote[] = "\nlatticedyn: interrupted: finishing the step and writing the results (again to stop at once)\n";
  (void)!::write(STDERR_FILENO, kNote, sizeof kNote - 1);  // async-signal-safe, unlike stdio
}

}  // namespace

InterruptObserver::InterruptObserver(MPI_Comm comm) : comm_(comm) {
  g_received = 0;
  struct sigaction act {};
  act.sa_handler = on_signal;
  sigemptyset(&act.sa_mask);
  act.sa_flags = SA_RESTART;
  sigaction(SIGINT, &act, &old_int_);
  sigaction(SIGTERM, &act, &old_term_);
}

InterruptObserver::~InterruptObserver() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

bool InterruptObserver::stop_requested() {
  const int mine = g_received;
  int any = mine;
  int size = 1;
  MPI_Comm_size(comm_, &size);
  if (size > 1) MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm_);  // a signal to one rank stops all
  if (any != 0) signal_ = any;
  return any != 0;
}

const char* InterruptObserver::signal_name() const {
  switch (signal_) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

}  // namespace latticedyn
