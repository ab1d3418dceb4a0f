// Static equilibrium, then dynamics with the integrator the model names.
#include "drivers/simulation.hpp"

#include "timestepping/baumgarte.hpp"
#include "timestepping/implicit_runge_kutta.hpp"
#include "timestepping/hydraulic_cosimulation.hpp"
#include "timestepping/minimum_dof_integrator.hpp"
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/static_solver.hpp"

namespace latticedyn {

PetscErrorCode initial_state(const Simulation& sim, SystemAssembler& sa, Vec U, Vec V) {
  PetscFunctionBeginUser;
  PetscCall(sa.initial_state(U, V));
  if (!sim.start_coordinates.empty()) set_state_in_model_order(sa.dofs(), U, sim.start_coordinates);
  PetscFunctionReturn(0);
}

void set_state_in_model_order(const DofMap& dofs, Vec U, const std::vector<double>& ordered) {
  const std::vector<double> full = dofs.from_model_order(ordered);
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(U));
  PetscInt lo = 0, hi = 0;
  PetscCallAbort(comm, VecGetOwnershipRange(U, &lo, &hi));
  PetscScalar* u = nullptr;
  PetscCallAbort(comm, VecGetArray(U, &u));
  for (PetscInt i = lo; i < hi; ++i) u[i - lo] = full[i];
  PetscCallAbort(comm, VecRestoreArray(U, &u));
}

const char* integrator_name(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::baumgarte:
      return "baumgarte";
    case IntegratorKind::implicit_rk:
      return "implicit_rk";
    case IntegratorKind::minimum_dof:
      return "minimum_dof";
    case IntegratorKind::generalized_alpha:
      break;
  }
  return "generalized_alpha";
}

PetscErrorCode simulate(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, bool statics, bool dynamics,
                        StepObserver* observer, SimulationOutcome* outcome, const ResumePoint* resume,
                        Vec acceleration) {
  PetscFunctionBeginUser;
  *outcome = SimulationOutcome{};
  if (statics) {
    StaticSettings st = sim.statics;
    if (dynamics) st.time = sim.dynamics.t_start;  // the dynamics start from this equilibrium
    StaticSolver solver(sa, st);
    outcome->static_run = true;
    PetscCall(solver.solve(U, &outcome->statics, observer));
    PetscCall(VecZeroEntries(V));
    if (!outcome->statics.converged) PetscFunctionReturn(0);
  }
  if (dynamics) {
    outcome->dynamics_run = true;
    if (sim.dynamics.integrator == IntegratorKind::baumgarte) {
      BaumgarteIntegrator integrator(sa, sim.dynamics);
      PetscCall(integrator.run(U, V, observer, &outcome->dynamics, resume));
    } else if (sim.dynamics.integrator == IntegratorKind::minimum_dof) {
      MinimumDofIntegrator integrator(sa, sim.dynamics);
      PetscCall(integrator.run(U, V, observer, &outcome->dynamics, resume));
    } else if (sim.dynamics.hydraulic_cosimulation) {
      // No checkpoints (the driver refuses --restart): a co-simulation starts from its start.
      PetscCheck(!resume, sa.comm(), PETSC_ERR_SUP, "a hydraulic co-simulation cannot continue a checkpoint");
      HydraulicCosimulation cosimulation(sa, sim.dynamics);
      PetscCall(cosimulation.run(U, V, observer, &outcome->dynamics));
    } else if (sim.dynamics.integrator == IntegratorKind::implicit_rk) {
      ImplicitRungeKuttaIntegrator integrator(sa, sim.dynamics);
      PetscCall(integrator.run(U, V, observer, &outcome->dynamics, resume));
    } else {
      GeneralizedAlphaIntegrator integrator(sa, sim.dynamics);
      PetscCall(integrator.run(U, V, observer, &outcome->dynamics, resume, acceleration));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode equilibrium_modes(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, int count,
                                 std::vector<Mode>* modes, SimulationOutcome* outcome, std::string* message) {
  PetscFunctionBeginUser;
  modes->clear();
  PetscCall(simulate(sim, sa, U, V, true, false, nullptr, outcome));
  if (!outcome->statics.converged) PetscFunctionReturn(0);
  ModalAnalysis modal(sa, ModalSettings{count, 1e-10});
  PetscCall(modal.solve(U, sim.statics.time, modes, message));
  PetscFunctionReturn(0);
}

PetscErrorCode equilibrium_buckling(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, int count,
                                    std::vector<BucklingMode>* modes, SimulationOutcome* outcome,
                                    std::string* message) {
  PetscFunctionBeginUser;
  modes->clear();
  Vec U0;
  PetscCall(VecDuplicate(U, &U0));
  PetscCall(VecCopy(U, U0));
  PetscCall(simulate(sim, sa, U, V, true, false, nullptr, outcome));
  if (outcome->statics.converged) {
    BucklingAnalysis buckling(sa, BucklingSettings{count, 1e-10});
    PetscCall(buckling.solve(U0, U, sim.statics.time, modes, message));
  }
  PetscCall(VecDestroy(&U0));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
