// PETSc's own sparse LU for the constrained (saddle-point) Jacobians on one process: an ordering
// under which it needs no pivoting, and the switch to a pivoting LU should a pivot vanish anyway.
#pragma once

#include "assembly/system_assembler.hpp"

#include <petscksp.h>

namespace latticedyn {

/// The ordering's name for PCFactorSetMatOrderingType / -pc_factor_mat_ordering_type.
inline constexpr const char* kSaddlePointOrdering = "saddle";

/// Registers kSaddlePointOrdering with PETSc (once; after PetscInitialize): approximate minimum
/// degree on the whole pattern (reverse Cuthill-McKee where PETSc lacks AMD), then every row
/// without a pivot of its own (a Lagrange multiplier's, or a frame that only constraints hold,
/// such as the reference node of a rigid end section) moved to just after rows that give it one.
/// When the factorisation reaches a multiplier, an unknown of its constraint no other multiplier
/// relies on has been eliminated, so its pivot is a Schur complement -G K^-1 G^T (nonzero for
/// independent constraint rows) instead of the zero the plain ordering would meet; a frame comes
/// after as many of its multipliers. The rows are those of the ISs composed on the matrix under
/// kMultiplierRows and kUnstiffenedRows (SystemAssembler::create_matrix does); without them, the
/// rows with a zero diagonal count as multipliers. On a block (BAIJ) matrix, which has no such
/// rows, it is the matrix's own block order where factoring in it takes at most 5 % more work than
/// in the block minimum-degree order (counted on the block graph: elimination_cost), so PETSc's
/// natural-ordering kernels run; else the minimum-degree order.
PetscErrorCode register_saddle_point_ordering();

/// Sets ksp's LU to PETSc's own factorisation in kSaddlePointOrdering. Without pivoting or the
/// frontal machinery of UMFPACK it factors the small fronts of lattices and cranes several times
/// faster (docs/performance.md). One process only.
PetscErrorCode use_native_lu(KSP ksp);

/// If ksp's last factorisation failed (a zero pivot: dependent constraint rows, a singular
/// tangent), makes the next one start afresh and sets *reset: PETSc's own LU is switched to
/// UMFPACK, which pivots, for the rest of the solver's life; any other package (MUMPS, which
/// would otherwise skip the next factorisation and fail in the solve) is set up anew, analysis
/// included. The caller then assembles a fresh matrix. Cheap: call it before every Jacobian.
PetscErrorCode recover_from_failed_factorisation(KSP ksp, PetscBool* reset);

}  // namespace latticedyn
