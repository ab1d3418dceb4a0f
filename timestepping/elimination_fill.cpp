// Fill and work of a symmetric elimination order from its elimination tree.
#include "timestepping/elimination_fill.hpp"

#include <stdexcept>
#include <vector>

namespace latticedyn {

EliminationCost elimination_cost(std::span<const PetscInt> row_start, std::span<const PetscInt> columns,
                                 std::span<const PetscInt> order) {
  const auto n = static_cast<PetscInt>(order.size());
  if (row_start.size() != order.size() + 1) throw std::invalid_argument("elimination_cost: row_start needs n + 1 entries");
  std::vector<PetscInt> position(n, -1);  // row -> its place in the order
  for (PetscInt k = 0; k < n; ++k) {
    if (order[k] < 0 || order[k] >= n || position[order[k]] >= 0)
      throw std::invalid_argument("elimination_cost: order is not a permutation");
    position[order[k]] = k;
  }
  // The elimination tree: the parent of column i is the first row below it in i's column of L.
  // Path compression through `ancestor` keeps the whole pass near-linear.
  std::vector<PetscInt> parent(n, -1), ancestor(n, -1);
  for (PetscInt k = 0; k < n; ++k)
    for (PetscInt p = row_start[order[k]]; p < row_start[order[k] + 1]; ++p)
      for (PetscInt i = position[columns[p]]; i != -1 && i < k;) {
        const PetscInt next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
  // Row k of L: the union of the tree paths from each of its entries i < k up to k. Each column
  // met on the way gains an entry in row k; marking stops a path where an earlier one passed.
  std::vector<PetscInt> below(n, 0), mark(n, -1);
  for (PetscInt k = 0; k < n; ++k) {
    mark[k] = k;
    for (PetscInt p = row_start[order[k]]; p < row_start[order[k] + 1]; ++p)
      for (PetscInt i = position[columns[p]]; i < k && mark[i] != k; i = parent[i]) {
        ++below[i];
        mark[i] = k;
      }
  }
  EliminationCost cost;
  for (PetscInt c : below) {
    cost.entries += static_cast<double>(c);
    cost.work += static_cast<double>(c) * static_cast<double>(c);
  }
  return cost;
}

}  // namespace latticedyn
