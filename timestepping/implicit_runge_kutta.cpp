// TSARKIMEX / TSROSW callbacks of the implicit Runge-Kutta route. The acceleration-level
// constraint rows make the DAE index 1, where stiffly accurate implicit Runge-Kutta and
// Rosenbrock methods keep their classical order; the drift that index reduction allows is
// removed by projecting each accepted step back onto g = 0 and g_dot = 0 (Hairer, Lubich & Roche
// 1989; Hairer & Wanner, Solving ODEs II, VII.2), which keeps the order too.
#include "timestepping/implicit_runge_kutta.hpp"

#include "timestepping/native_lu.hpp"
#include "timestepping/prefixed_options.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace latticedyn {

namespace {

/// "arkimex:3" -> ("arkimex", "3"); a family alone takes its default scheme.
void parse_method(const std::string& method, std::string* family, std::string* type) {
  const auto colon = method.find(':');
  *family = method.substr(0, colon);
  *type = colon == std::string::npos ? "" : method.substr(colon + 1);
  if (*family != TSARKIMEX && *family != TSROSW)
    throw std::invalid_argument("implicit Runge-Kutta method '" + method + "': expected arkimex:TYPE or rosw:TYPE");
  if (type->empty()) *type = *family == TSARKIMEX ? "3" : "ra34pw2";
}

}  // namespace

ImplicitRungeKuttaIntegrator::ImplicitRungeKuttaIntegrator(SystemAssembler& sa, DynamicSettings settings)
    : sa_(sa), settings_(settings) {
  const PrefixedOptions options(kDynamicPrefix);  // -dyn_ts_..., -dyn_snes_... over -ts_..., -snes_...
  const MPI_Comm comm = sa_.comm();
  parse_method(settings_.implicit_method, &family_, &type_);
  // The constraint rows weigh like the force rows: s (G a + Gamma) with s a typical mass.
  constraint_scale_ = sa_.characteristic_mass();
  const PetscInt n = sa_.dofs().owned_size(), N = sa_.dofs().global_size();
  for (Vec* v : {&U0_, &V0_, &A0_, &F0_, &Vp_, &Ap_, &Fp_, &w_, &r_, &d_, &V_prev_, &A_est_})
    PetscCallAbort(comm, sa_.create_vector(v));
  PetscCallAbort(comm, VecCreateMPI(comm, 2 * n, 2 * N, &X_));
  PetscInt lo;
  PetscCallAbort(comm, VecGetOwnershipRange(X_, &lo, nullptr));
  PetscCallAbort(comm, ISCreateStride(comm, n, lo, 1, &is_u_));
  PetscCallAbort(comm, ISCreateStride(comm, n, lo + n, 1, &is_v_));
  multipliers_ = owned_multiplier_rows(sa_);

  // The reduced matrix and its own direct solver: PETSc's LU in the saddle-point ordering on one
  // rank (as for generalized-alpha), MUMPS on several; -dyn_irk_pc_type and the like change it.
  PetscCallAbort(comm, sa_.create_matrix(&J_));
  PetscCallAbort(comm, KSPCreate(comm, &inner_));
  PetscCallAbort(comm, KSPSetOptionsPrefix(inner_, "irk_"));
  PetscCallAbort(comm, set_direct_solver_defaults(inner_));
  PetscMPIInt ranks;
  PetscCallAbort(comm, MPI_Comm_size(comm, &ranks));
  if (ranks == 1) PetscCallAbort(comm, use_native_lu(inner_));
  PetscCallAbort(comm, KSPSetOperators(inner_, J_, J_));
  PetscCallAbort(comm, KSPSetFromOptions(inner_));

  PetscCallAbort(comm, MatCreateShell(comm, 2 * n, 2 * n, 2 * N, 2 * N, this, &shell_));
  PetscCallAbort(comm, MatShellSetOperation(shell_, MATOP_MULT, reinterpret_cast<void (*)(void)>(shell_mult)));

  PetscCallAbort(comm, TSCreate(comm, &ts_));
  PetscCallAbort(comm, TSSetType(ts_, family_.c_str()));
  if (family_ == TSARKIMEX) {
    PetscCallAbort(comm, TSARKIMEXSetType(ts_, type_.c_str()));
    PetscCallAbort(comm, TSARKIMEXSetFullyImplicit(ts_, PETSC_TRUE));
  } else {
    PetscCallAbort(comm, TSRosWSetType(ts_, type_.c_str()));
  }
  PetscCallAbort(comm, TSSetEquationType(ts_, TS_EQ_DAE_IMPLICIT_INDEX1));
  PetscCallAbort(comm, TSSetApplicationContext(ts_, this));
  PetscCallAbort(comm, TSSetIFunction(ts_, nullptr, ifunction, this));
  PetscCallAbort(comm, TSSetIJacobian(ts_, shell_, shell_, ijacobian, this));
  PetscCallAbort(comm, TSSetTime(ts_, settings_.t_start));
  PetscCallAbort(comm, TSSetTimeStep(ts_, settings_.time_step));
  PetscCallAbort(comm, TSSetMaxTime(ts_, settings_.t_end));
  PetscCallAbort(comm, TSSetMaxSteps(ts_, settings_.max_steps));
  PetscCallAbort(comm, TSSetExactFinalTime(ts_, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCallAbort(comm, TSSetErrorIfStepFails(ts_, PETSC_FALSE));  // we report failures ourselves
  PetscCallAbort(comm, TSSetPostStep(ts_, post_step));
  PetscCallAbort(comm, TSMonitorSet(ts_, monitor, this, nullptr));
  PetscCallAbort(comm, TSSetMaxSNESFailures(ts_, kMaxStepCuts + 1));

  // Local error of coordinates and rates only: the multipliers (and the zero rows beside the
  // rates) are algebraic.
  TSAdapt adapt;
  PetscCallAbort(comm, TSGetAdapt(ts_, &adapt));
  PetscCallAbort(comm, TSAdaptSetType(adapt, settings_.adaptive ? TSADAPTBASIC : TSADAPTNONE));
  Vec vatol, vrtol;
  PetscCallAbort(comm, VecDuplicate(X_, &vatol));
  PetscCallAbort(comm, VecDuplicate(X_, &vrtol));
  PetscCallAbort(comm, VecSet(vatol, settings_.atol));
  PetscCallAbort(comm, VecSet(vrtol, settings_.rtol));
  PetscScalar *a, *r;
  PetscCallAbort(comm, VecGetArray(vatol, &a));
  PetscCallAbort(comm, VecGetArray(vrtol, &r));
  for (PetscInt i : multipliers_)
    for (PetscInt k : {i, i + n}) a[k] = r[k] = 1e300;
  PetscCallAbort(comm, VecRestoreArray(vatol, &a));
  PetscCallAbort(comm, VecRestoreArray(vrtol, &r));
  PetscCallAbort(comm, TSSetTolerances(ts_, 0.0, vatol, 0.0, vrtol));
  PetscCallAbort(comm, VecDestroy(&vatol));
  PetscCallAbort(comm, VecDestroy(&vrtol));

  SNES snes;
  PetscCallAbort(comm, TSGetSNES(ts_, &snes));
  PetscCallAbort(comm, SNESSetType(snes, SNESNEWTONLS));
  SNESLineSearch ls;
  PetscCallAbort(comm, SNESGetLineSearch(snes, &ls));
  PetscCallAbort(comm, SNESLineSearchSetType(ls, has_first_order_blocks(sa_.model()) ? SNESLINESEARCHBT : SNESLINESEARCHBASIC));
  // The stage equations to the same fraction of the model's load as generalized-alpha's.
  const double atol = std::max(settings_.newton_tolerance * sa_.characteristic_load(), sa_.residual_floor());
  PetscCallAbort(comm, SNESSetTolerances(snes, atol, 1e-10, 1e-14, 25, 100000));
  // Every stage takes at least one Newton step. A stage's first guess is the last stage value
  // (Y' = 0), and where the model moves slowly its residual is already below atol (a force: the
  // kinematic rows U' = V are not measured in it): accepted as it was, the reduced crane lifting
  // stood still from t = 55.6 s on (44 outputs of one state) while the clock ran.
  PetscCallAbort(comm, SNESSetForceIteration(snes, PETSC_TRUE));
  const double force_scale = std::max(1.0, sa_.characteristic_mass() * std::max(1.0, sa_.model().gravity.norm()));
  PetscCallAbort(comm, set_roundoff_convergence_test(snes, std::max(force_scale, 1e-3 * sa_.characteristic_stiffness()),
                                                           sa_.residual_floor()));
  KSP ksp;
  PC pc;
  PetscCallAbort(comm, SNESGetKSP(snes, &ksp));
  PetscCallAbort(comm, KSPSetType(ksp, KSPPREONLY));
  PetscCallAbort(comm, KSPGetPC(ksp, &pc));
  PetscCallAbort(comm, PCSetType(pc, PCSHELL));
  PetscCallAbort(comm, PCShellSetContext(pc, this));
  PetscCallAbort(comm, PCShellSetApply(pc, shell_apply));
  PetscCallAbort(comm, PCShellSetName(pc, "implicit Runge-Kutta elimination"));
  PetscCallAbort(comm, TSSetFromOptions(ts_));  // -ts_type rosw, -ts_arkimex_type 4 and the like win
  TSType chosen;
  PetscCallAbort(comm, TSGetType(ts_, &chosen));
  if (std::string(chosen) != TSARKIMEX && std::string(chosen) != TSROSW)
    throw std::invalid_argument(std::string("-ts_type ") + chosen +
                                ": the implicit Runge-Kutta route steps with arkimex or rosw");
  family_ = chosen;
  if (family_ == TSARKIMEX) {
    TSARKIMEXType t;
    PetscCallAbort(comm, TSARKIMEXGetType(ts_, &t));
    type_ = t;
    PetscCallAbort(comm, TSARKIMEXSetFullyImplicit(ts_, PETSC_TRUE));  // no explicit part: F is all of it
  } else {
    TSRosWType t;
    PetscCallAbort(comm, TSRosWGetType(ts_, &t));
    type_ = t;
  }
  // Whatever the options did to the linear solver, the elimination is what solves.
  PetscCallAbort(comm, KSPSetType(ksp, KSPPREONLY));
}

ImplicitRungeKuttaIntegrator::~ImplicitRungeKuttaIntegrator() {
  TSDestroy(&ts_);
  KSPDestroy(&inner_);
  MatDestroy(&J_);
  MatDestroy(&shell_);
  ISDestroy(&is_u_);
  ISDestroy(&is_v_);
  for (Vec* v : {&X_, &U0_, &V0_, &A0_, &F0_, &Vp_, &Ap_, &Fp_, &w_, &r_, &d_, &V_prev_, &A_est_}) VecDestroy(v);
}

std::string ImplicitRungeKuttaIntegrator::method_name() const {
  std::string f = family_;
  std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return f + " " + type_;
}

PetscErrorCode ImplicitRungeKuttaIntegrator::split(Vec X, Vec* U, Vec* V) const {
  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(X, is_u_, U));
  PetscCall(VecGetSubVector(X, is_v_, V));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::unsplit(Vec X, Vec* U, Vec* V) const {
  PetscFunctionBeginUser;
  PetscCall(VecRestoreSubVector(X, is_u_, U));
  PetscCall(VecRestoreSubVector(X, is_v_, V));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::settings_for(EvaluationSettings* how) const {
  PetscFunctionBeginUser;
  how->param = Parametrization::rotation_vector_rates;
  how->rows = ConstraintRows::acceleration;
  how->constraint_scale = constraint_scale_;
  how->baumgarte_alpha = 0.0;  // the projection keeps g and g_dot at zero
  how->uc_per_u = 1.0;
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::zero_multipliers(Vec v) const {
  PetscScalar* x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &x));
  for (PetscInt i : multipliers_) x[i] = 0.0;
  PetscCall(VecRestoreArray(v, &x));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::copy_multipliers(Vec from, Vec to) const {
  PetscScalar* t;
  const PetscScalar* f;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(to, &t));
  PetscCall(VecGetArrayRead(from, &f));
  for (PetscInt i : multipliers_) t[i] = f[i];
  PetscCall(VecRestoreArray(to, &t));
  PetscCall(VecRestoreArrayRead(from, &f));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::ifunction(TS ts, PetscReal t, Vec X, Vec Xdot, Vec F, void* ctx) {
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  Vec U, V, Ud, Vd, F1, F2;
  PetscFunctionBeginUser;
  PetscCall(self->split(X, &U, &V));
  PetscCall(self->split(Xdot, &Ud, &Vd));
  PetscCall(self->split(F, &F1, &F2));
  EvaluationSettings how;
  PetscCall(self->settings_for(&how));
  PetscBool finite;
  PetscCall(self->sa_.residual(EvaluationPoint{U, V, Vd, nullptr, t, t}, how, F2, &finite));
  // Kinematic rows U_dot - V; on the multiplier rows the unused slots of V are held at zero.
  PetscCall(VecWAXPY(F1, -1.0, V, Ud));
  PetscCall(self->copy_multipliers(V, F1));
  PetscCall(self->unsplit(F, &F1, &F2));
  PetscCall(self->unsplit(Xdot, &Ud, &Vd));
  PetscCall(self->unsplit(X, &U, &V));
  if (!finite) {
    SNES snes;
    PetscCall(TSGetSNES(ts, &snes));
    PetscCall(SNESSetFunctionDomainError(snes));
    if (!self->sa_.evaluation_error().empty()) self->domain_error_ = self->sa_.evaluation_error();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::ijacobian(TS ts, PetscReal t, Vec X, Vec Xdot, PetscReal shift, Mat A,
                                                       Mat, void* ctx) {
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  Vec U, V, Ud, Vd;
  PetscFunctionBeginUser;
  PetscCall(self->split(X, &U, &V));
  PetscCall(self->split(Xdot, &Ud, &Vd));
  PetscCall(VecCopy(U, self->U0_));
  PetscCall(VecCopy(V, self->V0_));
  PetscCall(VecCopy(Vd, self->A0_));
  PetscCall(self->unsplit(Xdot, &Ud, &Vd));
  PetscCall(self->unsplit(X, &U, &V));
  self->t0_ = t;
  self->sigma_ = shift;
  self->f0_valid_ = false;
  EvaluationSettings how;
  PetscCall(self->settings_for(&how));
  PetscBool switched;
  PetscCall(recover_from_failed_factorisation(self->inner_, &switched));
  PetscCall(self->sa_.jacobian(EvaluationPoint{self->U0_, self->V0_, self->A0_, nullptr, t, t}, how, 1.0, shift,
                               shift * shift, self->J_));
  int outside = self->sa_.evaluation_error().empty() ? 0 : 1, anywhere = 0;
  PetscCallMPI(MPI_Allreduce(&outside, &anywhere, 1, MPI_INT, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(ts))));
  if (anywhere) {
    if (outside) self->domain_error_ = self->sa_.evaluation_error();
    SNES snes;
    PetscCall(TSGetSNES(ts, &snes));
    PetscCall(SNESSetJacobianDomainError(snes));
  }
  PetscCall(KSPSetOperators(self->inner_, self->J_, self->J_));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));  // a new state: PETSc sets the PC up again
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  self->have_jacobian_ = true;
  ++self->jacobians_;
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::rate_derivative(Vec x, Vec y) {
  PetscFunctionBeginUser;
  EvaluationSettings how;
  PetscCall(settings_for(&how));
  PetscBool finite;
  if (!f0_valid_) {
    PetscCall(sa_.residual(EvaluationPoint{U0_, V0_, A0_, nullptr, t0_, t0_}, how, F0_, &finite));
    f0_valid_ = true;
  }
  PetscReal xn, vn;
  PetscCall(VecNorm(x, NORM_INFINITY, &xn));
  PetscCall(VecNorm(V0_, NORM_INFINITY, &vn));
  if (xn == 0.0) {
    PetscCall(VecZeroEntries(y));
    PetscFunctionReturn(0);
  }
  const double eps = 1e-7 * std::max(1.0, vn) / xn;
  PetscCall(VecWAXPY(Vp_, eps, x, V0_));
  PetscCall(VecWAXPY(Ap_, eps * sigma_, x, A0_));
  PetscCall(sa_.residual(EvaluationPoint{U0_, Vp_, Ap_, nullptr, t0_, t0_}, how, Fp_, &finite));
  PetscCall(VecWAXPY(y, -1.0, F0_, Fp_));
  PetscCall(VecScale(y, 1.0 / eps));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::shell_apply(PC pc, Vec b, Vec y) {
  void* ctx;
  Vec b1, b2, y1, y2;
  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  PetscCall(self->split(b, &b1, &b2));
  PetscCall(self->split(y, &y1, &y2));
  // J [y_U; y_V] = [b1; b2] with the kinematic rows sigma y_q - y_v = b1_q and y_w = b1_w:
  // (dF/dU + sigma (dF/dV + sigma dF/dA)) y_U = b2 + (dF/dV + sigma dF/dA) b1_q, the reduced matrix.
  PetscCall(VecCopy(b1, self->w_));
  PetscCall(self->zero_multipliers(self->w_));
  PetscCall(self->rate_derivative(self->w_, self->d_));
  PetscCall(VecWAXPY(self->r_, 1.0, self->d_, b2));
  PetscCall(KSPSolve(self->inner_, self->r_, y1));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(self->inner_, &reason));
  if (reason < 0) PetscCall(PCSetFailedReason(pc, PC_FACTOR_OTHER));
  PetscCall(VecAXPBYPCZ(y2, self->sigma_, -1.0, 0.0, y1, self->w_));
  PetscCall(self->copy_multipliers(b1, y2));
  PetscCall(self->unsplit(y, &y1, &y2));
  PetscCall(self->unsplit(b, &b1, &b2));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::shell_mult(Mat A, Vec x, Vec y) {
  void* ctx;
  Vec x1, x2, y1, y2;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  PetscCall(self->split(x, &x1, &x2));
  PetscCall(self->split(y, &y1, &y2));
  // y1 = sigma x_q - x_v (x_w on the multiplier rows); y2 = J x_U + D (x_v - sigma x_q).
  PetscCall(VecAXPBYPCZ(y1, self->sigma_, -1.0, 0.0, x1, x2));
  PetscCall(VecWAXPY(self->w_, -self->sigma_, x1, x2));
  PetscCall(self->zero_multipliers(self->w_));
  PetscCall(self->copy_multipliers(x2, y1));
  PetscCall(self->rate_derivative(self->w_, self->d_));
  PetscCall(MatMult(self->J_, x1, y2));
  PetscCall(VecAXPY(y2, 1.0, self->d_));
  PetscCall(self->unsplit(y, &y1, &y2));
  PetscCall(self->unsplit(x, &x1, &x2));
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::project(Vec U, Vec V, double t) {
  PetscFunctionBeginUser;
  if (!have_jacobian_ || sa_.model().constraints.empty()) PetscFunctionReturn(0);
  // The reduced matrix's constraint rows are about sigma^2 s G T: a right-hand side -sigma^2 s g
  // on them and zero forces gives the correction with G T dq = -g that the iteration matrix
  // weighs least; its O(h) terms make the passes converge linearly, fast.
  const double tol_g = 1e-12 * std::max(1.0, sa_.characteristic_length());
  for (int pass = 0; pass < 2; ++pass) {
    const bool rates = pass == 1;
    for (int it = 0; it < 5; ++it) {
      PetscCall(sa_.constraint_values(U, V, t, rates, r_));
      PetscReal violation;
      PetscCall(VecNorm(r_, NORM_INFINITY, &violation));
      // Rates to the same relative level over a step's time scale.
      if (violation <= (rates ? tol_g * std::max(sigma_, 1.0) : tol_g)) break;
      PetscCall(VecScale(r_, -sigma_ * sigma_ * constraint_scale_));
      PetscCall(KSPSolve(inner_, r_, d_));
      PetscCall(zero_multipliers(d_));
      PetscCall(VecAXPY(rates ? V : U, 1.0, d_));
      ++projections_;
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::restart() {
  PetscFunctionBeginUser;
  PetscCall(TSRestartStep(ts_));
  if (family_ == TSARKIMEX) {
    PetscReal dt;
    PetscCall(TSGetTimeStep(ts_, &dt));
    PetscCall(TSGetTime(ts_, &restart_time_));
    PetscCall(TSSetTimeStep(ts_, kStartStepFraction * dt));
    start_step_ = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::post_step(TS ts) {
  void* ctx = nullptr;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &ctx));
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  if (!self || self->ts_ != ts) PetscFunctionReturn(0);  // PETSc's own start step (a clone)
  PetscInt failures;
  PetscCall(TSGetSNESFailures(ts, &failures));
  PetscCall(TSSetMaxSNESFailures(ts, failures + kMaxStepCuts + 1));
  PetscReal t, dt;
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetTimeStep(ts, &dt));
  if (self->start_step_) {
    // After the short start step the run goes on with the step it had (or asked for).
    self->start_step_ = false;
    ++self->start_steps_taken_;  // PETSc counted it as a step of its own
    // Back onto the step grid the restart left: the next step ends one step after it.
    dt = self->settings_.time_step - (t - self->restart_time_);
    if (self->settings_.adaptive || dt <= 0.5 * self->settings_.time_step) dt = self->settings_.time_step;
  } else if (!self->settings_.adaptive && dt < self->settings_.time_step) dt = self->settings_.time_step;
  PetscReal t_max;
  PetscCall(TSGetMaxTime(ts, &t_max));
  if (t < t_max && t + dt > t_max + 1e-9 * dt) dt = t_max - t;  // land on the end
  PetscReal dt_now;
  PetscCall(TSGetTimeStep(ts, &dt_now));
  if (dt != dt_now) PetscCall(TSSetTimeStep(ts, dt));
  if (self->report_->interrupted) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  Vec X, U, V;
  PetscCall(TSGetSolution(ts, &X));
  PetscCall(self->split(X, &U, &V));
  PetscBool changed;
  PetscCall(self->sa_.rescale_rotations(U, V, Parametrization::rotation_vector_rates, &changed));
  PetscCall(self->unsplit(X, &U, &V));
  if (changed) {
    // The method's slope at the step's start is in the old coordinates: start afresh.
    PetscCall(self->restart());
    ++self->report_->rotation_rescales;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx) {
  auto* self = static_cast<ImplicitRungeKuttaIntegrator*>(ctx);
  Vec U, V;
  PetscInt snes_its, rejects;
  PetscReal dt, t_prev;
  PetscFunctionBeginUser;
  if (self->ts_ != ts) PetscFunctionReturn(0);
  PetscCall(TSGetSNESIterations(ts, &snes_its));
  PetscCall(TSGetStepRejections(ts, &rejects));
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetPrevTime(ts, &t_prev));
  PetscCall(self->split(X, &U, &V));
  if (self->resumed_step_) {
    self->resumed_step_ = false;
    PetscCall(VecCopy(V, self->V_prev_));
    PetscCall(self->unsplit(X, &U, &V));
    PetscFunctionReturn(0);
  }
  // Here rather than in the post-step hook: PETSc restarts the method when that hook changes the
  // solution, and ARKIMEX's restart is a backward-Euler step. The projection moves the state by
  // the method's own error, so the slope it carries on with stays as valid as it was.
  PetscCall(self->project(U, V, t));
  if (step > 0 && t > t_prev) {
    PetscCall(VecWAXPY(self->A_est_, -1.0, self->V_prev_, V));
    PetscCall(VecScale(self->A_est_, 1.0 / (t - t_prev)));
  } else {
    PetscCall(VecZeroEntries(self->A_est_));
  }
  PetscCall(VecCopy(V, self->V_prev_));
  StepInfo info{static_cast<int>(step - self->start_steps_taken_), t, t - t_prev, U, V, self->A_est_, Parametrization::rotation_vector_rates,
                self->iteration_offset_ + snes_its, self->rejection_offset_ + rejects};
  info.checkpoint = self->checkpoints_.due(t, self->report_->interrupted);
  info.next_time_step = self->start_step_ ? self->settings_.time_step : dt;
  self->report_->jacobians = self->jacobians_;
  PetscErrorCode recorded = record_step(self->sa_, info, self->report_, self->observer_);
  PetscCall(self->unsplit(X, &U, &V));
  PetscCall(recorded);
  if (info.checkpoint && t < self->settings_.t_end) PetscCall(self->restart());
  PetscFunctionReturn(0);
}

PetscErrorCode ImplicitRungeKuttaIntegrator::run(Vec U, Vec V, StepObserver* observer, DynamicReport* report,
                                                 const ResumePoint* resume) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kDynamicPrefix);
  start_report(resume, report);
  observer_ = observer;
  report_ = report;
  PetscReal t_begin, t_end;
  PetscCall(TSGetTime(ts_, &t_begin));
  PetscCall(TSGetMaxTime(ts_, &t_end));
  settings_.t_end = t_end;
  checkpoints_ = CheckpointSchedule(settings_.checkpoint_interval, t_begin, t_end, true);
  if (resume) {
    PetscCall(TSSetStepNumber(ts_, resume->step));
    PetscCall(TSSetTimeStep(ts_, resume->next_time_step));
    jacobians_ = resume->jacobians;
    iteration_offset_ = resume->newton_iterations;
    rejection_offset_ = resume->rejected_steps;
    resumed_step_ = true;
  } else {
    PetscCall(consistent_first_order_rates(sa_, t_begin, U, V));
  }
  // X = [U; V]; the multiplier slots of V are zero.
  {
    Vec Ux, Vx;
    PetscCall(split(X_, &Ux, &Vx));
    PetscCall(VecCopy(U, Ux));
    PetscCall(VecCopy(V, Vx));
    PetscCall(zero_multipliers(Vx));
    PetscCall(unsplit(X_, &Ux, &Vx));
  }
  PetscCall(restart());
  const auto start = std::chrono::steady_clock::now();
  PetscCall(TSSolve(ts_, X_));
  report->wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report->jacobians = jacobians_;
  {
    Vec Ux, Vx;
    PetscCall(split(X_, &Ux, &Vx));
    PetscCall(VecCopy(Ux, U));
    PetscCall(VecCopy(Vx, V));
    PetscCall(unsplit(X_, &Ux, &Vx));
  }

  PetscCall(describe_ending(sa_, ts_, U, method_name(), domain_error_, report));
  PetscInt solves = 0;
  PetscCall(TSGetSNESIterations(ts_, &solves));
  PetscCall(describe_linear_solver(inner_, 0, solves, &report->linear_solver));
  report->linear_solver = method_name() + ", " + report->linear_solver;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
