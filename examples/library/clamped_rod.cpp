// latticedyn as a library: a model from a string, its static equilibrium, and the clamp's reaction
// read from the solved state; the weight m g and the moment m g c come out (c the centroid's arm).
#include "assembly/model_state.hpp"
#include "assembly/system_assembler.hpp"
#include "drivers/simulation.hpp"
#include "io/model_reader.hpp"

#include <petscsys.h>

#include <cmath>
#include <cstdio>
#include <exception>

namespace {

const char* kModel = R"(title: clamped rod
gravity: [0, 0, -9.81]
ground:
  joints: [{name: wall, position: [0, 0, 0]}]
bodies:
  - {name: rod, type: rigid_body, mass: 3.0, centroid: [1.2, 0, 0], inertia: [0.1, 0.5, 0.5],
     joints: [{name: root, position: [0, 0, 0]}]}
constraints:
  - {name: clamp, type: fixed, joints: [ground.wall, rod.root]}
)";

PetscErrorCode solve() {
  PetscFunctionBeginUser;
  latticedyn::Simulation sim;
  try {
    sim = latticedyn::read_simulation_from_string(kModel, "clamped_rod.yaml");
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "%s", e.what());
  }
  latticedyn::SystemAssembler sa(sim.model, PETSC_COMM_WORLD);
  Vec U, V;
  PetscCall(sa.create_vector(&U));
  PetscCall(sa.create_vector(&V));
  PetscCall(latticedyn::initial_state(sim, sa, U, V));
  latticedyn::SimulationOutcome outcome;
  PetscCall(latticedyn::simulate(sim, sa, U, V, /*statics=*/true, /*dynamics=*/false, nullptr, &outcome));
  PetscCheck(outcome.ok(), PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "%s", outcome.statics.message.c_str());

  latticedyn::ModelState state(sim.model, sa.dofs());
  PetscCall(sa.gather(0.0, U, V, nullptr, latticedyn::Parametrization::rotation_vector_rates, &state));
  const latticedyn::ConstraintReaction r = state.constraint_reaction(0);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "clamp reaction: force %.6g %.6g %.6g N, moment %.6g %.6g %.6g N m\n",
                        r.force.x(), r.force.y(), r.force.z(), r.moment.x(), r.moment.y(), r.moment.z()));
  const double weight = 3.0 * 9.81;
  const bool right = std::abs(r.force.z() - weight) < 1e-9 && std::abs(r.moment.y() + 1.2 * weight) < 1e-9;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", right ? "as by hand: m g and m g c" : "NOT as by hand"));
  PetscCall(VecDestroy(&U));
  PetscCall(VecDestroy(&V));
  PetscCheck(right, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the reaction differs from m g, m g c");
  PetscFunctionReturn(0);
}

}  // namespace

int main(int argc, char** argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(solve());
  PetscCall(PetscFinalize());
  return 0;
}
