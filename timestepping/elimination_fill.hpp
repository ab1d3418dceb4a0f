// What factoring a structurally symmetric sparse matrix in a given order costs, counted on its
// graph without factoring: how PETSc's LU chooses between the matrix's own order and a permutation.
#pragma once

#include <petscsys.h>

#include <span>

namespace latticedyn {

/// Size and work of the factor L of P A P^T (A's pattern, which must be symmetric).
struct EliminationCost {
  double entries = 0;  ///< nonzeros of L below the diagonal
  double work = 0;     ///< sum over the columns of L of (entries below the diagonal)^2: the
                       ///< factorisation's flops up to a constant factor
};

/// A's pattern in compressed rows (row_start of size n + 1; a row may list its diagonal), `order`
/// the elimination order (order[k]: the row eliminated k-th). Counted through the elimination tree
/// in time proportional to the entries of L (Liu's row subtrees), so it costs about as much as a
/// symbolic factorisation but allocates nothing of the factor's size.
EliminationCost elimination_cost(std::span<const PetscInt> row_start, std::span<const PetscInt> columns,
                                 std::span<const PetscInt> order);

}  // namespace latticedyn
