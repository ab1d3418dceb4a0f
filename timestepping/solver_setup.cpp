// Shared solver setup: direct-solver defaults and failure descriptions.
#include "timestepping/solver_setup.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

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
  // Under the KSP's own prefix: the factor reads its options with it (SLEPc's shift-and-invert
  // KSP has "st_", so a plain -mat_mumps_icntl_14 never reached the modal and buckling analyses,
  // which ran out of space on the full main boom on 2 ranks).
  const char* prefix = nullptr;
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  std::string name = "-";
  name.append(prefix ? prefix : "").append("mat_mumps_icntl_14");
  PetscBool set;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, name.c_str(), "100"));
  PetscFunctionReturn(0);
}

std::vector<PetscInt> owned_multiplier_rows(const SystemAssembler& sa) {
  std::vector<PetscInt> rows;
  const int lo = sa.dofs().owned_begin(), hi = sa.dofs().owned_end();
  for (std::size_t c = 0; c < sa.model().constraints.size(); ++c) {
    const int g = sa.dofs().multiplier_dof(static_cast<int>(c));
    if (g < lo || g >= hi) continue;  // a constraint's rows are all on the rank of its first
    for (int i = 0; i < sa.model().constraints[c].rows(); ++i) rows.push_back(g - lo + i);
  }
  return rows;
}

PetscErrorCode fill_by_row_kind(const SystemAssembler& sa, double coordinate, double multiplier, Vec v) {
  PetscFunctionBeginUser;
  PetscCall(VecSet(v, coordinate));
  for (std::size_t c = 0; c < sa.model().constraints.size(); ++c) {
    const PetscInt first = sa.dofs().multiplier_dof(static_cast<int>(c));
    for (int i = 0; i < sa.model().constraints[c].rows(); ++i)
      if (first + i >= sa.dofs().owned_begin() && first + i < sa.dofs().owned_end())
        PetscCall(VecSetValue(v, first + i, multiplier, INSERT_VALUES));
  }
  PetscCall(VecAssemblyBegin(v));
  PetscCall(VecAssemblyEnd(v));
  PetscFunctionReturn(0);
}

namespace {

// "PETSc LU", "MUMPS LU", "dense LU (LAPACK)", or the preconditioner's name.
PetscErrorCode describe_preconditioner(PC pc, std::string* text) {
  PCType type;
  PetscBool factor;
  PetscFunctionBeginUser;
  PetscCall(PCGetType(pc, &type));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  if (!factor) {
    *text = type ? type : "none";
    PetscFunctionReturn(0);
  }
  const std::string kind = std::string_view(type) == PCLU ? "LU" : "Cholesky";
  Mat P = nullptr;
  PetscCall(PCGetOperators(pc, nullptr, &P));
  PetscBool dense = PETSC_FALSE;
  if (P) PetscCall(PetscObjectTypeCompareAny((PetscObject)P, &dense, MATSEQDENSE, MATMPIDENSE, ""));
  if (dense) {
    *text = "dense " + kind + " (LAPACK)";
    PetscFunctionReturn(0);
  }
  MatSolverType package = nullptr;
  PetscCall(PCFactorGetMatSolverType(pc, &package));
  const std::string name = package ? package : MATSOLVERPETSC;
  if (name == MATSOLVERPETSC) {
    PetscBool baij = PETSC_FALSE;
    PetscInt bs = 1;
    if (P) PetscCall(PetscObjectTypeCompareAny((PetscObject)P, &baij, MATSEQBAIJ, MATMPIBAIJ, ""));
    if (baij) PetscCall(MatGetBlockSize(P, &bs));
    *text = "PETSc " + kind + (baij ? " in " + std::to_string(bs) + " x " + std::to_string(bs) + " blocks" : "");
  } else {
    std::string upper = name;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    *text = upper + " " + kind;
  }
  PetscFunctionReturn(0);
}

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

PetscErrorCode describe_linear_solver(KSP ksp, long krylov_iterations, long solves, std::string* text) {
  PC pc;
  KSPType ktype;
  PetscBool preonly, asm_pc, bjacobi;
  PetscFunctionBeginUser;
  PetscCall(KSPGetType(ksp, &ktype));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPPREONLY, &preonly));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCASM, &asm_pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCBJACOBI, &bjacobi));
  std::string pc_text;
  if (asm_pc || bjacobi) {
    KSP* sub = nullptr;
    PetscInt nsub = 0;
    std::string local = "?";
    if (solves > 0) {  // the subdomain solvers exist once a solve has set the preconditioner up
      if (asm_pc) PetscCall(PCASMGetSubKSP(pc, &nsub, nullptr, &sub));
      else PetscCall(PCBJacobiGetSubKSP(pc, &nsub, nullptr, &sub));
    }
    if (nsub > 0) {
      PC subpc;
      PetscCall(KSPGetPC(sub[0], &subpc));
      PetscCall(describe_preconditioner(subpc, &local));
    }
    pc_text = asm_pc ? "additive Schwarz, " + local + " per subdomain" : "block Jacobi, " + local + " per block";
  } else {
    PetscCall(describe_preconditioner(pc, &pc_text));
  }
  if (preonly) {
    *text = pc_text;
  } else {
    std::string upper = ktype;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    char buf[64];
    std::snprintf(buf, sizeof buf, ", %.1f iterations per solve", solves > 0 ? double(krylov_iterations) / solves : 0.0);
    *text = upper + " on " + pc_text + buf;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode set_roundoff_convergence_test(SNES snes, double reference_force, double floor) {
  PetscFunctionBeginUser;
  auto* test = new RoundoffTest;
  test->reference = reference_force;
  test->floor = floor;
  PetscCall(SNESSetConvergenceTest(snes, roundoff_test, test, destroy_roundoff_test));
  PetscFunctionReturn(0);
}

PetscErrorCode describe_ending(SystemAssembler& sa, TS ts, Vec U, const std::string& method,
                               const std::string& domain_error, DynamicReport* report) {
  PetscFunctionBeginUser;
  TSConvergedReason reason;
  PetscCall(TSGetConvergedReason(ts, &reason));
  PetscReal t;
  PetscCall(TSGetTime(ts, &t));
  report->time_reached = t;
  report->completed = reason > 0 && !report->interrupted;
  char buf[768];
  if (report->completed) {
    std::snprintf(buf, sizeof buf, "reached t = %.6g s", t);
  } else if (report->interrupted) {
    std::snprintf(buf, sizeof buf, "dynamics interrupted at t = %.6g s after step %ld", t, report->steps);
  } else {
    SNES snes;
    SNESConvergedReason sr;
    PetscReal fnorm;
    PetscInt its;
    PetscCall(TSGetSNES(ts, &snes));
    PetscCall(SNESGetConvergedReason(snes, &sr));
    PetscCall(SNESGetFunctionNorm(snes, &fnorm));
    PetscCall(SNESGetIterationNumber(snes, &its));
    double violation;
    int where;
    PetscCall(sa.max_constraint_violation(U, t, &violation, &where));
    const std::string step = method.empty() ? "" : ", " + method;
    std::snprintf(buf, sizeof buf,
                  "dynamics stopped at t = %.6g s (step %ld%s): TS %s; the last Newton solve ended %s after %d "
                  "iterations with residual %.3g; largest violation: %s",
                  t, report->steps, step.c_str(), TSConvergedReasons[reason], SNESConvergedReasons[sr],
                  static_cast<int>(its), fnorm, describe_violation(sa.model(), violation, where).c_str());
  }
  report->message = buf;
  if (!report->completed && !domain_error.empty()) report->message += "; " + domain_error;
  PetscFunctionReturn(0);
}

PetscErrorCode solve_saddle_point(SystemAssembler& sa, const EvaluationPoint& at, const EvaluationSettings& how,
                                  KSP ksp, Mat S, Vec b, Vec y) {
  PetscFunctionBeginUser;
  PetscBool finite;
  PetscCall(sa.residual(at, how, b, &finite));
  // An explicit method has no Newton solve to cut: the run ends here, saying why.
  PetscCheck(finite, sa.comm(), PETSC_ERR_FP, "non-finite forces at t = %g%s%s", (double)at.t,
             sa.evaluation_error().empty() ? "" : ": ", sa.evaluation_error().c_str());
  PetscCall(VecScale(b, -1.0));
  PetscCall(sa.jacobian(at, how, 0.0, 0.0, 1.0, S));  // [M G^T; G 0]
  PetscCall(KSPSetOperators(ksp, S, S));
  PetscCall(KSPSolve(ksp, b, y));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCheck(reason >= 0, sa.comm(), PETSC_ERR_NOT_CONVERGED,
             "the saddle-point system [M G^T; G 0] could not be solved at t = %g (%s): redundant constraints or a "
             "massless free DoF?",
             (double)at.t, KSPConvergedReasons[reason]);
  PetscFunctionReturn(0);
}

bool has_first_order_blocks(const Model& model) {
  return std::any_of(model.blocks.begin(), model.blocks.end(), [](const DofBlock& b) { return b.first_order && !b.fixed; });
}

PetscErrorCode consistent_first_order_rates(SystemAssembler& sa, double t, Vec U, Vec V) {
  PetscFunctionBeginUser;
  const Model& model = sa.model();
  const DofMap& dofs = sa.dofs();
  std::vector<PetscInt> rows;  // owned first-order rows, local offsets
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const DofBlock& blk = model.blocks[b];
    if (!blk.first_order || blk.fixed || dofs.block_owner(static_cast<int>(b)) != dofs.rank()) continue;
    for (int i = 0; i < blk.size(); ++i) rows.push_back(dofs.block_dof(static_cast<int>(b)) - dofs.owned_begin() + i);
  }
  PetscInt any = static_cast<PetscInt>(rows.size());
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPIU_INT, MPI_SUM, sa.comm()));
  if (any == 0) PetscFunctionReturn(0);
  Vec r0, r1;
  PetscCall(sa.create_vector(&r0));
  PetscCall(sa.create_vector(&r1));
  auto set_rates = [&](double value) -> PetscErrorCode {
    PetscScalar* v;
    PetscFunctionBeginUser;
    PetscCall(VecGetArray(V, &v));
    for (PetscInt i : rows) v[i] = value;
    PetscCall(VecRestoreArray(V, &v));
    PetscFunctionReturn(0);
  };
  const EvaluationPoint at{U, V, nullptr, nullptr, t, t};
  const EvaluationSettings how;
  PetscBool finite0, finite1;
  PetscCall(set_rates(0.0));
  PetscCall(sa.residual(at, how, r0, &finite0));
  PetscCall(set_rates(1.0));
  PetscCall(sa.residual(at, how, r1, &finite1));
  PetscCheck(finite0 && finite1, sa.comm(), PETSC_ERR_FP, "non-finite forces at the start (t = %g)%s%s", t,
             sa.evaluation_error().empty() ? "" : ": ", sa.evaluation_error().c_str());
  const PetscScalar *f, *g;
  PetscScalar* v;
  PetscCall(VecGetArrayRead(r0, &f));
  PetscCall(VecGetArrayRead(r1, &g));
  PetscCall(VecGetArray(V, &v));
  for (PetscInt i : rows) {
    const double c = g[i] - f[i];
    v[i] = c != 0.0 ? -f[i] / c : 0.0;  // a row without its rate (no volume) keeps a zero rate
  }
  PetscCall(VecRestoreArray(V, &v));
  PetscCall(VecRestoreArrayRead(r0, &f));
  PetscCall(VecRestoreArrayRead(r1, &g));
  PetscCall(VecDestroy(&r0));
  PetscCall(VecDestroy(&r1));
  PetscFunctionReturn(0);
}

PetscErrorCode configure_runge_kutta(TS ts, const DynamicSettings& settings) {
  PetscFunctionBeginUser;
  PetscCall(TSSetType(ts, TSRK));
  PetscCall(TSRKSetType(ts, settings.rk_type.c_str()));
  PetscCall(TSSetTime(ts, settings.t_start));
  PetscCall(TSSetTimeStep(ts, settings.time_step));
  PetscCall(TSSetMaxTime(ts, settings.t_end));
  PetscCall(TSSetMaxSteps(ts, settings.max_steps));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetErrorIfStepFails(ts, PETSC_FALSE));  // the integrators report failures themselves
  TSAdapt adapt;
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptSetType(adapt, settings.adaptive ? TSADAPTBASIC : TSADAPTNONE));
  PetscCall(TSSetTolerances(ts, settings.atol, nullptr, settings.rtol, nullptr));
  PetscCall(TSSetFromOptions(ts));
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
  if (observer) {
    StepInfo seen = info;
    seen.report = r;
    // Called from PETSc's monitor: an exception must end here, as a PETSc error with its message.
    PetscErrorCode status = 0;
    PetscCallCXX(status = observer->on_step(seen));
    PetscCall(status);
    if (observer->stop_requested()) r->interrupted = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode record_runge_kutta_step(SystemAssembler& sa, TS ts, PetscInt step, PetscReal t, Vec U, Vec V, Vec A,
                                       long rejection_offset, CheckpointSchedule& checkpoints, DynamicReport* report,
                                       StepObserver* observer, StepInfo* info) {
  PetscReal t_prev, dt;
  PetscInt rejects;
  PetscFunctionBeginUser;
  PetscCall(TSGetPrevTime(ts, &t_prev));
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetStepRejections(ts, &rejects));
  *info = StepInfo{static_cast<int>(step), t, t - t_prev, U, V, A, Parametrization::velocity_variables, 0,
                   rejection_offset + rejects};
  info->checkpoint = checkpoints.due(t, report->interrupted);
  info->next_time_step = dt;
  PetscCall(record_step(sa, *info, report, observer));
  PetscFunctionReturn(0);
}

CheckpointSchedule::CheckpointSchedule(double interval, double t_start, double t_end, bool end_is_checkpoint)
    : interval_(interval), t_end_(t_end), next_(next_after(t_start)), end_is_checkpoint_(end_is_checkpoint) {}

double CheckpointSchedule::next_after(double t) const {
  if (interval_ <= 0.0) return std::numeric_limits<double>::infinity();
  const double eps = 1e-9 * std::max(1.0, std::abs(t));
  return (std::floor((t + eps) / interval_) + 1.0) * interval_;
}

bool CheckpointSchedule::due(double t, bool stopping) {
  const double eps = 1e-9 * std::max(1.0, std::abs(t));
  if (stopping || (end_is_checkpoint_ && t >= t_end_ - eps)) return true;
  if (t < next_ - eps) return false;
  next_ = next_after(t);
  return true;
}

void start_report(const ResumePoint* resume, DynamicReport* report) {
  *report = DynamicReport{};
  if (!resume) return;
  report->steps = resume->step;
  report->newton_iterations = resume->newton_iterations;
  report->rejected_steps = resume->rejected_steps;
  report->rotation_rescales = resume->rotation_rescales;
  report->jacobians = resume->jacobians;
  report->max_violation = resume->max_violation;
  report->violation_constraint = resume->violation_constraint;
}

std::string describe_violation(const Model& model, double value, int constraint) {
  if (constraint < 0) return "no constraints";
  const Constraint& c = model.constraints[constraint];
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", value);
  return "constraint '" + c.name + "' (" + to_string(c.type) + "), |g| = " + buf;
}

}  // namespace latticedyn
