// The exit codes of the latticedyn executable, and how a PETSc error code becomes one of them:
// 0 success, 1 solver failure, 2 bad input or usage, 3 internal error; nothing else.
#pragma once

namespace latticedyn {

enum ExitCode : int { kSuccess = 0, kSolverFailure = 1, kInputError = 2, kInternalError = 3 };

/// The exit code of a run that ends with this code: latticedyn's own codes pass; a PETSc error
/// code (PETSC_ERR_*) maps by its class: an unknown type, a wrong or out-of-range option value, a
/// file that cannot be opened, a solver package that is missing: bad input (2); a zero pivot, a
/// floating-point exception, a failed or unconverged solver, an error in an external solver
/// library: solver failure (1); the rest (memory, corrupted objects, PETSc's own
/// inconsistencies): internal error (3).
ExitCode exit_code_for(int code);

}  // namespace latticedyn
