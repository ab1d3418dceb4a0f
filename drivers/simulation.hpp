// One simulation as the model file describes it: static equilibrium if asked, then dynamics with
// the chosen integrator. Shared by the latticedyn commands and the verification runner.
#pragma once

#include "io/model_reader.hpp"
#include "timestepping/buckling_analysis.hpp"
#include "timestepping/modal_analysis.hpp"
#include "timestepping/solver_setup.hpp"

namespace latticedyn {

struct SimulationOutcome {
  bool static_run = false;
  StaticReport statics;
  bool dynamics_run = false;
  DynamicReport dynamics;
  bool ok() const { return (!static_run || statics.converged) && (!dynamics_run || dynamics.completed); }
};

/// The state a run starts from: the model's initial state (SystemAssembler::initial_state), its
/// coordinates replaced by the recorded ones when the model names a start_state. Collective.
PetscErrorCode initial_state(const Simulation& sim, SystemAssembler& sa, Vec U, Vec V);

/// Sets a distributed vector from a full copy in model order (DofMap::to_model_order), as recorded
/// states and batch chains keep it; each rank takes its range.
void set_state_in_model_order(const DofMap& dofs, Vec U, const std::vector<double>& ordered);

/// U, V: the initial state (SystemAssembler::initial_state) in, the final state out (rotation-
/// vector rates). With `statics` the equilibrium replaces U and the rates are zeroed; with
/// `dynamics` the integrator runs from t_start to t_end and `observer` sees every step. The
/// dynamics are skipped when the equilibrium fails. Collective.
/// With `resume` (dynamics only) the run continues a checkpoint at sim.dynamics.t_start: U, V hold
/// its coordinates and velocities (in the integrator's parametrization), `acceleration` its
/// acceleration estimate.
PetscErrorCode simulate(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, bool statics, bool dynamics,
                        StepObserver* observer, SimulationOutcome* outcome, const ResumePoint* resume = nullptr,
                        Vec acceleration = nullptr);

/// The name a checkpoint gives the model's integrator ("generalized_alpha", "baumgarte").
const char* integrator_name(IntegratorKind kind);

/// The static equilibrium (as `simulate` with statics only), then the lowest `count` natural
/// modes about it. U, V: the initial state in, the equilibrium out. `modes` stays empty when the
/// statics fail (outcome says why); fewer than `count` modes come with a reason in `message`.
/// The caller destroys the modes (destroy_modes). Collective.
PetscErrorCode equilibrium_modes(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, int count,
                                 std::vector<Mode>* modes, SimulationOutcome* outcome, std::string* message);

/// Linearized buckling: the initial state U is the unloaded reference, the static equilibrium
/// under the model's loads (gravity and nodal loads) the loaded one; then the `count` load factors
/// of smallest magnitude (timestepping/buckling_analysis.hpp). U, V: the initial state in, the
/// equilibrium out; as equilibrium_modes otherwise.
PetscErrorCode equilibrium_buckling(Simulation& sim, SystemAssembler& sa, Vec U, Vec V, int count,
                                    std::vector<BucklingMode>* modes, SimulationOutcome* outcome,
                                    std::string* message);

}  // namespace latticedyn
