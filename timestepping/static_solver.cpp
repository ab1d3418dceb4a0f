// Static equilibrium by Newton's method on the assembled system, with gravity and nodal loads
// ramped in increments and a failed increment halved, as a path-following safeguard for large
// deflections.
#include "timestepping/static_solver.hpp"

#include "timestepping/native_lu.hpp"
#include "timestepping/prefixed_options.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>

namespace latticedyn {

StaticSolver::StaticSolver(SystemAssembler& sa, StaticSettings settings) : sa_(sa), settings_(settings) {
  const PrefixedOptions options(kStaticPrefix);  // -static_snes_... over -snes_...
  // A warm start begins next to an equilibrium where the neutral modes (a load free to turn on
  // its hook) are already known to need the regularized tangent.
  regularized_ = settings_.warm_start && settings_.regularization > 0;
  PetscCallAbort(sa_.comm(), sa_.create_matrix(&J_));
  PetscCallAbort(sa_.comm(), sa_.create_vector(&F_));
  PetscCallAbort(sa_.comm(), SNESCreate(sa_.comm(), &snes_));
  PetscCallAbort(sa_.comm(), SNESSetFunction(snes_, F_, form_function, this));
  PetscCallAbort(sa_.comm(), SNESSetJacobian(snes_, J_, J_, form_jacobian, this));
  PetscCallAbort(sa_.comm(), SNESSetType(snes_, SNESNEWTONLS));
  PetscCallAbort(sa_.comm(), SNESMonitorSet(snes_, monitor, this, nullptr));
  PetscCallAbort(sa_.comm(), SNESSetTolerances(snes_, settings_.atol, settings_.rtol, 0.0, settings_.max_iterations, 100000));
  // Round-off reference: the force of the typical stiffness over a millimetre. A model that starts
  // in equilibrium (no loads) has nothing else to measure its residual's floor against.
  PetscCallAbort(sa_.comm(), set_roundoff_convergence_test(snes_, 1e-3 * sa_.characteristic_stiffness()));
  history_.resize(static_cast<std::size_t>(settings_.max_iterations) + 1);
  PetscCallAbort(sa_.comm(), SNESSetConvergenceHistory(snes_, history_.data(), nullptr,
                                                       static_cast<PetscInt>(history_.size()), PETSC_TRUE));
  // Full Newton steps, with the load increment halved when they fail: a backtracking line search
  // on the 2-norm of a residual that mixes forces, moments and stiff axial terms crawls in tiny
  // steps through the (physical) axial-bending coupling of beams under large rotation, where the
  // full step converges in a few iterations (measured on the end-moment study, docs/elements.md).
  SNESLineSearch line_search;
  PetscCallAbort(sa_.comm(), SNESGetLineSearch(snes_, &line_search));
  PetscCallAbort(sa_.comm(), SNESLineSearchSetType(line_search, SNESLINESEARCHBASIC));
  KSP ksp;
  PetscCallAbort(sa_.comm(), SNESGetKSP(snes_, &ksp));
  PetscCallAbort(sa_.comm(), set_direct_solver_defaults(ksp));
  PetscCallAbort(sa_.comm(), SNESSetFromOptions(snes_));  // every -snes_/-ksp_/-pc_ option wins
}

StaticSolver::~StaticSolver() {
  SNESDestroy(&snes_);
  MatDestroy(&J_);
  VecDestroy(&F_);
}

EvaluationSettings StaticSolver::evaluation() const {
  EvaluationSettings how;
  how.param = Parametrization::rotation_vector_rates;
  how.load_scale = load_factor_;
  // Constraint rows in force units: a violation weighs like the force that would close it.
  how.constraint_scale = sa_.characteristic_stiffness();
  return how;
}

PetscErrorCode StaticSolver::form_function(SNES snes, Vec U, Vec F, void* ctx) {
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscBool finite = PETSC_TRUE;
  PetscFunctionBeginUser;
  const double t = self->settings_.time;
  PetscCall(self->sa_.residual(EvaluationPoint{U, nullptr, nullptr, nullptr, t, t}, self->evaluation(), F, &finite));
  if (!finite) {
    PetscCall(SNESSetFunctionDomainError(snes));
    if (!self->sa_.evaluation_error().empty()) self->evaluation_error_ = self->sa_.evaluation_error();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolver::form_jacobian(SNES snes, Vec U, Mat J, Mat, void* ctx) {
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscFunctionBeginUser;
  const double t = self->settings_.time;
  // Pseudo-transient continuation with switched evolution relaxation (Kelley & Keyes 1998): the
  // regularization shrinks with the residual, mu_k = mu_0 |F_k| / |F_0|, so it steers the first
  // iterations through free or soft motions and leaves full Newton steps near the solution. A
  // constant mu scaled by the stiffest members would crawl along soft modes (ropes, ties).
  double mu = 0.0;
  if (self->regularized_) {
    PetscInt it;
    PetscReal fnorm;
    PetscCall(SNESGetIterationNumber(snes, &it));
    PetscCall(SNESGetFunctionNorm(snes, &fnorm));
    if (it == 0 || self->initial_residual_ <= 0.0) self->initial_residual_ = fnorm;
    const double ratio = self->initial_residual_ > 0.0 ? std::min(1.0, fnorm / self->initial_residual_) : 1.0;
    mu = ratio * self->settings_.regularization * self->sa_.characteristic_stiffness() / self->sa_.characteristic_mass();
    // Below round-off against the stiffness, mu M no longer changes K + mu M: drop it, and with it
    // the mass matrix (the elements then evaluate their tangents at rest, K alone).
    if (mu * self->sa_.characteristic_mass() <= std::numeric_limits<double>::epsilon() * self->sa_.characteristic_stiffness())
      mu = 0.0;
  }
  KSP ksp;
  PetscBool reset;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(recover_from_failed_factorisation(ksp, &reset));  // a failed one must not poison the next
  PetscCall(self->sa_.jacobian(EvaluationPoint{U, nullptr, nullptr, nullptr, t, t}, self->evaluation(), 1.0, 0.0, mu, J));
  // A failed evaluation (on any rank) leaves the matrix unusable: the solve fails and the load
  // step is cut.
  int failed = self->sa_.evaluation_error().empty() ? 0 : 1, anywhere = 0;
  PetscCallMPI(MPI_Allreduce(&failed, &anywhere, 1, MPI_INT, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(snes))));
  if (anywhere) {
    if (failed) self->evaluation_error_ = self->sa_.evaluation_error();
    PetscCall(SNESSetJacobianDomainError(snes));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolver::monitor(SNES, PetscInt it, PetscReal fnorm, void* ctx) {
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscFunctionBeginUser;
  if (it == 0 || !self->observer_) PetscFunctionReturn(0);
  StaticIterationInfo info = self->progress_;
  info.load_factor = self->load_factor_;
  info.newton_iterations += static_cast<int>(it);
  info.residual = fnorm;
  self->observer_->on_static_iteration(info);
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolver::solve(Vec U, StaticReport* report, StepObserver* observer) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kStaticPrefix);  // also for what is read while solving (-snes_view)
  observer_ = observer;
  progress_ = StaticIterationInfo{};
  const auto started = std::chrono::steady_clock::now();
  StaticReport r;
  Vec last;
  PetscCall(VecDuplicate(U, &last));
  PetscCall(VecCopy(U, last));

  const int steps = settings_.warm_start ? 1 : std::max(1, settings_.load_steps);
  double reached = 0.0;
  double increment = 1.0 / steps;
  // A warm start has nothing to cut back to: the load stays full, only the tangent may change.
  const int max_cuts = settings_.warm_start ? 0 : settings_.max_cuts;
  int cuts = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  while (reached < 1.0 - 1e-12) {
    load_factor_ = std::min(1.0, reached + increment);
    evaluation_error_.clear();
    progress_.reached = reached;
    progress_.increments = r.increments;
    progress_.newton_iterations = r.newton_iterations;
    PetscCall(SNESSolve(snes_, nullptr, U));
    PetscInt its;
    PetscCall(SNESGetIterationNumber(snes_, &its));
    PetscCall(SNESGetConvergedReason(snes_, &reason));
    PetscCall(SNESGetFunctionNorm(snes_, &r.residual_norm));
    r.newton_iterations += static_cast<int>(its);
    if (reason > 0) {
      reached = load_factor_;
      ++r.increments;
      PetscBool changed;
      PetscCall(sa_.rescale_rotations(U, nullptr, Parametrization::velocity_variables, &changed));  // rates are zero
      PetscCall(VecCopy(U, last));
      continue;
    }
    if (!regularized_ && settings_.regularization > 0) {
      regularized_ = true;  // retry the increment with the regularized tangent, then keep it
      PetscCall(VecCopy(last, U));
      continue;
    }
    if (++cuts > max_cuts) break;
    increment *= 0.5;  // back to the last equilibrium with a smaller step
    PetscCall(VecCopy(last, U));
  }
  r.converged = reached >= 1.0 - 1e-12;
  r.load_factor = reached;
  PetscCall(sa_.max_constraint_violation(r.converged ? U : last, settings_.time, &r.max_violation, &r.violation_constraint));

  char buf[512];
  if (r.converged) {
    std::snprintf(buf, sizeof buf,
                  "static equilibrium found: %d load increment(s), %d Newton iterations%s, residual %.3g; largest violation: %s",
                  r.increments, r.newton_iterations, regularized_ ? " (regularized tangent)" : "", r.residual_norm,
                  describe_violation(sa_.model(), r.max_violation, r.violation_constraint).c_str());
  } else {
    const char* why = SNESConvergedReasons[reason];
    const bool direction_failed = reason == SNES_DIVERGED_LINEAR_SOLVE || reason == SNES_DIVERGED_LINE_SEARCH;
    // Did the last increment's iterations get anywhere?
    const PetscReal* hist = nullptr;
    PetscInt n = 0;
    PetscCall(SNESGetConvergenceHistory(snes_, const_cast<PetscReal**>(&hist), nullptr, &n));
    bool stalled = false;
    if (hist && n > 2) {
      const PetscReal best = *std::min_element(hist + 1, hist + n);
      stalled = !(best < 1e-3 * hist[0]);
    }
    const char* hint = direction_failed
                           ? " (no usable Newton direction: is the tangent singular? A body free to move without "
                             "stiffness, e.g. unsupported, has no equilibrium; -ksp_converged_reason shows zero pivots)"
                       : stalled ? " (the residual does not fall: there is no equilibrium near this state; a body free "
                                   "to move without support or stiffness is singular, or the load passes a limit point; "
                                   "-snes_monitor shows the iterations)"
                                 : "";
    std::snprintf(buf, sizeof buf,
                  "static equilibrium failed at load factor %.4g (last equilibrium at %.4g): SNES %s%s, Newton residual "
                  "%.3g after %d iterations; largest violation: %s",
                  load_factor_, reached, why, hint, r.residual_norm, r.newton_iterations,
                  describe_violation(sa_.model(), r.max_violation, r.violation_constraint).c_str());
  }
  r.message = buf;
  if (!r.converged && !evaluation_error_.empty()) r.message += "; " + evaluation_error_;
  if (!r.converged) PetscCall(VecCopy(last, U));
  PetscCall(VecDestroy(&last));
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  *report = r;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
