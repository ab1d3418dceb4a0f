// What every solver of this layer shares: the default sparse direct linear solver (overridable by
// PETSc options), the step observer interface, and the report of a failure.
#pragma once

#include "assembly/system_assembler.hpp"
#include "timestepping/dynamic_settings.hpp"

#include <petscsnes.h>
#include <petscts.h>

#include <string>
#include <vector>

namespace latticedyn {

/// KSP defaults for the saddle-point systems: no Krylov iterations, a sparse LU with pivoting
/// (UMFPACK on one process, MUMPS on several). -ksp_type, -pc_type and
/// -pc_factor_mat_solver_type given on the command line or in the model still win, because the
/// callers apply the options database afterwards.
PetscErrorCode set_direct_solver_defaults(KSP ksp);

/// The settings' explicit Runge-Kutta scheme on ts (the Baumgarte and minimum-DoF routes): TSRK
/// `rk_type` from t_start to t_end in steps of time_step, the last step shortened to end at t_end,
/// TSADAPTBASIC on the embedded estimate with rtol/atol when `adaptive`, step failures left to the
/// caller to report; then the options database. Set the right-hand side and monitors before.
PetscErrorCode configure_runge_kutta(TS ts, const DynamicSettings& settings);

/// y = -[M G^T; G 0]^{-1} r(at) with r the residual in `how` (acceleration-level constraint rows):
/// the accelerations (or their correction, when `at` carries some) and the multipliers at one
/// state. The Baumgarte route's right-hand side and the minimum-DoF route's joint reactions. b
/// and S are work space of the assembler's layout; a non-finite force or a failed factorisation
/// is an error naming the time. Collective.
PetscErrorCode solve_saddle_point(SystemAssembler& sa, const EvaluationPoint& at, const EvaluationSettings& how,
                                  KSP ksp, Mat S, Vec b, Vec y);

/// Whether the model has first-order DoFs (DofBlock::first_order: a hydraulic circuit).
bool has_first_order_blocks(const Model& model);

/// The rates of the first-order DoFs (DofBlock::first_order: hydraulic pressures) consistent with
/// their equations at (t, U, V), the other rates kept: each such row is linear in its own rate
/// alone, r = c p_dot + f(U, V), so p_dot = -f / c from two residual evaluations. A run starts
/// with them (a pressure's rate is not an initial condition). Collective; nothing without such DoFs.
PetscErrorCode consistent_first_order_rates(SystemAssembler& sa, double t, Vec U, Vec V);

/// The rank's own multiplier rows, as offsets into its part of a vector of the assembler's layout.
std::vector<PetscInt> owned_multiplier_rows(const SystemAssembler& sa);

/// v = `coordinate` on the rows of coordinates, `multiplier` on the constraints' multiplier rows
/// (v created by the assembler). Collective.
PetscErrorCode fill_by_row_kind(const SystemAssembler& sa, double coordinate, double multiplier, Vec v);

/// What ksp solved with, for the run's summary: e.g. "PETSc LU", "MUMPS LU",
/// "GMRES on additive Schwarz (overlap 1), PETSc LU per subdomain, 5.1 iterations per solve". Call
/// after the solves (the subdomain solvers exist once the preconditioner is set up);
/// krylov_iterations and solves are totals over the run.
PetscErrorCode describe_linear_solver(KSP ksp, long krylov_iterations, long solves, std::string* text);

/// SNES convergence test: PETSc's default (atol, rtol, stol) plus "converged to round-off": once
/// the residual has fallen below 1e-6 of max(its initial value, reference_force) and a Newton
/// step no longer halves it, it has reached the floor set by the stiffest terms (e.g. E A of a
/// steel bar times machine precision) and further iterations cannot improve it. The reference
/// force covers a step that starts at that floor already (a time step from a static
/// equilibrium). A residual at or below `floor` (the assembler's round-off estimate) is converged
/// whatever the absolute tolerance asked: a -snes_atol below it cannot be met, only stalled at.
/// Installed with the context it needs.
PetscErrorCode set_roundoff_convergence_test(SNES snes, double reference_force = 0.0, double floor = 0.0);

/// A snapshot after an accepted step (or the initial state, step 0). U, V are the distributed
/// coordinates/multipliers and rates in `param`; A may be null.
struct StepInfo {
  int step = 0;
  double time = 0.0;
  double dt = 0.0;
  Vec U = nullptr, V = nullptr, A = nullptr;
  Parametrization param = Parametrization::rotation_vector_rates;
  long newton_iterations = 0;  ///< cumulative
  long rejected_steps = 0;     ///< cumulative
  /// A checkpoint is due here: the integrator restarts after this step, and the observer keeps
  /// what continues the run (U, V, A as they are, next_time_step, the report).
  bool checkpoint = false;
  double next_time_step = 0.0;          ///< the step size the next step will take
  const DynamicReport* report = nullptr;  ///< the run so far (set by record_step)
};

/// A Newton iteration of a static solve (for a progress line).
struct StaticIterationInfo {
  double load_factor = 0.0;  ///< the load level being solved for
  double reached = 0.0;      ///< the last one in equilibrium
  int increments = 0;        ///< accepted load increments so far
  int newton_iterations = 0; ///< in all, this one included
  double residual = 0.0;
};

class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual PetscErrorCode on_step(const StepInfo& info) = 0;
  /// After each Newton iteration of a static solve; nothing by default.
  virtual void on_static_iteration(const StaticIterationInfo&) {}
  /// Whether the run should stop after this accepted step (an interrupting signal). Collective:
  /// asked on every rank after every step, it must answer the same everywhere.
  virtual bool stop_requested() { return false; }
};

/// When checkpoints fall: on the grid of multiples of `interval` simulated seconds (0: none on
/// the way), at the end of the run and where it stops on request. A run continued from a
/// checkpoint builds its schedule from the checkpoint's time and meets the same grid.
class CheckpointSchedule {
 public:
  /// `end_is_checkpoint`: the run's end is one (false: a run that will be continued, as the
  /// library's Simulator::advance does, goes on without a restart there).
  CheckpointSchedule(double interval = 0.0, double t_start = 0.0, double t_end = 0.0, bool end_is_checkpoint = true);
  /// Whether the state at t (after an accepted step) is a checkpoint; moves on past t if so.
  bool due(double t, bool stopping);

 private:
  double next_after(double t) const;
  double interval_, t_end_, next_;
  bool end_is_checkpoint_;
};

/// After an accepted step: updates the report (time, steps, iterations, rejections, the largest
/// constraint violation so far), hands the step to the observer (if any) and marks the report
/// interrupted when the observer asks to stop. Collective.
PetscErrorCode record_step(SystemAssembler& sa, const StepInfo& info, DynamicReport* report, StepObserver* observer);

/// record_step for the explicit Runge-Kutta routes (Baumgarte, minimum-DoF) from their TS monitor:
/// the step's size, the rejections so far (plus those before a resume), whether a checkpoint is
/// due, the next step size, with U, V, A in velocity variables. `info` gets what was recorded.
PetscErrorCode record_runge_kutta_step(SystemAssembler& sa, TS ts, PetscInt step, PetscReal t, Vec U, Vec V, Vec A,
                                       long rejection_offset, CheckpointSchedule& checkpoints, DynamicReport* report,
                                       StepObserver* observer, StepInfo* info);

/// After TSSolve of a Newton-based integrator: the report's time reached, whether it completed,
/// and its message: "reached t = ...", interrupted, or what failed (TS and Newton reasons, the
/// last residual, the largest constraint violation at U, the element outside its domain).
/// `method` (may be empty) is named beside the step of a failure. Collective.
PetscErrorCode describe_ending(SystemAssembler& sa, TS ts, Vec U, const std::string& method,
                               const std::string& domain_error, DynamicReport* report);

/// The report's counters from where a continued run resumes (ResumePoint), or zero.
void start_report(const ResumePoint* resume, DynamicReport* report);

/// "constraint 'hinge' (revolute), |g| = 1.2e-3" or "no constraints".
std::string describe_violation(const Model& model, double value, int constraint);

}  // namespace latticedyn
