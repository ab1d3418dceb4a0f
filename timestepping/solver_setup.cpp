// Shared solver setup: direct-solver defaults and failure descriptions.
#include "timestepping/solver_setup.hpp"

#include <algorithm>
#include <cstdio>

namespace latticedyn {

PetscErrorCode set_direct_solver_defaults(KSP ksp) {
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  // Serially UMFPACK: MUMPS costs ~0.1 ms per factorisation in setup alone, which dominates small
  // models (measured in docs/performance.md). In parallel MUMPS, the distributed direct solver.
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)ksp), &size));
  PetscCall(PCFactorSetMatSolverType(pc, size > 1 ? MATSOLVERMUMPS : MATSOLVERUMFPACK));
  // MUMPS on a saddle-point matrix: the multipliers' rows and the frames held only by constraints
  // (rigid end sections) have no diagonal, their pivots are delayed, and the factors outgrow the
  // space MUMPS estimated (INFOG(1) = -9 on the full main boom and the full crane on 2 ranks).
  // 100 % more working space than the estimate (ICNTL(14), MUMPS's default 20-35 %) covers every
  // model here; a factorisation that runs out anyway doubles it (recover_from_failed_factorisation).
  PetscBool set;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-mat_mumps_icntl_14", &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, "-mat_mumps_icntl_14", "100"));
  PetscFunctionReturn(0);
}

namespace {

struct RoundoffTest {
  PetscReal reference = 0.0, floor = 0.0, f0 = 0.0, previous = 0.0;
};

PetscErrorCode roundoff_test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                             SNESConvergedReason* reason, void* ctx) {
  auto* t = static_cast<RoundoffTest*>(ctx);
  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (it == 0) {
    t->f0 = t->previous = fnorm;
    PetscFunctionReturn(0);
  }
  if (*reason == SNES_CONVERGED_ITERATING && fnorm <= t->floor) *reason = SNES_CONVERGED_FNORM_ABS;
  if (*reason == SNES_CONVERGED_ITERATING && fnorm <= 1e-6 * std::max(t->f0, t->reference) && fnorm > 0.5 * t->previous)
    *reason = SNES_CONVERGED_FNORM_RELATIVE;
  t->previous = fnorm;
  PetscFunctionReturn(0);
}

PetscErrorCode destroy_roundoff_test(void* ctx) {
  delete static_cast<RoundoffTest*>(ctx);
  return 0;
}

}  // namespace

PetscErrorCode set_roundoff_convergence_test(SNES snes, double reference_force, double floor) {
  PetscFunctionBeginUser;
  auto* test = new RoundoffTest;
  test->reference = reference_force;
  test->floor = floor;
  PetscCall(SNESSetConvergenceTest(snes, roundoff_test, test, destroy_roundoff_test));
  PetscFunctionReturn(0);
}

PetscErrorCode record_step(SystemAssembler& sa, const StepInfo& info, DynamicReport* r, StepObserver* observer) {
  double violation;
  int where;
  PetscFunctionBeginUser;
  PetscCall(sa.max_constraint_violation(info.U, info.time, &violation, &where));
  if (violation > r->max_violation || r->violation_constraint < 0) {
    r->max_violation = violation;
    r->violation_constraint = where;
  }
  r->steps = info.step;
  r->time_reached = info.time;
  r->newton_iterations = info.newton_iterations;
  r->rejected_steps = info.rejected_steps;
  if (observer) PetscCall(observer->on_step(info));
  PetscFunctionReturn(0);
}

std::string describe_violation(const Model& model, double value, int constraint) {
  if (constraint < 0) return "no constraints";
  const Constraint& c = model.constraints[constraint];
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", value);
  return "constraint '" + c.name + "' (" + to_string(c.type) + "), |g| = " + buf;
}

}  // namespace latticedyn
