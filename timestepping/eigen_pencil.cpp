// Multiplier column scaling and SLEPc's shift-and-invert set-up for the eigenanalyses.
#include "timestepping/eigen_pencil.hpp"

#include "timestepping/solver_setup.hpp"

#include <algorithm>

namespace latticedyn {

PetscErrorCode scale_multiplier_columns(const SystemAssembler& sa, double s, std::initializer_list<Mat> matrices) {
  PetscFunctionBeginUser;
  Vec D;
  PetscCall(MatCreateVecs(*matrices.begin(), &D, nullptr));
  PetscCall(fill_by_row_kind(sa, 1.0, s, D));
  for (Mat M : matrices) PetscCall(MatDiagonalScale(M, nullptr, D));
  PetscCall(VecDestroy(&D));
  PetscFunctionReturn(0);
}

int search_count(const SystemAssembler& sa, int wanted) {
  return std::max(1, std::min(wanted + std::max(4, wanted / 2), sa.model().num_free_dofs()));
}

PetscErrorCode create_shift_invert_eps(MPI_Comm comm, Mat A, Mat B, EPSProblemType type, double target, int count,
                                       double tolerance, EPS* eps) {
  PetscFunctionBeginUser;
  ST st;
  KSP ksp;
  PetscCall(EPSCreate(comm, eps));
  PetscCall(EPSSetOperators(*eps, A, B));
  PetscCall(EPSSetProblemType(*eps, type));
  PetscCall(EPSGetST(*eps, &st));
  PetscCall(STSetType(st, STSINVERT));
  PetscCall(EPSSetTarget(*eps, target));
  PetscCall(EPSSetWhichEigenpairs(*eps, EPS_TARGET_MAGNITUDE));
  PetscCall(EPSSetDimensions(*eps, count, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscCall(EPSSetTolerances(*eps, tolerance, 1000));
  PetscCall(STGetKSP(st, &ksp));
  PetscCall(set_direct_solver_defaults(ksp));
  PetscCall(EPSSetFromOptions(*eps));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
