// Shared solver setup: direct-solver defaults and failure descriptions.
#include "timestepping/solver_setup.hpp"

#include <cstdio>

namespace latticedyn {

PetscErrorCode set_direct_solver_defaults(KSP ksp) {
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
#if defined(PETSC_HAVE_MUMPS)
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
#else
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERUMFPACK));
#endif
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
