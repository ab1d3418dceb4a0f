// Settings of a dynamic simulation and the summary it ends with, shared by both integrators.
#pragma once

#include <string>

namespace latticedyn {

enum class IntegratorKind {
  generalized_alpha,  ///< TSALPHA2 on the index-3 system (default)
  baumgarte,          ///< state space with Baumgarte stabilisation, PETSc TSRK (thesis 4.5)
  implicit_rk,        ///< first-order constrained system, PETSc TSARKIMEX / TSROSW, projection
  minimum_dof         ///< joint coordinates of a tree of rigid bodies (Lagrange II), PETSc TSRK
};

struct DynamicSettings {
  IntegratorKind integrator = IntegratorKind::generalized_alpha;
  double t_start = 0.0;
  double t_end = 1.0;
  double time_step = 1e-3;
  double rho_infinity = 0.9;      ///< generalized-alpha spectral radius at infinite frequency
  bool adaptive = false;          ///< TSAdapt basic on the local error estimate
  double rtol = 1e-4, atol = 1e-6;
  int max_steps = 100000000;
  double baumgarte_alpha = 10.0;  ///< [1/s], (4-27); the thesis suggests half the lowest natural frequency
  double baumgarte_beta = 1.0;
  std::string rk_type = "5dp";    ///< TSRK scheme of the Baumgarte and minimum-DoF routes
  /// Method of the implicit Runge-Kutta route, "family:type": arkimex:3 (ESDIRK, L-stable,
  /// stiffly accurate, order 3), arkimex:4, arkimex:5, arkimex:l2, rosw:ra34pw2, rosw:rodas3, ...
  std::string implicit_method = "arkimex:3";
  /// Generalized-alpha: Newton iterations one Jacobian and its factorisation serve, across steps
  /// (1: a fresh one every iteration). A new step size or a rotation rescale forces a fresh one.
  int jacobian_reuse = 1;
  /// Generalized-alpha: a step's Newton iterations stop when the residual's 2-norm falls below
  /// this fraction of the model's load (its weight and nodal forces), or to its round-off floor.
  double newton_tolerance = 1e-6;
  /// Simulated seconds between checkpoints (0: only at the end). A checkpoint restarts the
  /// integrator there (as a rotation rescale does), so a run continued from it repeats the rest of
  /// the uninterrupted run bit for bit.
  double checkpoint_interval = 0.0;
  /// A hydraulic circuit and its mechanism solved as one system (false: the default), or stepped
  /// apart and coupled every coupling_step (HydraulicCosimulation; generalized-alpha only).
  bool hydraulic_cosimulation = false;
  double coupling_step = 0.0;  ///< s; 0: the time step
};

/// Where a run continues from a checkpoint: the integrator's state beside the coordinates and
/// rates (which the caller puts into U and V, V in the integrator's own parametrization) and the
/// report's counters so far, so that the continued run ends with the whole run's summary.
struct ResumePoint {
  long step = 0;                  ///< steps taken up to the checkpoint
  double next_time_step = 0.0;    ///< the step size the next step takes
  long newton_iterations = 0;
  long rejected_steps = 0;
  long rotation_rescales = 0;
  long jacobians = 0;
  double max_violation = 0.0;
  int violation_constraint = -1;
};

struct DynamicReport {
  bool completed = false;
  bool interrupted = false;       ///< stopped on request after an accepted step (StepObserver::stop_requested)
  double time_reached = 0.0;
  long steps = 0;
  long newton_iterations = 0;
  long rejected_steps = 0;
  long rotation_rescales = 0;
  long jacobians = 0;             ///< Jacobians assembled and factorised (generalized-alpha)
  double wall_seconds = 0.0;
  double max_violation = 0.0;     ///< over all accepted steps
  int violation_constraint = -1;
  std::string message;            ///< what failed and where, or a summary
  std::string linear_solver;      ///< what the linear systems were solved with (describe_linear_solver)
};

}  // namespace latticedyn
