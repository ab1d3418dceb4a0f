// Static equilibrium (thesis 5.1.1, "nonlinear equation solution"): F(q) + G^T lambda = f_ext,
// g(q) = 0 with rates zero, solved by PETSc SNES (full Newton steps) under load ramping with cuts.
#pragma once

#include "timestepping/solver_setup.hpp"

#include <petscsnes.h>

#include <string>
#include <vector>

namespace latticedyn {

struct StaticSettings {
  double time = 0.0;       ///< time at which drives and loads are evaluated
  int load_steps = 1;      ///< equal increments of gravity and nodal loads
  /// U is the equilibrium of a nearby model under full load (a warm start in a batch chain): one
  /// Newton solve at full load instead of a ramp from zero, which would unload the state first.
  bool warm_start = false;
  int max_cuts = 8;        ///< halvings of a failed increment before giving up
  double rtol = 1e-10;     ///< SNES relative residual tolerance
  double atol = 1e-8;      ///< SNES absolute residual tolerance (scaled units: N)
  int max_iterations = 50;
  /// Inertia added to the tangent, K + mu M with mu = regularization x (mean diagonal stiffness
  /// / mean diagonal mass), once plain Newton has failed on an increment: a pseudo-time step that
  /// keeps neutral modes solvable (a load spinning on its hook, an unstressed straight rope with
  /// no lateral stiffness yet). It changes the path of the iterations, not the equilibrium they
  /// converge to (but costs iterations, so it stays off until needed); 0 never adds it.
  double regularization = 1e-6;
};

struct StaticReport {
  bool converged = false;
  int increments = 0;           ///< accepted load increments
  int newton_iterations = 0;    ///< total
  double residual_norm = 0.0;   ///< at the end (or where it failed)
  double load_factor = 0.0;     ///< reached
  double max_violation = 0.0;
  int violation_constraint = -1;
  std::string message;          ///< what failed and where, or a summary
  double wall_seconds = 0.0;
};

class StaticSolver {
 public:
  StaticSolver(SystemAssembler& assembler, StaticSettings settings);
  ~StaticSolver();
  StaticSolver(const StaticSolver&) = delete;
  StaticSolver& operator=(const StaticSolver&) = delete;

  /// U: initial guess in, equilibrium (coordinates and multipliers) out. On failure U holds the
  /// last converged load level and the report says where and why it failed. Collective.
  /// `observer` (may be null) hears of every Newton iteration (StepObserver::on_static_iteration).
  PetscErrorCode solve(Vec U, StaticReport* report, StepObserver* observer = nullptr);

 private:
  static PetscErrorCode form_function(SNES, Vec U, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec U, Mat J, Mat P, void* ctx);
  static PetscErrorCode monitor(SNES, PetscInt it, PetscReal fnorm, void* ctx);
  EvaluationSettings evaluation() const;

  SystemAssembler& sa_;
  StaticSettings settings_;
  SNES snes_ = nullptr;
  Mat J_ = nullptr;
  Vec F_ = nullptr;
  std::vector<PetscReal> history_;  ///< residual norms of the current Newton solve
  std::string evaluation_error_;    ///< the last failed evaluation (SystemAssembler::evaluation_error)
  bool regularized_ = false;        ///< K + mu M in use (after plain Newton failed once)
  double initial_residual_ = 0.0;   ///< |F| at the first Jacobian of the current solve (mu's scale)
  double load_factor_ = 1.0;
  StaticIterationInfo progress_;      ///< of the solve in progress
  StepObserver* observer_ = nullptr;  ///< of the solve in progress
};

}  // namespace latticedyn
