// The thesis's route (4.5): state x = [q, dq] with dq = [r_dot, omega], accelerations and
// multipliers from the saddle-point system [M G^T; G 0][a; lambda] = -[F; Gamma*] with Baumgarte's
// Gamma* = Gamma + 2 alpha beta g_dot + alpha^2 g, integrated by a PETSc Runge-Kutta TS.
#pragma once

#include "timestepping/dynamic_settings.hpp"
#include "timestepping/solver_setup.hpp"

#include <petscts.h>

namespace latticedyn {

class BaumgarteIntegrator {
 public:
  BaumgarteIntegrator(SystemAssembler& assembler, DynamicSettings settings);
  ~BaumgarteIntegrator();
  BaumgarteIntegrator(const BaumgarteIntegrator&) = delete;
  BaumgarteIntegrator& operator=(const BaumgarteIntegrator&) = delete;

  /// U (coordinates; multipliers are outputs) and V (rotation-vector rates, as everywhere at the
  /// interface) at t_start in, at the end out. The observer sees velocity variables. With
  /// `resume` the run continues a checkpoint taken at t_start, and V comes in velocity variables
  /// as the checkpoint keeps them (a conversion would not give back the same bits).
  PetscErrorCode run(Vec U, Vec V, StepObserver* observer, DynamicReport* report, const ResumePoint* resume = nullptr);

  TS ts() const { return ts_; }

 private:
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec Xdot, void* ctx);
  static PetscErrorCode post_step(TS ts);
  static PetscErrorCode monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx);
  PetscErrorCode unpack(Vec X, Vec U, Vec V) const;
  PetscErrorCode pack(Vec U, Vec V, Vec X) const;
  /// a and lambda at (t, U, V): fills A_ and the multipliers of U_.
  PetscErrorCode accelerations(PetscReal t, Vec U, Vec V);

  SystemAssembler& sa_;
  DynamicSettings settings_;
  TS ts_ = nullptr;
  KSP ksp_ = nullptr;
  long solves_ = 0;  // linear solves in the run (one per right-hand side)
  Mat S_ = nullptr;
  Vec X_ = nullptr, U_ = nullptr, V_ = nullptr, A_ = nullptr, b_ = nullptr, y_ = nullptr, Ulam0_ = nullptr;
  std::vector<PetscInt> multipliers_;  // owned multiplier rows (local offsets)
  CheckpointSchedule checkpoints_;
  bool resumed_step_ = false;  // the first monitor call shows the checkpoint's step: not recorded again
  long rejection_offset_ = 0;
  StepObserver* observer_ = nullptr;
  DynamicReport* report_ = nullptr;
};

}  // namespace latticedyn
