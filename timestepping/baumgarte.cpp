// Baumgarte route: every right-hand side evaluation assembles and factorises the saddle-point
// matrix (same pattern every time, so the symbolic factorisation is reused) and returns
// x_dot = [q_dot(q, dq), a]. Multipliers are algebraic outputs kept beside the state.
#include "timestepping/baumgarte.hpp"

#include "timestepping/prefixed_options.hpp"

#include <chrono>
#include <cstdio>

namespace latticedyn {

BaumgarteIntegrator::BaumgarteIntegrator(SystemAssembler& sa, DynamicSettings settings)
    : sa_(sa), settings_(settings) {
  const PrefixedOptions options(kDynamicPrefix);  // -dyn_ts_..., -dyn_ksp_... over -ts_..., -ksp_...
  const MPI_Comm comm = sa_.comm();
  for (Vec* v : {&U_, &V_, &A_, &b_, &y_, &Ulam0_}) PetscCallAbort(comm, sa_.create_vector(v));
  PetscCallAbort(comm, VecCreateMPI(comm, 2 * sa_.dofs().owned_size(), 2 * sa_.dofs().global_size(), &X_));
  PetscCallAbort(comm, sa_.create_matrix(&S_));
  multipliers_ = owned_multiplier_rows(sa_);

  PetscCallAbort(comm, KSPCreate(comm, &ksp_));
  PetscCallAbort(comm, set_direct_solver_defaults(ksp_));
  PetscCallAbort(comm, KSPSetFromOptions(ksp_));

  PetscCallAbort(comm, TSCreate(comm, &ts_));
  PetscCallAbort(comm, TSSetApplicationContext(ts_, this));
  PetscCallAbort(comm, TSSetRHSFunction(ts_, nullptr, rhs, this));
  PetscCallAbort(comm, TSSetPostStep(ts_, post_step));
  PetscCallAbort(comm, TSMonitorSet(ts_, monitor, this, nullptr));
  PetscCallAbort(comm, configure_runge_kutta(ts_, settings_));
}

BaumgarteIntegrator::~BaumgarteIntegrator() {
  TSDestroy(&ts_);
  KSPDestroy(&ksp_);
  MatDestroy(&S_);
  for (Vec* v : {&X_, &U_, &V_, &A_, &b_, &y_, &Ulam0_}) VecDestroy(v);
}

PetscErrorCode BaumgarteIntegrator::unpack(Vec X, Vec U, Vec V) const {
  const PetscScalar* x;
  PetscScalar *u, *v;
  PetscFunctionBeginUser;
  const int n = sa_.dofs().owned_size();
  PetscCall(VecGetArrayRead(X, &x));
  PetscCall(VecGetArray(U, &u));
  PetscCall(VecGetArray(V, &v));
  // The multipliers of U are not part of x: keep the latest ones.
  std::vector<double> keep;
  for (PetscInt i : multipliers_) keep.push_back(u[i]);
  std::copy(x, x + n, u);
  std::copy(x + n, x + 2 * n, v);
  for (std::size_t k = 0; k < multipliers_.size(); ++k) u[multipliers_[k]] = keep[k];
  PetscCall(VecRestoreArrayRead(X, &x));
  PetscCall(VecRestoreArray(U, &u));
  PetscCall(VecRestoreArray(V, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::pack(Vec U, Vec V, Vec X) const {
  PetscScalar* x;
  const PetscScalar *u, *v;
  PetscFunctionBeginUser;
  const int n = sa_.dofs().owned_size();
  PetscCall(VecGetArray(X, &x));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(V, &v));
  std::copy(u, u + n, x);
  std::copy(v, v + n, x + n);
  for (PetscInt i : multipliers_) x[i] = x[n + i] = 0.0;
  PetscCall(VecRestoreArray(X, &x));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(V, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::accelerations(PetscReal t, Vec U, Vec V) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(U, Ulam0_));
  PetscScalar* u;
  PetscCall(VecGetArray(Ulam0_, &u));
  for (PetscInt i : multipliers_) u[i] = 0.0;
  PetscCall(VecRestoreArray(Ulam0_, &u));

  EvaluationSettings how;
  how.param = Parametrization::velocity_variables;
  how.rows = ConstraintRows::acceleration;
  how.baumgarte_alpha = settings_.baumgarte_alpha;
  how.baumgarte_beta = settings_.baumgarte_beta;
  const EvaluationPoint at{Ulam0_, V, nullptr, nullptr, t, t};
  PetscCall(solve_saddle_point(sa_, at, how, ksp_, S_, b_, y_));  // [F - f_ext; Gamma*] at a = 0, lambda = 0
  ++solves_;
  PetscCall(VecCopy(y_, A_));
  PetscScalar *a, *uu;
  const PetscScalar* y;
  PetscCall(VecGetArray(A_, &a));
  PetscCall(VecGetArray(U, &uu));
  PetscCall(VecGetArrayRead(y_, &y));
  for (PetscInt i : multipliers_) {
    uu[i] = y[i];
    a[i] = 0.0;
  }
  PetscCall(VecRestoreArray(A_, &a));
  PetscCall(VecRestoreArray(U, &uu));
  PetscCall(VecRestoreArrayRead(y_, &y));
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::rhs(TS, PetscReal t, Vec X, Vec Xdot, void* ctx) {
  auto* self = static_cast<BaumgarteIntegrator*>(ctx);
  PetscFunctionBeginUser;
  PetscCall(self->unpack(X, self->U_, self->V_));
  PetscCall(self->accelerations(t, self->U_, self->V_));
  // q_dot: translations r_dot, rotations T(phi)^{-1} omega; then dq_dot = a.
  Vec qdot = self->b_;  // free after the solve
  PetscCall(VecCopy(self->V_, qdot));
  PetscCall(self->sa_.velocities_to_rates(self->U_, qdot));
  PetscCall(self->pack(qdot, self->A_, Xdot));
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::post_step(TS ts) {
  void* ctx;
  Vec X;
  PetscBool changed;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &ctx));
  auto* self = static_cast<BaumgarteIntegrator*>(ctx);
  // A stop asked for at the last monitor ends the run after this step (TSStep resets the reason).
  if (self->report_->interrupted) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  PetscCall(TSGetSolution(ts, &X));
  PetscCall(self->unpack(X, self->U_, self->V_));
  PetscCall(self->sa_.rescale_rotations(self->U_, nullptr, Parametrization::velocity_variables, &changed));
  if (changed) {
    PetscCall(self->pack(self->U_, self->V_, X));
    PetscCall(TSRestartStep(ts));  // first-same-as-last schemes must not reuse the old stage
    ++self->report_->rotation_rescales;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx) {
  auto* self = static_cast<BaumgarteIntegrator*>(ctx);
  PetscFunctionBeginUser;
  if (self->resumed_step_) {  // the checkpoint's state, recorded by the run that wrote it
    self->resumed_step_ = false;
    PetscFunctionReturn(0);
  }
  PetscCall(self->unpack(X, self->U_, self->V_));
  PetscCall(self->accelerations(t, self->U_, self->V_));  // exact a and lambda at this state
  StepInfo info;
  PetscCall(record_runge_kutta_step(self->sa_, ts, step, t, self->U_, self->V_, self->A_, self->rejection_offset_,
                                    self->checkpoints_, self->report_, self->observer_, &info));
  // First-same-as-last schemes reuse the last stage: from a checkpoint on the scheme starts
  // afresh, in this run as in one continued from it.
  if (info.checkpoint) PetscCall(TSRestartStep(ts));
  PetscFunctionReturn(0);
}

PetscErrorCode BaumgarteIntegrator::run(Vec U, Vec V, StepObserver* observer, DynamicReport* report,
                                        const ResumePoint* resume) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kDynamicPrefix);  // also for what is read while solving
  start_report(resume, report);
  observer_ = observer;
  report_ = report;
  solves_ = 0;
  PetscReal t_begin, t_end;  // -ts_max_time and the like may have changed them
  PetscCall(TSGetTime(ts_, &t_begin));
  PetscCall(TSGetMaxTime(ts_, &t_end));
  checkpoints_ = CheckpointSchedule(settings_.checkpoint_interval, t_begin, t_end);
  const auto start = std::chrono::steady_clock::now();
  PetscCall(VecCopy(U, U_));
  PetscCall(VecCopy(V, V_));
  if (resume) {
    PetscCall(TSSetStepNumber(ts_, resume->step));
    PetscCall(TSSetTimeStep(ts_, resume->next_time_step));
    rejection_offset_ = resume->rejected_steps;
    resumed_step_ = true;
  } else {
    PetscCall(sa_.rates_to_velocities(U_, V_));
  }
  PetscCall(pack(U_, V_, X_));
  PetscCall(TSSolve(ts_, X_));
  PetscCall(unpack(X_, U_, V_));
  PetscCall(VecCopy(U_, U));
  PetscCall(VecCopy(V_, V));
  PetscCall(sa_.velocities_to_rates(U, V));
  report->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  TSConvergedReason reason;
  PetscReal t;
  PetscCall(TSGetConvergedReason(ts_, &reason));
  PetscCall(TSGetTime(ts_, &t));
  report->time_reached = t;
  report->completed = reason > 0 && !report->interrupted;
  char buf[512];
  if (report->completed)
    std::snprintf(buf, sizeof buf, "reached t = %.6g s", t);
  else if (report->interrupted)
    std::snprintf(buf, sizeof buf, "dynamics interrupted at t = %.6g s after step %ld", t, report->steps);
  else
    std::snprintf(buf, sizeof buf, "dynamics stopped at t = %.6g s (step %ld): TS %s", t, report->steps,
                  TSConvergedReasons[reason]);
  report->message = buf;
  PetscInt krylov = 0;
  PetscCall(KSPGetTotalIterations(ksp_, &krylov));
  PetscCall(describe_linear_solver(ksp_, krylov, solves_, &report->linear_solver));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
