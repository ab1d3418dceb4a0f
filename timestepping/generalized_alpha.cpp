// TSALPHA2 callbacks. PETSc evaluates the residual at the stage point (t_a, U_a, V_a, A_a) with
// U_a = U_0 + alpha_f (U_1 - U_0). Force balance stays there, but the constraint rows are
// evaluated at the reconstructed end of the step U_1 (so g(q_{n+1}) = 0 exactly, no drift), and
// the multipliers are taken from U_1 too: they are algebraic, and reading them there makes the
// stored multiplier the force that balances the stage instead of an extrapolation that would
// oscillate step to step.
#include "timestepping/generalized_alpha.hpp"

#include "timestepping/native_lu.hpp"
#include "timestepping/prefixed_options.hpp"
#include "timestepping/subdomain_lu.hpp"

#include <chrono>
#include <cstdio>
#include <limits>

namespace latticedyn {

GeneralizedAlphaIntegrator::GeneralizedAlphaIntegrator(SystemAssembler& sa, DynamicSettings settings)
    : sa_(sa), settings_(settings) {
  const PrefixedOptions options(kDynamicPrefix);  // -dyn_ts_..., -dyn_snes_... over -ts_..., -snes_...
  const MPI_Comm comm = sa_.comm();
  for (Vec* v : {&F_, &Uc_, &V_prev_, &A_est_, &A_scaled_}) PetscCallAbort(comm, sa_.create_vector(v));
  PetscCallAbort(comm, TSCreate(comm, &ts_));
  PetscCallAbort(comm, TSSetType(ts_, TSALPHA2));
  PetscCallAbort(comm, TSSetApplicationContext(ts_, this));
  PetscCallAbort(comm, TSSetI2Function(ts_, F_, i2function, this));
  // Small systems (a few rigid bodies) factor fastest dense: LAPACK's LU with partial pivoting on a
  // dense copy of the Jacobian instead of a sparse direct solver whose setup dominates there
  // (UMFPACK: about 230 k instructions per factorisation of the double pendulum's 22 unknowns).
  PetscMPIInt ranks;
  PetscCallAbort(comm, MPI_Comm_size(comm, &ranks));
  const PetscInt n = sa_.dofs().global_size();
  PetscInt dense_below = kDenseBelow;
  PetscCallAbort(comm, PetscOptionsGetInt(nullptr, nullptr, "-dyn_dense_below", &dense_below, nullptr));
  // A direct solver or preconditioner asked for by option is taken as asked.
  PetscBool solver_chosen = PETSC_FALSE, pc_chosen = PETSC_FALSE;
  PetscCallAbort(comm, PetscOptionsHasName(nullptr, nullptr, "-pc_factor_mat_solver_type", &solver_chosen));
  PetscCallAbort(comm, PetscOptionsHasName(nullptr, nullptr, "-pc_type", &pc_chosen));
  PetscBool ksp_chosen = PETSC_FALSE;
  PetscCallAbort(comm, PetscOptionsHasName(nullptr, nullptr, "-ksp_type", &ksp_chosen));
  const bool dense = ranks == 1 && n <= dense_below && !solver_chosen && !pc_chosen;
  if (dense) PetscCallAbort(comm, MatCreateSeqDense(PETSC_COMM_SELF, n, n, nullptr, &P_));
  // Where every unknown is in a block of three (translations and rotations; no multipliers), PETSc's
  // LU works in dense blocks: 3 x 3, 0.6 of the AIJ factorisation's time on a 640-bay lattice, or
  // where each node's translation and rotation lie side by side, the node's 6 x 6
  // (docs/performance.md). -dyn_block_matrix 0: AIJ all the same; -dyn_block_size 3: no larger.
  PetscBool blocks = PETSC_TRUE;
  PetscInt largest = 6;
  PetscCallAbort(comm, PetscOptionsGetBool(nullptr, nullptr, "-dyn_block_matrix", &blocks, nullptr));
  PetscCallAbort(comm, PetscOptionsGetInt(nullptr, nullptr, "-dyn_block_size", &largest, nullptr));
  const bool native = ranks == 1 && !dense && !solver_chosen && !pc_chosen;
  const bool subdomains = ranks > 1 && !solver_chosen && !pc_chosen && !ksp_chosen && sa_.model().constraints.empty();
  int block_size = 1;
  if ((native || subdomains) && blocks)
    for (int bs : kBlockSizes)
      if (bs <= largest && (bs == 1 || sa_.uniform_blocks(bs))) {
        block_size = bs;
        break;
      }
  PetscCallAbort(comm, sa_.create_matrix(&J_, block_size));
  PetscCallAbort(comm, TSSetI2Jacobian(ts_, J_, P_ ? P_ : J_, i2jacobian, this));
  PetscCallAbort(comm, TSAlpha2SetRadius(ts_, settings_.rho_infinity));
  PetscCallAbort(comm, TSSetTime(ts_, settings_.t_start));
  PetscCallAbort(comm, TSSetTimeStep(ts_, settings_.time_step));
  PetscCallAbort(comm, TSSetMaxTime(ts_, settings_.t_end));
  PetscCallAbort(comm, TSSetMaxSteps(ts_, settings_.max_steps));
  PetscCallAbort(comm, TSSetExactFinalTime(ts_, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCallAbort(comm, TSSetErrorIfStepFails(ts_, PETSC_FALSE));  // we report failures ourselves
  PetscCallAbort(comm, TSSetPostStep(ts_, post_step));
  PetscCallAbort(comm, TSMonitorSet(ts_, monitor, this, nullptr));

  TSAdapt adapt;
  PetscCallAbort(comm, TSGetAdapt(ts_, &adapt));
  PetscCallAbort(comm, TSAdaptSetType(adapt, settings_.adaptive ? TSADAPTBASIC : TSADAPTNONE));
  if (settings_.adaptive) {
    // The multipliers are algebraic: leave them out of the local error estimate.
    Vec vatol, vrtol;
    PetscCallAbort(comm, sa_.create_vector(&vatol));
    PetscCallAbort(comm, sa_.create_vector(&vrtol));
    PetscCallAbort(comm, VecSet(vatol, settings_.atol));
    PetscCallAbort(comm, VecSet(vrtol, settings_.rtol));
    for (std::size_t c = 0; c < sa_.model().constraints.size(); ++c) {
      if (sa_.dofs().multiplier_dof(static_cast<int>(c)) < sa_.dofs().owned_begin() ||
          sa_.dofs().multiplier_dof(static_cast<int>(c)) >= sa_.dofs().owned_end())
        continue;
      for (int i = 0; i < sa_.model().constraints[c].rows(); ++i) {
        const PetscInt g = sa_.dofs().multiplier_dof(static_cast<int>(c)) + i;
        PetscCallAbort(comm, VecSetValue(vatol, g, 1e300, INSERT_VALUES));
        PetscCallAbort(comm, VecSetValue(vrtol, g, 1e300, INSERT_VALUES));
      }
    }
    for (Vec v : {vatol, vrtol}) {
      PetscCallAbort(comm, VecAssemblyBegin(v));
      PetscCallAbort(comm, VecAssemblyEnd(v));
    }
    PetscCallAbort(comm, TSSetTolerances(ts_, 0.0, vatol, 0.0, vrtol));
    PetscCallAbort(comm, VecDestroy(&vatol));
    PetscCallAbort(comm, VecDestroy(&vrtol));
  }
  // A failed Newton solve retries the step at a quarter of its size (PETSc's TSAdapt), up to
  // kMaxStepCuts times in a row (post_step re-arms the count); fixed-step runs then return to
  // their step (tension-only ropes switching between slack and taut need this now and then).
  PetscCallAbort(comm, TSSetMaxSNESFailures(ts_, kMaxStepCuts + 1));

  SNES snes;
  KSP ksp;
  PetscCallAbort(comm, TSGetSNES(ts_, &snes));
  PetscCallAbort(comm, SNESSetType(snes, SNESNEWTONLS));
  SNESLineSearch ls;
  PetscCallAbort(comm, SNESGetLineSearch(snes, &ls));
  // Full Newton steps; a hydraulic circuit's valves (a relief valve's opening law, steep between
  // its cracking and full-open pressures) make Newton overshoot there: backtracking.
  PetscCallAbort(comm, SNESLineSearchSetType(ls, has_first_order_blocks(sa_.model()) ? SNESLINESEARCHBT
                                                                                    : SNESLINESEARCHBASIC));
  const double force_scale = std::max(1.0, sa_.characteristic_mass() * std::max(1.0, sa_.model().gravity.norm()));
  // rtol 1e-8: the Newton error stays below the time-discretisation error (double pendulum:
  // energy drift 3.9e-5 at 1e-8, 5.7e-5 at 1e-6, 4.0e-5 at 1e-10; docs/performance.md).
  // atol: a fraction of the model's loads (newton_tolerance, 1e-6 of its weight by default), or the
  // residual's round-off floor (stiff members) when that is larger. Starting from the predictor a
  // step meets it in two or three chord iterations; the Newton error it leaves is far below the
  // time discretisation's (the crane's load path moves by 1 um, its rope forces by 2e-5 %, where
  // the step of 0.05 s itself makes 1.5 mm: docs/performance.md). rtol only matters for a cold
  // start (after a restart), where it asks for about the same of a residual that starts at the
  // step's whole inertia.
  PetscCallAbort(comm, SNESSetTolerances(snes, std::max(settings_.newton_tolerance * sa_.characteristic_load(),
                                                        sa_.residual_floor()),
                                         1e-8, 1e-14, 25, 100000));
  // Round-off floor: the residual of stiff members cannot fall below machine precision times their
  // forces; the typical stiffness over a millimetre measures it where loads and weights are small.
  PetscCallAbort(comm, PetscInfo(nullptr, "Newton atol %g (residual floor %g, load %g)\n",
                                 std::max(settings_.newton_tolerance * sa_.characteristic_load(), sa_.residual_floor()),
                                 sa_.residual_floor(), sa_.characteristic_load()));
  PetscCallAbort(comm, set_roundoff_convergence_test(snes, std::max(force_scale, 1e-3 * sa_.characteristic_stiffness()),
                                                           sa_.residual_floor()));
  PetscCallAbort(comm, SNESGetKSP(snes, &ksp));
  ksp_ = ksp;
  PetscCallAbort(comm, set_direct_solver_defaults(ksp));
  if (P_) {
    PC pc;
    PetscCallAbort(comm, KSPGetPC(ksp, &pc));
    PetscCallAbort(comm, PCFactorSetMatSolverType(pc, MATSOLVERPETSC));
  } else if (native) {
    // The iteration matrix M a_m/(a_f beta h^2) + C gamma/(beta h) + K has its mass on the
    // diagonal, and with every multiplier ordered after its constraint's unknowns no pivot is zero:
    // PETSc's own LU then factors lattices and cranes several times faster than UMFPACK, whose
    // frontal machinery costs more than it saves on small fronts (640-bay lattice: 14 against
    // 42 ms; the full crane: docs/performance.md). A failed factorisation switches to UMFPACK.
    PetscCallAbort(comm, use_native_lu(ksp));
  } else if (subdomains) {
    // Without multipliers every subdomain of the iteration matrix is nonsingular and factors
    // without pivoting: GMRES on additive Schwarz with PETSc's LU per rank takes half of MUMPS's
    // time and beats one rank (lattice-bays, docs/performance.md). -pc_type lu: MUMPS again.
    PetscCallAbort(comm, use_subdomain_lu(ksp));
  }
  if (settings_.jacobian_reuse > 1) PetscCallAbort(comm, SNESMonitorSet(snes, watch_contraction, this, nullptr));
  PetscCallAbort(comm, PetscOptionsGetBool(nullptr, nullptr, "-dyn_predictor", &predictor_, nullptr));
  if (predictor_) PetscCallAbort(comm, SNESSetComputeInitialGuess(snes, predict, this));
  PetscCallAbort(comm, TSSetFromOptions(ts_));  // -ts_, -snes_, -ksp_, -pc_ options win
}

GeneralizedAlphaIntegrator::~GeneralizedAlphaIntegrator() {
  TSDestroy(&ts_);
  MatDestroy(&J_);
  MatDestroy(&P_);
  for (Vec* v : {&F_, &Uc_, &V_prev_, &A_est_, &A_scaled_}) VecDestroy(v);
}

PetscErrorCode GeneralizedAlphaIntegrator::stage(PetscReal ta, Vec Ua, Vec Va, Vec Aa, EvaluationPoint* at,
                                                 EvaluationSettings* how, double* inertia_factor) {
  PetscReal am, af, gamma, beta, t0, dt;
  Vec U0;
  PetscFunctionBeginUser;
  PetscCall(TSAlpha2GetParams(ts_, &am, &af, &gamma, &beta));
  *inertia_factor = 1.0;
#if PETSC_VERSION_LT(3, 22, 0)
  // PETSc before 3.22 starts TSALPHA2 with two backward-Euler half steps and estimates the initial
  // acceleration with a backward difference divided by half the step instead of the whole step
  // (fixed upstream in commit 070f04f, 2024), which doubles it. Doubling the inertia during those
  // start-up steps (recognised by their parameters 1, 1, 1, 1/2, which no spectral radius gives)
  // halves the accelerations they produce, so the estimate comes out right.
  // See docs/decisions/0001-tsalpha2-startup.md.
  if (am == 1.0 && af == 1.0 && gamma == 1.0 && beta == 0.5) {
    *inertia_factor = 2.0;
    PetscCall(VecAXPBY(A_scaled_, 2.0, 0.0, Aa));
    Aa = A_scaled_;
  }
#endif
  PetscCall(TSGetTime(ts_, &t0));
  PetscCall(TSGetTimeStep(ts_, &dt));
  PetscCall(TSGetSolution(ts_, &U0));  // still U_n while the stage is solved
  // U_1 = U_0 + (U_a - U_0) / alpha_f; with alpha_f = 1 (PETSc's start-up Euler steps) U_1 = U_a.
  PetscCall(VecWAXPY(Uc_, -1.0, U0, Ua));
  PetscCall(VecAYPX(Uc_, 1.0 / af, U0));
  *at = EvaluationPoint{Ua, Va, Aa, Uc_, ta, t0 + (ta - t0) / af};
  how->param = Parametrization::rotation_vector_rates;
  how->rows = ConstraintRows::position;
  how->uc_per_u = 1.0 / af;
  // Constraint rows weigh like the mass block of the Jacobian, m / (beta h^2) (scaled by
  // alpha_m / alpha_f as PETSc's shift), so the saddle point stays well conditioned as h -> 0.
  how->constraint_scale = sa_.characteristic_mass() * am / (af * beta * dt * dt);
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::i2function(TS ts, PetscReal t, Vec U, Vec V, Vec A, Vec F, void* ctx) {
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  EvaluationPoint at;
  EvaluationSettings how;
  PetscBool finite;
  PetscFunctionBeginUser;
  double inertia;
  PetscCall(self->stage(t, U, V, A, &at, &how, &inertia));
  PetscCall(self->sa_.residual(at, how, F, &finite));
  if (!finite) {
    SNES snes;
    PetscCall(TSGetSNES(ts, &snes));
    PetscCall(SNESSetFunctionDomainError(snes));
    if (!self->sa_.evaluation_error().empty()) self->domain_error_ = self->sa_.evaluation_error();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::i2jacobian(TS ts, PetscReal t, Vec U, Vec V, Vec A, PetscReal shift_v,
                                                      PetscReal shift_a, Mat J, Mat, void* ctx) {
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  EvaluationPoint at;
  EvaluationSettings how;
  PetscFunctionBeginUser;
  double inertia;
  PetscCall(self->stage(t, U, V, A, &at, &how, &inertia));
  PetscBool switched;
  PetscCall(recover_from_failed_factorisation(self->ksp_, &switched));
  if (switched) self->reuse_count_ = self->settings_.jacobian_reuse;  // a fresh matrix for the new factorisation
  // Jacobian reuse (a chord Newton method): leaving J untouched keeps its state, so PETSc keeps
  // the factorisation too. Only while the shifts, i.e. the step size, stay the same.
  const bool same_shifts = shift_v == self->reuse_shift_v_ && inertia * shift_a == self->reuse_shift_a_;
  if (self->settings_.jacobian_reuse > 1 && same_shifts && self->reuse_count_ < self->settings_.jacobian_reuse) {
    ++self->reuse_count_;
    PetscFunctionReturn(0);
  }
  PetscCall(self->sa_.jacobian(at, how, 1.0, shift_v, inertia * shift_a, J));
  // An element outside its domain (on any rank): the Newton solve fails and the step is cut.
  int outside = self->sa_.evaluation_error().empty() ? 0 : 1, anywhere = 0;
  PetscCallMPI(MPI_Allreduce(&outside, &anywhere, 1, MPI_INT, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(ts))));
  if (anywhere) {
    if (outside) self->domain_error_ = self->sa_.evaluation_error();
    SNES snes;
    PetscCall(TSGetSNES(ts, &snes));
    PetscCall(SNESSetJacobianDomainError(snes));
    self->reuse_count_ = self->settings_.jacobian_reuse;  // never reuse this matrix
  }
  if (self->P_) PetscCall(MatCopy(J, self->P_, DIFFERENT_NONZERO_PATTERN));
  self->reuse_shift_v_ = shift_v;
  self->reuse_shift_a_ = inertia * shift_a;
  self->reuse_count_ = 1;
  ++self->jacobians_;
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::watch_contraction(SNES, PetscInt it, PetscReal fnorm, void* ctx) {
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  PetscFunctionBeginUser;
  // Modified Newton with an old Jacobian contracts linearly; once a step reduces the residual by
  // less than half, the next iteration takes a fresh Jacobian (and keeps the step size); not at the
  // residual's round-off floor, where no Jacobian contracts it further.
  if (it > 0 && fnorm > kChordContraction * self->last_fnorm_ && fnorm > self->sa_.residual_floor())
    self->reuse_count_ = self->settings_.jacobian_reuse;
  self->last_fnorm_ = fnorm;
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::predict(SNES, Vec U1, void* ctx) {
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  PetscReal am, af, gamma, beta, dt;
  Vec U0, V0;
  PetscFunctionBeginUser;
  // TSALPHA2 starts Newton from U_1 = U_0, where the residual is the whole inertia of the step;
  // the Taylor guess U_0 + h V_0 + h^2/2 A_0 (A_0 estimated from the last step's velocity change)
  // starts it near the solution. Not in PETSc's start-up Euler steps (their U_0 is internal).
  PetscCall(TSAlpha2GetParams(self->ts_, &am, &af, &gamma, &beta));
  if (am == 1.0 && af == 1.0 && gamma == 1.0 && beta == 0.5) PetscFunctionReturn(0);
  PetscCall(TSGetTimeStep(self->ts_, &dt));
  PetscCall(TS2GetSolution(self->ts_, &U0, &V0));
  PetscCall(VecWAXPY(U1, dt, V0, U0));
  PetscCall(VecAXPY(U1, 0.5 * dt * dt, self->A_est_));
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::post_step(TS ts) {
  void* ctx;
  Vec U, V;
  PetscBool changed;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &ctx));
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  PetscCall(TS2GetSolution(ts, &U, &V));
  PetscInt failures;
  PetscCall(TSGetSNESFailures(ts, &failures));
  PetscCall(TSSetMaxSNESFailures(ts, failures + kMaxStepCuts + 1));
  if (!self->settings_.adaptive) {
    PetscReal dt;
    PetscCall(TSGetTimeStep(ts, &dt));
    if (dt < self->settings_.time_step) PetscCall(TSSetTimeStep(ts, self->settings_.time_step));
  }
  PetscCall(self->land_on_end());
  // A stop asked for at the last monitor: here, after TSStep (which resets the reason) and before
  // TSSolve looks at it, so the run ends after this step.
  if (self->report_->interrupted) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  PetscCall(self->sa_.rescale_rotations(U, V, Parametrization::rotation_vector_rates, &changed));
  if (changed) {
    // TSALPHA2 keeps the acceleration internally; a restart recomputes it for the new coordinates.
    PetscCall(TSRestartStep(ts));
    self->reuse_count_ = self->settings_.jacobian_reuse;  // the old Jacobian is in the old coordinates
    ++self->report_->rotation_rescales;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::land_on_end() {
  PetscReal t, dt, t_max;
  PetscFunctionBeginUser;
  PetscCall(TSGetTime(ts_, &t));
  PetscCall(TSGetTimeStep(ts_, &dt));
  PetscCall(TSGetMaxTime(ts_, &t_max));
  // TSALPHA2 without adaptivity steps past the end (PETSc's exact-final-time option shortens only
  // through an adaptor); a step that would overshoot by more than round-off is cut to land on it.
  // Steps summed to the end can fall short of it by round-off: that is the end, not a step of
  // 1e-16 s (whose Newton system, scaled by 1/h^2, cannot be solved).
  if (t < t_max && t_max - t <= 1e-9 * dt) PetscCall(TSSetTime(ts_, t_max));
  else if (t < t_max && t + dt > t_max + 1e-9 * dt) PetscCall(TSSetTimeStep(ts_, t_max - t));
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::monitor(TS ts, PetscInt step, PetscReal t, Vec, void* ctx) {
  auto* self = static_cast<GeneralizedAlphaIntegrator*>(ctx);
  Vec U, V;
  PetscInt snes_its, rejects;
  PetscReal dt, t_prev;
  PetscFunctionBeginUser;
  PetscCall(TS2GetSolution(ts, &U, &V));
  PetscCall(TSGetSNESIterations(ts, &snes_its));
  PetscCall(TSGetStepRejections(ts, &rejects));
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetPrevTime(ts, &t_prev));
  if (self->resumed_step_) {
    // The checkpoint's state, recorded by the run that wrote it; its acceleration estimate came
    // with it.
    self->resumed_step_ = false;
    PetscCall(VecCopy(V, self->V_prev_));
    PetscFunctionReturn(0);
  }
  // TSALPHA2 keeps its acceleration private: output estimates it from the last velocity change.
  if (step > 0 && t > t_prev) {
    PetscCall(VecWAXPY(self->A_est_, -1.0, self->V_prev_, V));
    PetscCall(VecScale(self->A_est_, 1.0 / (t - t_prev)));
  } else {
    PetscCall(VecZeroEntries(self->A_est_));
  }
  PetscCall(VecCopy(V, self->V_prev_));

  StepInfo info{static_cast<int>(step), t, t - t_prev, U, V, self->A_est_, Parametrization::rotation_vector_rates,
                self->iteration_offset_ + snes_its, self->rejection_offset_ + rejects};
  info.checkpoint = self->checkpoints_.due(t, self->report_->interrupted);
  info.next_time_step = dt;
  self->report_->jacobians = self->jacobians_;
  PetscCall(record_step(self->sa_, info, self->report_, self->observer_));
  if (info.checkpoint) {
    // TSALPHA2's acceleration is private and cannot be restored: from a checkpoint on, the
    // integrator starts afresh (its start-up steps, a fresh Jacobian), in this run as in one
    // continued from it, so that both go on identically.
    PetscCall(TSRestartStep(ts));
    self->reuse_count_ = self->settings_.jacobian_reuse;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::run(Vec U, Vec V, StepObserver* observer, DynamicReport* report,
                                               const ResumePoint* resume, Vec acceleration) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kDynamicPrefix);  // also for what is read while solving (-ts_view)
  start_report(resume, report);
  observer_ = observer;
  report_ = report;
  PetscReal t_begin, t_end;  // -ts_max_time and the like may have changed them
  PetscCall(TSGetTime(ts_, &t_begin));
  PetscCall(TSGetMaxTime(ts_, &t_end));
  checkpoints_ = CheckpointSchedule(settings_.checkpoint_interval, t_begin, t_end, !open_end_);
  if (resume) {
    PetscCall(TSSetStepNumber(ts_, resume->step));
    PetscCall(TSSetTimeStep(ts_, resume->next_time_step));
    if (acceleration) PetscCall(VecCopy(acceleration, A_est_));
    else PetscCall(VecZeroEntries(A_est_));
    jacobians_ = resume->jacobians;
    iteration_offset_ = resume->newton_iterations;
    rejection_offset_ = resume->rejected_steps;
    resumed_step_ = true;
  } else {
    PetscCall(consistent_first_order_rates(sa_, t_begin, U, V));
  }
  PetscCall(solve(U, V, report));
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::continue_to(double t_end, Vec U, Vec V, StepObserver* observer,
                                                       DynamicReport* report) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kDynamicPrefix);
  observer_ = observer;
  report_ = report;
  report->completed = false;
  PetscReal t_now;
  PetscCall(TSGetTime(ts_, &t_now));
  PetscCall(TSSetMaxTime(ts_, t_end));
  checkpoints_ = CheckpointSchedule(settings_.checkpoint_interval, t_now, t_end, !open_end_);
  // TSSolve's first monitor call shows the state the last call ended with, which was recorded.
  resumed_step_ = true;
  PetscCall(solve(U, V, report));
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralizedAlphaIntegrator::solve(Vec U, Vec V, DynamicReport* report) {
  PetscFunctionBeginUser;
  const auto start = std::chrono::steady_clock::now();
  PetscCall(TS2SetSolution(ts_, U, V));
  PetscCall(land_on_end());
  PetscCall(TSSolve(ts_, U));
  Vec Uend, Vend;
  PetscCall(TS2GetSolution(ts_, &Uend, &Vend));
  PetscCall(VecCopy(Uend, U));
  PetscCall(VecCopy(Vend, V));
  report->wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report->jacobians = jacobians_;

  PetscCall(describe_ending(sa_, ts_, U, "", domain_error_, report));
  PetscInt krylov = 0, solves = 0;
  PetscCall(TSGetKSPIterations(ts_, &krylov));
  PetscCall(TSGetSNESIterations(ts_, &solves));
  PetscCall(describe_linear_solver(ksp_, krylov, solves, &report->linear_solver));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
