// The linear solver of the dynamics on several ranks for models without constraints: Krylov
// iterations preconditioned by an exact LU of each rank's overlapping part of the Jacobian.
#pragma once

#include <petscksp.h>

namespace latticedyn {

/// Sets ksp to flexible GMRES with an additive Schwarz preconditioner (ten layers of overlap) whose
/// subdomain solves are PETSc's own LU in kSaddlePointOrdering. For the generalized-alpha
/// iteration matrix of a lattice, whose mass term keeps every subdomain's block nonsingular, it
/// solves to rtol 1e-8 in one or two iterations; a step costs a fifth to a quarter of one with
/// MUMPS's distributed factorisation on 2 ranks (lattice-bays, docs/performance.md). Not for
/// statics (a subdomain that floats free has a singular stiffness) nor for multipliers (a
/// constraint cut by the partition leaves a subdomain without the pivot the ordering relies on).
/// Options the user gives with the sub_ prefix (-sub_pc_type, ...) still win.
PetscErrorCode use_subdomain_lu(KSP ksp);

}  // namespace latticedyn
