// Global numbering of the generalized coordinates and Lagrange multipliers, their distribution
// over MPI ranks (METIS partition of the block graph), and the exact nonzero pattern.
#pragma once

#include "assembly/model.hpp"

#include <span>
#include <vector>

namespace latticedyn {

/// Replicated on every rank and deterministic, so ranks agree without communication. Rank p owns
/// the global range [begin(p), begin(p+1)): its blocks' DoFs first, then its constraints'
/// multipliers. An element, load or constraint is evaluated on the rank owning its first free block.
class DofMap {
 public:
  DofMap(const Model& model, int rank, int size);

  int rank() const { return rank_; }
  int size() const { return size_; }
  int global_size() const { return global_size_; }
  int begin(int p) const { return range_[p]; }
  int owned_begin() const { return range_[rank_]; }
  int owned_end() const { return range_[rank_ + 1]; }
  int owned_size() const { return owned_end() - owned_begin(); }

  /// Global index of a block's first DoF, -1 for fixed blocks.
  int block_dof(int block) const { return block_dof_[block]; }
  int block_owner(int block) const { return block_part_[block]; }
  /// Global index of a constraint's first multiplier.
  int multiplier_dof(int constraint) const { return multiplier_dof_[constraint]; }
  int num_multipliers() const { return num_multipliers_; }

  /// A full vector from global numbering to model order and back. Model order (free blocks in
  /// the model's order, then multipliers in constraint order) is the numbering of one rank: a
  /// state recorded in it means the same on any number of ranks.
  std::vector<double> to_model_order(std::span<const double> global) const;
  std::vector<double> from_model_order(std::span<const double> ordered) const;

  const std::vector<int>& local_elements() const { return local_elements_; }
  const std::vector<int>& local_constraints() const { return local_constraints_; }
  const std::vector<int>& local_loads() const { return local_loads_; }
  /// Free blocks whose state the local elements, constraints and loads read, ascending.
  const std::vector<int>& needed_blocks() const { return needed_blocks_; }

  /// Nonzeros per owned row in the diagonal and off-diagonal parts (PETSc MPIAIJ convention).
  void count_nonzeros(std::vector<int>& diagonal, std::vector<int>& off_diagonal) const;
  /// Free blocks coupled to each free block (including itself), ascending.
  const std::vector<std::vector<int>>& block_graph() const { return graph_; }
  /// Free blocks each constraint acts on, ascending.
  const std::vector<std::vector<int>>& constraint_blocks() const { return constraint_blocks_; }

 private:
  void build_graph();
  void partition();
  void number();

  const Model& model_;
  int rank_, size_;
  std::vector<std::vector<int>> graph_;
  std::vector<std::vector<int>> constraint_blocks_;
  std::vector<std::vector<int>> block_constraints_;
  std::vector<int> block_part_;
  std::vector<int> block_dof_;
  std::vector<int> multiplier_dof_;
  std::vector<int> constraint_part_;
  std::vector<int> range_;
  std::vector<int> local_elements_, local_constraints_, local_loads_, needed_blocks_;
  int global_size_ = 0;
  int num_multipliers_ = 0;
};

/// Free blocks an element, load or constraint touches.
std::vector<int> element_blocks(const Model& model, int element);
std::vector<int> joint_blocks(const Model& model, int joint);

}  // namespace latticedyn
