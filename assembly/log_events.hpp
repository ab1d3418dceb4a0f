// PETSc log events of latticedyn's own work (-log_view shows them beside PETSc's): element
// residuals and Jacobians, loads and constraint rows, and writing results.
#pragma once

#include <petscsys.h>

namespace latticedyn {

struct LogEvents {
  PetscLogEvent element_residual;  ///< elements' residuals and their scatter into the local vector
  PetscLogEvent element_jacobian;  ///< elements' K, C, M and their blocks into the matrix
  PetscLogEvent constraints;       ///< loads and constraint rows, residual and Jacobian
  PetscLogEvent block_states;      ///< the blocks' states from the solver's vectors (ghosts, rotations)
  PetscLogEvent rotation_rows;     ///< the Jacobian's d(T^T y)/dphi on the rotation blocks' diagonal blocks
  PetscLogEvent output;            ///< results of a step: gather, element outputs, HDF5, XDMF, probes
};

/// The events, registered with PETSc on first use (after PetscInitialize).
const LogEvents& log_events();

}  // namespace latticedyn
