// What the modal and the buckling analyses share: the multiplier columns scaled like the
// constraint rows, and SLEPc's shift-and-invert about a target with an exact LU.
#pragma once

#include "assembly/system_assembler.hpp"

#include <slepceps.h>

#include <initializer_list>

namespace latticedyn {

/// Scales the multiplier columns of each matrix by s, as the Jacobian's constraint rows are (a
/// change of the multipliers' unit: the pencil's eigenvalues stay, its scaling improves). Collective.
PetscErrorCode scale_multiplier_columns(const SystemAssembler& sa, double s, std::initializer_list<Mat> matrices);

/// How many eigenpairs to ask SLEPc for when `wanted` are wanted: a few more, because a Krylov
/// method asked for exactly as many can miss the second copy of a double eigenvalue (a round
/// section's two bending planes: 200 cubic spline beams gave bending, then torsion), at most the
/// model's free DoFs.
int search_count(const SystemAssembler& sa, int wanted);

/// An EPS for A x = mu B x that finds the `count` eigenvalues nearest `target` by shift-and-invert
/// with the direct solver's defaults; -eps_ and -st_ options win. The caller destroys it.
PetscErrorCode create_shift_invert_eps(MPI_Comm comm, Mat A, Mat B, EPSProblemType type, double target, int count,
                                       double tolerance, EPS* eps);

}  // namespace latticedyn
