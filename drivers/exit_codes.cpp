// PETSc error classes to latticedyn's exit codes.
#include "drivers/exit_codes.hpp"

#include <petscsys.h>

namespace latticedyn {

ExitCode exit_code_for(int code) {
  switch (code) {
    case kSuccess: return kSuccess;
    case kSolverFailure: return kSolverFailure;
    case kInputError: return kInputError;
    case kInternalError: return kInternalError;
    case PETSC_ERR_ARG_UNKNOWN_TYPE:
    case PETSC_ERR_ARG_WRONG:
    case PETSC_ERR_ARG_OUTOFRANGE:
    case PETSC_ERR_ARG_INCOMP:
    case PETSC_ERR_USER_INPUT:
    case PETSC_ERR_FILE_OPEN:
    case PETSC_ERR_FILE_READ:
    case PETSC_ERR_FILE_UNEXPECTED:
    case PETSC_ERR_MISSING_FACTOR:
    case PETSC_ERR_OPT_OVERWRITE:
    case PETSC_ERR_WRONG_MPI_SIZE:
    case PETSC_ERR_SUP: return kInputError;
    case PETSC_ERR_FP:
    case PETSC_ERR_MAT_LU_ZRPVT:
    case PETSC_ERR_MAT_CH_ZRPVT:
    case PETSC_ERR_CONV_FAILED:
    case PETSC_ERR_NOT_CONVERGED:
    case PETSC_ERR_LIB:
    case PETSC_ERR_SIG: return kSolverFailure;
    default: return kInternalError;
  }
}

}  // namespace latticedyn
