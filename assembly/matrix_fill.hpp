// Direct writes of element blocks into a PETSc (B)AIJ matrix whose nonzero pattern never changes:
// each block's place in the compressed rows is looked up once, after the first assembly, so later
// Jacobians add into the value arrays without MatSetValues' search per entry.
#pragma once

#include <petscmat.h>

#include <vector>

namespace latticedyn {

/// A plan of positions in the value arrays of a (Seq|MPI)AIJ or (Seq|MPI)BAIJ matrix: per element,
/// one position per (row, block of columns) it adds to, in the element's own order. A position is
/// an offset into the diagonal part's values, or past them into the off-diagonal part's (MPI); -1
/// where the row belongs to another rank or there is no column block (those go through
/// MatSetValues). A row's entries of one column block lie column_stride() apart: 1 in AIJ's
/// compressed rows, the block size in BAIJ's column-major blocks. Other matrix types (e.g. by
/// -mat_type) get no plan: `ready` stays false.
class MatrixFill {
 public:
  bool ready = false;
  Mat matrix = nullptr;  ///< the matrix the plan is for (while being planned)

  /// Whether the plan is for J: the same object (not a new one at a freed one's address) with the
  /// same nonzero pattern.
  bool ready_for(Mat J) const;

  /// Starts a plan for J, assembled with its final nonzero pattern.
  PetscErrorCode open(Mat J);
  void start_element();
  /// The position of (row, first_col) in J; first_col < 0: none. Throws if J lacks the entry.
  void add_position(PetscInt row, PetscInt first_col);
  PetscErrorCode close();

  const PetscInt* element_offsets(int element) const { return offsets_.data() + first_[element]; }
  /// Between begin() and end(): the values at a planned position.
  double* values(PetscInt at) { return at < diagonal_nnz_ ? diagonal_ + at : off_diagonal_ + (at - diagonal_nnz_); }
  PetscInt column_stride() const { return block_size_; }
  PetscErrorCode begin(Mat J);
  PetscErrorCode end(Mat J);

 private:
  Mat a_ = nullptr, b_ = nullptr;  // diagonal and off-diagonal parts (b_ null for SeqAIJ)
  const PetscInt* garray_ = nullptr;
  PetscInt rstart_ = 0, rend_ = 0, cstart_ = 0, cend_ = 0;
  const PetscInt *ia_ = nullptr, *ja_ = nullptr, *ib_ = nullptr, *jb_ = nullptr;
  PetscInt diagonal_nnz_ = 0;
  PetscInt block_size_ = 1;  // BAIJ: positions index scalars, ia_/ja_ are block rows and columns
  double *diagonal_ = nullptr, *off_diagonal_ = nullptr;
  std::vector<PetscInt> offsets_, first_;
  PetscObjectId id_ = 0;
  PetscObjectState pattern_ = 0;
};

}  // namespace latticedyn
