// Additive Schwarz with exact subdomain LU and GMRES: the parallel linear solver of lattices.
#include "timestepping/subdomain_lu.hpp"

#include "timestepping/native_lu.hpp"

#include <string>

namespace latticedyn {

namespace {

// Sets -<prefix><name> to value unless the options database has it already: the sub-solvers
// exist only once the preconditioner is set up, so their defaults go through the database.
PetscErrorCode default_option(const char* prefix, const char* name, const char* value) {
  const std::string key = std::string("-") + (prefix ? prefix : "") + name;
  PetscBool set;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, key.c_str(), &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, key.c_str(), value));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode use_subdomain_lu(KSP ksp) {
  PC pc;
  const char* prefix = nullptr;
  PetscFunctionBeginUser;
  PetscCall(register_saddle_point_ordering());
  // Flexible GMRES: right preconditioning that keeps the preconditioned directions, so a solve of
  // one iteration applies the subdomain LUs once (left-preconditioned GMRES applies them to the
  // right-hand side first: 31 against 17 applications for 14 solves, lattice-bays of 61,440
  // unknowns on 2 ranks; at 245,760 the linear solves 0.44 -> 0.28 s over 5 steps,
  // docs/performance.md).
  PetscCall(KSPSetType(ksp, KSPFGMRES));
  // 1e-8: Newton takes as many iterations as with an exact solve (lattice-bays up to 1e6 unknowns).
  PetscCall(KSPSetTolerances(ksp, 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 500));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCASM));
  // Overlap: on lattice-bays (61,440 unknowns, 2 ranks) GMRES takes 6.4 iterations per solve on
  // block Jacobi, 4.1 with one layer of overlap, 2.0 with four, 1.2 with ten; deeper subdomains
  // cost little against a solve saved (0.98 -> 0.85 s for 5 steps from one layer to ten; more gain
  // nothing). Models that are not chains of members pay more per layer: -pc_asm_overlap.
  PetscCall(PCASMSetOverlap(pc, 10));
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  PetscCall(default_option(prefix, "sub_ksp_type", KSPPREONLY));
  PetscCall(default_option(prefix, "sub_pc_type", PCLU));
  PetscCall(default_option(prefix, "sub_pc_factor_mat_solver_type", MATSOLVERPETSC));
  PetscCall(default_option(prefix, "sub_pc_factor_mat_ordering_type", kSaddlePointOrdering));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
