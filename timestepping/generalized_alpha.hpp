// Dynamics with PETSc's generalized-alpha method for second-order systems (TSALPHA2) on the
// index-3 equations of motion: forces balanced at t_{n+alpha_f}, constraints g(q_{n+1}) = 0
// scaled to the mass block, rotation vectors rescaled after each step.
#pragma once

#include "timestepping/dynamic_settings.hpp"
#include "timestepping/solver_setup.hpp"

#include <petscts.h>

#include <array>

namespace latticedyn {

class GeneralizedAlphaIntegrator {
 public:
  /// Consecutive step cuts (x 1/4 each) after failed Newton solves before the run stops.
  static constexpr int kMaxStepCuts = 8;
  /// Jacobian reuse: a Newton iteration that leaves more than this fraction of the residual
  /// makes the next one take a fresh Jacobian.
  static constexpr double kChordContraction = 0.5;
  /// On one rank, systems of at most this many unknowns are factored dense (LAPACK); the option
  /// -dyn_dense_below N changes it (0: always the sparse direct solver).
  static constexpr int kDenseBelow = 64;
  /// The block sizes of the matrix, largest first: -dyn_block_size takes one of them (1: none).
  static constexpr std::array<int, 3> kBlockSizes{6, 3, 1};

  GeneralizedAlphaIntegrator(SystemAssembler& assembler, DynamicSettings settings);
  ~GeneralizedAlphaIntegrator();
  GeneralizedAlphaIntegrator(const GeneralizedAlphaIntegrator&) = delete;
  GeneralizedAlphaIntegrator& operator=(const GeneralizedAlphaIntegrator&) = delete;

  /// U (coordinates, multipliers) and V (rotation-vector rates) at t_start in, at the end (or
  /// where it failed) out. The observer sees the initial state and every accepted step. With
  /// `resume` the run continues a checkpoint taken at t_start: `acceleration` is its acceleration
  /// estimate (the predictor's), and the checkpoint's own step is not shown again.
  PetscErrorCode run(Vec U, Vec V, StepObserver* observer, DynamicReport* report, const ResumePoint* resume = nullptr,
                     Vec acceleration = nullptr);

  /// Whether the end of run() restarts the integrator as a checkpoint does (the default: a run
  /// continued from its last checkpoint then goes on identically) or leaves it running for
  /// continue_to().
  void set_open_end(bool open) { open_end_ = open; }
  /// Continues the last run() (open-ended, set_open_end) or continue_to() to t_end: TSALPHA2 keeps
  /// its acceleration and the Jacobian, so the steps are those of one run to the last end but for
  /// the step before each end, shortened to land on it. U, V: as the last call left them.
  /// `report` goes on counting from where the last call left it.
  PetscErrorCode continue_to(double t_end, Vec U, Vec V, StepObserver* observer, DynamicReport* report);
  /// The acceleration estimate at the last accepted step (what a checkpoint keeps).
  Vec acceleration_estimate() const { return A_est_; }

  TS ts() const { return ts_; }

 private:
  /// TSSolve from U, V to the TS's end time, then the report's ending (completed, or what failed).
  PetscErrorCode solve(Vec U, Vec V, DynamicReport* report);
  /// Shortens the next step where it would pass the TS's end time.
  PetscErrorCode land_on_end();
  static PetscErrorCode i2function(TS ts, PetscReal t, Vec U, Vec V, Vec A, Vec F, void* ctx);
  static PetscErrorCode i2jacobian(TS ts, PetscReal t, Vec U, Vec V, Vec A, PetscReal shift_v, PetscReal shift_a, Mat J,
                                   Mat P, void* ctx);
  static PetscErrorCode post_step(TS ts);
  static PetscErrorCode watch_contraction(SNES snes, PetscInt it, PetscReal fnorm, void* ctx);
  static PetscErrorCode predict(SNES snes, Vec U1, void* ctx);
  static PetscErrorCode monitor(TS ts, PetscInt step, PetscReal t, Vec U, void* ctx);
  /// The stage's end-of-step state Uc = U0 + (Ua - U0)/alpha_f, its time, and the settings.
  PetscErrorCode stage(PetscReal ta, Vec Ua, Vec Va, Vec Aa, EvaluationPoint* at, EvaluationSettings* how,
                       double* inertia_factor);

  SystemAssembler& sa_;
  DynamicSettings settings_;
  double reuse_shift_v_ = -1.0, reuse_shift_a_ = -1.0;  // shifts of the Jacobian in J_
  int reuse_count_ = 0;                                 // Newton iterations it has served
  double last_fnorm_ = 0.0;                             // residual norm of the last Newton iterate
  long jacobians_ = 0;                                  // Jacobians assembled in the run
  std::string domain_error_;  // the last failed evaluation: an element outside its domain, or an exception caught
  CheckpointSchedule checkpoints_;
  bool open_end_ = false;      // the end of a run is no checkpoint (set_open_end)
  bool resumed_step_ = false;  // the first monitor call shows the checkpoint's step: not recorded again
  long rejection_offset_ = 0, iteration_offset_ = 0;  // counted before the checkpoint
  PetscBool predictor_ = PETSC_TRUE;                    // -dyn_predictor: Newton starts from a Taylor guess
  TS ts_ = nullptr;
  KSP ksp_ = nullptr;  // the Newton solver's linear solver (ts_ owns it)
  Mat J_ = nullptr;
  Mat P_ = nullptr;  // a dense copy of J_ for small systems, factored instead of it
  Vec F_ = nullptr, Uc_ = nullptr, V_prev_ = nullptr, A_est_ = nullptr, A_scaled_ = nullptr;
  StepObserver* observer_ = nullptr;
  DynamicReport* report_ = nullptr;
};

}  // namespace latticedyn
