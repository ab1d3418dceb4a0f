// Minimum-DoF route: the joint coordinates' ODE M(q) q_ddot = f by PETSc TSRK, replicated on every
// rank (a handful of coordinates); after each step the multibody state is rebuilt from q for
// the observer, with the joint reactions from one saddle-point solve.
#include "timestepping/minimum_dof_integrator.hpp"

#include "core/rotation.hpp"
#include "timestepping/prefixed_options.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace latticedyn {

namespace {

// x = [a; b], each half of the (sequential) vector X.
PetscErrorCode unpack(Vec X, VecX& a, VecX& b) {
  PetscInt size;
  const PetscScalar* x;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(X, &size));
  const Eigen::Index n = size / 2;
  PetscCall(VecGetArrayRead(X, &x));
  a = Eigen::Map<const VecX>(x, n);
  b = Eigen::Map<const VecX>(x + n, n);
  PetscCall(VecRestoreArrayRead(X, &x));
  PetscFunctionReturn(0);
}

PetscErrorCode pack(const VecX& a, const VecX& b, Vec X) {
  PetscScalar* x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(X, &x));
  Eigen::Map<VecX>(x, a.size()) = a;
  Eigen::Map<VecX>(x + a.size(), b.size()) = b;
  PetscCall(VecRestoreArray(X, &x));
  PetscFunctionReturn(0);
}

}  // namespace

MinimumDofIntegrator::MinimumDofIntegrator(SystemAssembler& sa, DynamicSettings settings)
    : sa_(sa), settings_(settings), mdof_(sa.model()) {
  const PrefixedOptions options(kDynamicPrefix);
  const MPI_Comm comm = sa_.comm();
  for (Vec* v : {&U_, &V_, &A_, &b_, &y_}) PetscCallAbort(comm, sa_.create_vector(v));
  PetscCallAbort(comm, VecCreateSeq(PETSC_COMM_SELF, 2 * mdof_.num_free(), &X_));
  PetscCallAbort(comm, sa_.create_matrix(&S_));
  multipliers_ = owned_multiplier_rows(sa_);
  int offset = 0;
  for (const DofBlock& blk : sa_.model().blocks) {
    model_offset_.push_back(blk.fixed ? -1 : offset);
    if (!blk.fixed) offset += blk.size();
  }

  PetscCallAbort(comm, KSPCreate(comm, &ksp_));
  PetscCallAbort(comm, set_direct_solver_defaults(ksp_));
  PetscCallAbort(comm, KSPSetFromOptions(ksp_));

  // Every rank integrates the same few coordinates with the same steps: no communication, and
  // adaptive step decisions agree bit for bit.
  PetscCallAbort(comm, TSCreate(PETSC_COMM_SELF, &ts_));
  PetscCallAbort(comm, TSSetApplicationContext(ts_, this));
  PetscCallAbort(comm, TSSetRHSFunction(ts_, nullptr, rhs, this));
  PetscCallAbort(comm, TSMonitorSet(ts_, monitor, this, nullptr));
  PetscCallAbort(comm, configure_runge_kutta(ts_, settings_));
}

MinimumDofIntegrator::~MinimumDofIntegrator() {
  TSDestroy(&ts_);
  KSPDestroy(&ksp_);
  MatDestroy(&S_);
  for (Vec* v : {&X_, &U_, &V_, &A_, &b_, &y_}) VecDestroy(v);
}

PetscErrorCode MinimumDofIntegrator::rhs(TS ts, PetscReal t, Vec X, Vec Xdot, void* ctx) {
  auto* self = static_cast<MinimumDofIntegrator*>(ctx);
  PetscFunctionBeginUser;
  (void)ts;
  VecX q, qdot;
  PetscCall(unpack(X, q, qdot));
  // A stage at the end of a segment sees the drives' motion before the breakpoint (its left
  // limit, to 1e-12 s): the phase that starts there belongs to the next segment's steps.
  const double end = self->segment_end_, nudge = 1e-12 * std::max(1.0, std::abs(end));
  const double t_eval = t > end - nudge ? end - nudge : static_cast<double>(t);
  VecX qddot;
  PetscCallCXX(qddot = self->mdof_.accelerations(t_eval, q, qdot));  // a singular M(q) ends the run, saying where
  PetscCheck(qddot.allFinite(), PETSC_COMM_SELF, PETSC_ERR_FP, "non-finite accelerations of the minimum coordinates at t = %g",
             (double)t);
  PetscCall(pack(qdot, qddot, Xdot));
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::blocks_of(Vec U, Vec V, Parametrization param, std::vector<BlockState>& blocks) {
  PetscFunctionBeginUser;
  std::vector<double> u, v;
  PetscCall(sa_.gather_in_model_order(U, &u));
  PetscCall(sa_.gather_in_model_order(V, &v));
  const auto n = static_cast<PetscMPIInt>(sa_.dofs().global_size());
  u.resize(n);
  v.resize(n);
  PetscCallMPI(MPI_Bcast(u.data(), n, MPI_DOUBLE, 0, sa_.comm()));
  PetscCallMPI(MPI_Bcast(v.data(), n, MPI_DOUBLE, 0, sa_.comm()));
  const Model& model = sa_.model();
  blocks.assign(model.blocks.size(), BlockState{});
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const int o = model_offset_[b];
    block_kinematics(model.blocks[b], o >= 0 ? u.data() + o : nullptr, o >= 0 ? v.data() + o : nullptr, nullptr, param,
                     blocks[b]);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::coordinates_of(double t, Vec U, Vec V, Parametrization param, Vec X) {
  PetscFunctionBeginUser;
  std::vector<BlockState> blocks;
  PetscCall(blocks_of(U, V, param, blocks));
  VecX q, qdot;
  PetscCallCXX(mdof_.coordinates_from_blocks(t, blocks, q, qdot));
  PetscCall(pack(q, qdot, X));
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::set_vectors(const std::vector<BlockState>& blocks) {
  PetscFunctionBeginUser;
  const Model& model = sa_.model();
  const int n = sa_.dofs().global_size();
  std::vector<double> ordered[3] = {std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const int o = model_offset_[b];
    if (o < 0) continue;
    const DofBlock& blk = model.blocks[b];
    const BlockState& s = blocks[b];
    // Rotation blocks store phi with R = R0 exp(phi); |phi| <= pi from the logarithm.
    const Vec3 u = blk.kind == SlotKind::rotation ? rotation_vector(Mat3(blk.orientation0.transpose() * s.rot)) : s.pos;
    for (int i = 0; i < blk.size(); ++i) {
      ordered[0][o + i] = u(i);
      ordered[1][o + i] = s.vel(i);
      ordered[2][o + i] = s.acc(i);
    }
  }
  const int lo = sa_.dofs().owned_begin(), hi = sa_.dofs().owned_end();
  Vec targets[3] = {U_, V_, A_};
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> full = sa_.dofs().from_model_order(ordered[k]);
    PetscScalar* x;
    PetscCall(VecGetArray(targets[k], &x));
    for (int i = lo; i < hi; ++i) x[i - lo] = full[i];
    PetscCall(VecRestoreArray(targets[k], &x));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::solve_multipliers(double t) {
  PetscFunctionBeginUser;
  if (multipliers_.empty() && sa_.dofs().num_multipliers() == 0) PetscFunctionReturn(0);
  EvaluationSettings how;
  how.param = Parametrization::velocity_variables;
  how.rows = ConstraintRows::acceleration;
  how.baumgarte_alpha = 0.0;  // g and g_dot vanish: the state comes from the joint coordinates
  how.baumgarte_beta = 0.0;
  const EvaluationPoint at{U_, V_, A_, nullptr, t, t};  // [M a + F - f_ext; G a + Gamma] with lambda = 0
  PetscCall(solve_saddle_point(sa_, at, how, ksp_, S_, b_, y_));
  ++solves_;
  PetscScalar* u;
  PetscScalar* y;
  PetscCall(VecGetArray(U_, &u));
  PetscCall(VecGetArray(y_, &y));
  for (PetscInt i : multipliers_) {
    u[i] = y[i];
    y[i] = 0.0;
  }
  PetscCall(VecRestoreArray(U_, &u));
  PetscCall(VecRestoreArray(y_, &y));
  PetscReal difference;
  PetscCall(VecNorm(y_, NORM_INFINITY, &difference));  // the acceleration rows: a_multibody - a
  formulation_difference_ = std::max(formulation_difference_, static_cast<double>(difference));
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::monitor(TS ts, PetscInt step, PetscReal t, Vec X, void* ctx) {
  auto* self = static_cast<MinimumDofIntegrator*>(ctx);
  PetscFunctionBeginUser;
  if (self->resumed_step_) {  // the checkpoint's state, recorded by the run that wrote it
    self->resumed_step_ = false;
    PetscFunctionReturn(0);
  }
  VecX q, qdot;
  PetscCall(unpack(X, q, qdot));
  VecX qddot;
  PetscCallCXX(qddot = self->mdof_.accelerations(t, q, qdot));
  std::vector<BlockState> blocks;
  self->mdof_.block_states(t, q, qdot, &qddot, blocks);
  PetscCall(self->set_vectors(blocks));
  PetscCall(self->solve_multipliers(t));
  StepInfo info;
  PetscCall(record_runge_kutta_step(self->sa_, ts, step, t, self->U_, self->V_, self->A_, self->rejection_offset_,
                                    self->checkpoints_, self->report_, self->observer_, &info));
  if (self->report_->interrupted) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  if (info.checkpoint) {
    // Continue from the recorded state, as a run resumed from this checkpoint does: the
    // coordinates rebuilt from the stored poses, the scheme started afresh.
    PetscCall(self->coordinates_of(t, self->U_, self->V_, Parametrization::velocity_variables, X));
    PetscCall(TSRestartStep(ts));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MinimumDofIntegrator::run(Vec U, Vec V, StepObserver* observer, DynamicReport* report,
                                         const ResumePoint* resume) {
  PetscFunctionBeginUser;
  const PrefixedOptions options(kDynamicPrefix);
  start_report(resume, report);
  observer_ = observer;
  report_ = report;
  solves_ = 0;
  formulation_difference_ = 0.0;
  PetscReal t_begin, t_end;
  PetscCall(TSGetTime(ts_, &t_begin));
  PetscCall(TSGetMaxTime(ts_, &t_end));
  checkpoints_ = CheckpointSchedule(settings_.checkpoint_interval, t_begin, t_end);
  const auto start = std::chrono::steady_clock::now();
  PetscReal dt = 0.0;  // fixed steps: every segment starts with it, not with the step shortened to meet a stop
  PetscCall(TSGetTimeStep(ts_, &dt));
  if (resume) {
    PetscCall(TSSetStepNumber(ts_, resume->step));
    PetscCall(TSSetTimeStep(ts_, settings_.adaptive ? resume->next_time_step : dt));
    rejection_offset_ = resume->rejected_steps;
    resumed_step_ = true;
  }
  PetscCall(coordinates_of(t_begin, U, V,
                           resume ? Parametrization::velocity_variables : Parametrization::rotation_vector_rates, X_));
  // Steps end on the drives' breakpoints (where a prescribed acceleration jumps): a Runge-Kutta
  // step across one would lose its order there. Each segment starts the scheme afresh.
  std::vector<double> stops;
  for (const Drive& d : sa_.model().drives)
    for (double b : d.breakpoints())
      if (b > t_begin + 1e-9 * std::max(1.0, std::abs(t_begin)) && b < t_end - 1e-9 * std::max(1.0, std::abs(t_end)))
        stops.push_back(b);
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
  stops.push_back(t_end);
  for (std::size_t k = 0; k < stops.size(); ++k) {
    PetscCall(TSSetMaxTime(ts_, stops[k]));
    segment_end_ = stops[k];
    if (k > 0) {
      resumed_step_ = true;  // TSSolve shows its starting state again: recorded already
      PetscCall(TSRestartStep(ts_));
      if (!settings_.adaptive) PetscCall(TSSetTimeStep(ts_, dt));  // not the shortened step that met the stop
    }
    PetscCall(TSSolve(ts_, X_));
    TSConvergedReason reached;
    PetscCall(TSGetConvergedReason(ts_, &reached));
    if (reached != TS_CONVERGED_TIME || report->interrupted) break;
  }

  TSConvergedReason reason;
  PetscReal t;
  PetscCall(TSGetConvergedReason(ts_, &reason));
  PetscCall(TSGetTime(ts_, &t));
  {  // the state reached, back in the multibody coordinates (rotation-vector rates at the interface)
    VecX q, qdot;
    PetscCall(unpack(X_, q, qdot));
    std::vector<BlockState> blocks;
    mdof_.block_states(t, q, qdot, nullptr, blocks);
    PetscCall(set_vectors(blocks));
    PetscCall(VecCopy(U_, U));
    PetscCall(VecCopy(V_, V));
    PetscCall(sa_.velocities_to_rates(U, V));
  }
  report->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report->time_reached = t;
  report->completed = reason > 0 && !report->interrupted;
  char buf[512];
  if (report->completed)
    std::snprintf(buf, sizeof buf, "reached t = %.6g s in %d joint coordinates (%d driven); Lagrange's first and second "
                  "kind agree to %.2g in the accelerations", t, mdof_.num_coordinates(),
                  mdof_.num_coordinates() - mdof_.num_free(), formulation_difference_);
  else if (report->interrupted)
    std::snprintf(buf, sizeof buf, "dynamics interrupted at t = %.6g s after step %ld", t, report->steps);
  else
    std::snprintf(buf, sizeof buf, "dynamics stopped at t = %.6g s (step %ld): TS %s", t, report->steps,
                  TSConvergedReasons[reason]);
  report->message = buf;
  PetscInt krylov = 0;
  PetscCall(KSPGetTotalIterations(ksp_, &krylov));
  std::string reactions;
  PetscCall(describe_linear_solver(ksp_, krylov, solves_, &reactions));
  char agree[160];
  std::snprintf(agree, sizeof agree, "; Lagrange's equations of the first and second kind agree to %.2g in the "
                "accelerations", formulation_difference_);
  report->linear_solver = "Eigen LDLT of the " + std::to_string(mdof_.num_free()) + " x " +
                          std::to_string(mdof_.num_free()) + " mass matrix; joint reactions by " + reactions + agree;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
