// The minimum-DoF route (thesis 2.2.2, 5.1.2): Lagrange's equations of the second kind of a tree of
// rigid bodies in joint coordinates, x = [q; q_dot], integrated by a PETSc Runge-Kutta TS.
#pragma once

#include "assembly/minimum_dof_model.hpp"
#include "timestepping/dynamic_settings.hpp"
#include "timestepping/solver_setup.hpp"

#include <petscts.h>

namespace latticedyn {

/// Same interface as the other integrators: U, V of the multibody model in and out, the observer
/// sees the multibody state (poses, velocity variables, accelerations) after every step. The
/// multipliers (joint reactions) come from the multibody saddle-point system [M G^T; G 0] at the
/// recorded state; its acceleration part is the difference between the two formulations (Lagrange's
/// equations of the first and of the second kind), reported at the end.
class MinimumDofIntegrator {
 public:
  /// Throws ModelError when the model is not a tree of rigid bodies (MinimumDofModel).
  MinimumDofIntegrator(SystemAssembler& assembler, DynamicSettings settings);
  ~MinimumDofIntegrator();
  MinimumDofIntegrator(const MinimumDofIntegrator&) = delete;
  MinimumDofIntegrator& operator=(const MinimumDofIntegrator&) = delete;

  /// U, V (rotation-vector rates; velocity variables when resuming, as checkpoints keep them) at
  /// t_start in, at the end out.
  PetscErrorCode run(Vec U, Vec V, StepObserver* observer, DynamicReport* report, const ResumePoint* resume = nullptr);

  const MinimumDofModel& minimum_model() const { return mdof_; }
  /// Largest |a_multibody - a_minimum_dof| over the recorded steps (m/s^2, rad/s^2).
  double formulation_difference() const { return formulation_difference_; }

 private:
  static PetscErrorCode rhs(TS ts, PetscReal t, Vec X, Vec Xdot, void* ctx);
  static PetscErrorCode monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx);
  /// Every block's state from the distributed U, V (gathered to every rank).
  PetscErrorCode blocks_of(Vec U, Vec V, Parametrization param, std::vector<BlockState>& blocks);
  /// X = [q; q_dot] from U, V.
  PetscErrorCode coordinates_of(double t, Vec U, Vec V, Parametrization param, Vec X);
  /// U_, V_, A_ (velocity variables, multipliers zero) from the blocks' states.
  PetscErrorCode set_vectors(const std::vector<BlockState>& blocks);
  /// U_'s multipliers from [M G^T; G 0][da; lambda] = -r(U_, V_, A_); da is the formulations' difference.
  PetscErrorCode solve_multipliers(double t);

  SystemAssembler& sa_;
  DynamicSettings settings_;
  MinimumDofModel mdof_;
  TS ts_ = nullptr;
  KSP ksp_ = nullptr;
  Mat S_ = nullptr;
  Vec X_ = nullptr, U_ = nullptr, V_ = nullptr, A_ = nullptr, b_ = nullptr, y_ = nullptr;
  std::vector<PetscInt> multipliers_;  // owned multiplier rows (local offsets)
  std::vector<int> model_offset_;      // per block: first DoF in model order, -1 if fixed
  long solves_ = 0;
  double formulation_difference_ = 0.0;
  double segment_end_ = 0.0;  // the stop (drive breakpoint or t_end) the current TSSolve runs to
  CheckpointSchedule checkpoints_;
  bool resumed_step_ = false;
  long rejection_offset_ = 0;
  StepObserver* observer_ = nullptr;
  DynamicReport* report_ = nullptr;
};

}  // namespace latticedyn
