// Registers latticedyn's PETSc log events once, under one class id of its own.
#include "assembly/log_events.hpp"

namespace latticedyn {

const LogEvents& log_events() {
  static const LogEvents events = [] {
    LogEvents e{};
    PetscClassId id;
    PetscCallAbort(PETSC_COMM_SELF, PetscClassIdRegister("latticedyn", &id));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdElemResidual", id, &e.element_residual));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdElemJacobian", id, &e.element_jacobian));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdConstraints", id, &e.constraints));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdBlockStates", id, &e.block_states));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdRotationRows", id, &e.rotation_rows));
    PetscCallAbort(PETSC_COMM_SELF, PetscLogEventRegister("LdOutput", id, &e.output));
    return e;
  }();
  return events;
}

}  // namespace latticedyn
