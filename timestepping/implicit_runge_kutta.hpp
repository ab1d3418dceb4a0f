// Implicit Runge-Kutta route: the constrained equations as a first-order index-1 DAE in
// X = [U; V] (coordinates and multipliers; rotation-vector rates), stepped by PETSc's TSARKIMEX
// (fully implicit ESDIRK) or TSROSW, and projected back onto g = 0 and g_dot = 0 after each step.
#pragma once

#include "timestepping/dynamic_settings.hpp"
#include "timestepping/solver_setup.hpp"

#include <petscts.h>

#include <string>
#include <vector>

namespace latticedyn {

/// The residual F(t, X, X_dot) = [U_dot - V ; M V_dot + F(U, V) + G^T lambda ; s (G V_dot + Gamma)]
/// (the multiplier slots of V are held at zero) is linear in U_dot, so every Newton matrix
/// dF/dX + sigma dF/dX_dot reduces, by eliminating the kinematic rows, to the generalized-alpha
/// iteration matrix K + sigma C + sigma^2 M with the constraint rows sigma^2 s G: one assembly
/// and one sparse LU of the size of U per Jacobian, as for TSALPHA2. PETSc sees a shell matrix of
/// size 2N and a shell preconditioner that does the elimination exactly (KSPPREONLY).
class ImplicitRungeKuttaIntegrator {
 public:
  /// Consecutive step cuts (x 1/4 each) after failed Newton solves before the run stops.
  static constexpr int kMaxStepCuts = 8;
  /// An ESDIRK method needs the slope at its first stage; at a (re)start PETSc gets it from a
  /// backward Euler step, which is only first-order accurate: that step is taken this fraction
  /// of the time step long, so its error stays far below the method's.
  static constexpr double kStartStepFraction = 1e-4;

  ImplicitRungeKuttaIntegrator(SystemAssembler& assembler, DynamicSettings settings);
  ~ImplicitRungeKuttaIntegrator();
  ImplicitRungeKuttaIntegrator(const ImplicitRungeKuttaIntegrator&) = delete;
  ImplicitRungeKuttaIntegrator& operator=(const ImplicitRungeKuttaIntegrator&) = delete;

  /// U (coordinates, multipliers) and V (rotation-vector rates) at t_start in, at the end (or
  /// where it failed) out. The observer sees the initial state and every accepted step. With
  /// `resume` the run continues a checkpoint taken at t_start (the method restarts there, as it
  /// does at every checkpoint of the run that wrote it).
  PetscErrorCode run(Vec U, Vec V, StepObserver* observer, DynamicReport* report, const ResumePoint* resume = nullptr);

  TS ts() const { return ts_; }
  /// "ARKIMEX 3" and the like, for the summary.
  std::string method_name() const;

 private:
  static PetscErrorCode ifunction(TS ts, PetscReal t, Vec X, Vec Xdot, Vec F, void* ctx);
  static PetscErrorCode ijacobian(TS ts, PetscReal t, Vec X, Vec Xdot, PetscReal shift, Mat A, Mat P, void* ctx);
  static PetscErrorCode shell_mult(Mat A, Vec x, Vec y);
  static PetscErrorCode shell_apply(PC pc, Vec b, Vec y);
  static PetscErrorCode post_step(TS ts);
  static PetscErrorCode monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx);

  /// y = (dF/dV + sigma dF/dA) x at the Jacobian's point (x zero on the multiplier rows), by a
  /// difference of residuals: the force rows are linear in A, and in V the step is 1e-7 of it.
  PetscErrorCode rate_derivative(Vec x, Vec y);
  /// Moves U onto g = 0 and then V onto g_dot = 0 with the last factorisation (the correction
  /// least in the iteration matrix's norm); a few passes for the nonlinearity of g.
  PetscErrorCode project(Vec U, Vec V, double t);
  /// The next step starts the method afresh (a backward-Euler start step of kStartStepFraction h).
  PetscErrorCode restart();
  PetscErrorCode split(Vec X, Vec* U, Vec* V) const;
  PetscErrorCode unsplit(Vec X, Vec* U, Vec* V) const;
  PetscErrorCode settings_for(EvaluationSettings* how) const;
  /// Zero on the multiplier rows of a vector of the assembler's layout.
  PetscErrorCode zero_multipliers(Vec v) const;
  /// `to`'s multiplier rows = `from`'s (both of the assembler's layout).
  PetscErrorCode copy_multipliers(Vec from, Vec to) const;

  SystemAssembler& sa_;
  DynamicSettings settings_;
  std::string family_, type_;  // TSARKIMEX or TSROSW and its scheme
  double constraint_scale_ = 1.0;
  TS ts_ = nullptr;
  KSP inner_ = nullptr;  // factors the reduced matrix J_
  Mat J_ = nullptr;      // K + sigma C + sigma^2 M, constraint rows sigma^2 s G
  Mat shell_ = nullptr;  // the 2N x 2N Newton matrix, applied through J_
  IS is_u_ = nullptr, is_v_ = nullptr;
  Vec X_ = nullptr;
  Vec U0_ = nullptr, V0_ = nullptr, A0_ = nullptr, F0_ = nullptr;  // the Jacobian's point and residual there
  Vec Vp_ = nullptr, Ap_ = nullptr, Fp_ = nullptr, w_ = nullptr, r_ = nullptr, d_ = nullptr;
  Vec V_prev_ = nullptr, A_est_ = nullptr;
  std::vector<PetscInt> multipliers_;  // owned multiplier rows (local offsets)
  double t0_ = 0.0, sigma_ = 0.0;
  bool have_jacobian_ = false, f0_valid_ = false;
  bool start_step_ = false;  // the step after a restart is the short start step
  double restart_time_ = 0.0;
  long jacobians_ = 0, projections_ = 0;
  std::string domain_error_;
  CheckpointSchedule checkpoints_;
  bool resumed_step_ = false;
  long rejection_offset_ = 0, iteration_offset_ = 0;
  long start_steps_taken_ = 0;  // ARKIMEX's start steps so far, which PETSc numbers as steps
  StepObserver* observer_ = nullptr;
  DynamicReport* report_ = nullptr;
};

}  // namespace latticedyn
