// Positions of element blocks in the compressed rows of an AIJ or BAIJ matrix, and writes into them.
#include "assembly/matrix_fill.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace latticedyn {

PetscErrorCode MatrixFill::open(Mat J) {
  PetscFunctionBeginUser;
  ready = false;
  matrix = nullptr;
  offsets_.clear();
  first_.clear();
  MatType type;
  PetscCall(MatGetType(J, &type));
  a_ = b_ = nullptr;
  garray_ = nullptr;
  block_size_ = 1;
  if (std::strcmp(type, MATSEQAIJ) == 0) {
    a_ = J;
  } else if (std::strcmp(type, MATSEQBAIJ) == 0) {
    a_ = J;
    PetscCall(MatGetBlockSize(J, &block_size_));
  } else if (std::strcmp(type, MATMPIAIJ) == 0) {
    PetscCall(MatMPIAIJGetSeqAIJ(J, &a_, &b_, &garray_));
  } else if (std::strcmp(type, MATMPIBAIJ) == 0) {
    PetscCall(MatMPIBAIJGetSeqBAIJ(J, &a_, &b_, &garray_));  // garray: the off-diagonal block columns
    PetscCall(MatGetBlockSize(J, &block_size_));
  } else {
    PetscFunctionReturn(0);  // no plan: MatSetValues as before
  }
  PetscCall(MatGetOwnershipRange(J, &rstart_, &rend_));
  PetscCall(MatGetOwnershipRangeColumn(J, &cstart_, &cend_));
  PetscInt n;
  PetscBool done;
  // BAIJ: the block rows' block columns.
  const PetscBool blocks = block_size_ > 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(MatGetRowIJ(a_, 0, PETSC_FALSE, blocks, &n, &ia_, &ja_, &done));
  diagonal_nnz_ = ia_[n] * block_size_ * block_size_;
  if (b_) PetscCall(MatGetRowIJ(b_, 0, PETSC_FALSE, blocks, &n, &ib_, &jb_, &done));
  matrix = J;
  PetscCall(PetscObjectGetId(reinterpret_cast<PetscObject>(J), &id_));
  PetscCall(MatGetNonzeroState(J, &pattern_));
  PetscFunctionReturn(0);
}

bool MatrixFill::ready_for(Mat J) const {
  if (!ready || J != matrix) return false;
  PetscObjectId id = 0;
  PetscObjectState pattern = 0;
  if (PetscObjectGetId(reinterpret_cast<PetscObject>(J), &id) || MatGetNonzeroState(J, &pattern)) return false;
  return id == id_ && pattern == pattern_;
}

void MatrixFill::start_element() { first_.push_back(static_cast<PetscInt>(offsets_.size())); }

void MatrixFill::add_position(PetscInt row, PetscInt col) {
  if (!matrix) return;
  if (col < 0 || row < rstart_ || row >= rend_) {
    offsets_.push_back(-1);
    return;
  }
  const PetscInt lr = row - rstart_;
  auto missing = [&] {
    throw std::logic_error("MatrixFill: the matrix has no entry (" + std::to_string(row) + ", " + std::to_string(col) +
                           ") of the preallocated pattern");
  };
  if (block_size_ > 1) {
    // Block (lr / bs, col / bs), stored column by column: its entry (r, c) at bs^2 k + bs c + r. A
    // column block of the elements may start inside a matrix block (3 x 3 slots in 6 x 6 blocks).
    const PetscInt bs = block_size_, br = lr / bs, within = (col % bs) * bs + lr % bs;
    if (col >= cstart_ && col < cend_) {
      const PetscInt bc = (col - cstart_) / bs;
      const PetscInt* begin = ja_ + ia_[br];
      const PetscInt* end = ja_ + ia_[br + 1];
      const PetscInt* it = std::lower_bound(begin, end, bc);
      if (it == end || *it != bc) missing();
      offsets_.push_back(static_cast<PetscInt>(it - ja_) * bs * bs + within);
      return;
    }
    if (!b_) missing();
    const PetscInt bc = col / bs;  // global block column, in the sorted garray
    const PetscInt* begin = jb_ + ib_[br];
    const PetscInt* end = jb_ + ib_[br + 1];
    const PetscInt* it = std::lower_bound(begin, end, bc, [&](PetscInt k, PetscInt c) { return garray_[k] < c; });
    if (it == end || garray_[*it] != bc) missing();
    offsets_.push_back(diagonal_nnz_ + static_cast<PetscInt>(it - jb_) * bs * bs + within);
    return;
  }
  if (col >= cstart_ && col < cend_) {
    const PetscInt* begin = ja_ + ia_[lr];
    const PetscInt* end = ja_ + ia_[lr + 1];
    const PetscInt* it = std::lower_bound(begin, end, col - cstart_);
    if (it == end || *it != col - cstart_) missing();
    offsets_.push_back(static_cast<PetscInt>(it - ja_));
    return;
  }
  if (!b_) missing();
  // The off-diagonal part's columns are positions in garray, which is sorted by global column.
  const PetscInt* begin = jb_ + ib_[lr];
  const PetscInt* end = jb_ + ib_[lr + 1];
  const PetscInt* it = std::lower_bound(begin, end, col, [&](PetscInt k, PetscInt c) { return garray_[k] < c; });
  if (it == end || garray_[*it] != col) missing();
  offsets_.push_back(diagonal_nnz_ + static_cast<PetscInt>(it - jb_));
}

PetscErrorCode MatrixFill::close() {
  PetscInt n;
  PetscBool done;
  PetscFunctionBeginUser;
  if (!matrix) PetscFunctionReturn(0);
  const PetscBool blocks = block_size_ > 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(MatRestoreRowIJ(a_, 0, PETSC_FALSE, blocks, &n, &ia_, &ja_, &done));
  if (b_) PetscCall(MatRestoreRowIJ(b_, 0, PETSC_FALSE, blocks, &n, &ib_, &jb_, &done));
  ready = true;
  PetscFunctionReturn(0);
}

PetscErrorCode MatrixFill::begin(Mat) {
  PetscFunctionBeginUser;
  if (block_size_ > 1) {
    PetscCall(MatSeqBAIJGetArray(a_, &diagonal_));
    if (b_) PetscCall(MatSeqBAIJGetArray(b_, &off_diagonal_));
    PetscFunctionReturn(0);
  }
  PetscCall(MatSeqAIJGetArray(a_, &diagonal_));
  if (b_) PetscCall(MatSeqAIJGetArray(b_, &off_diagonal_));
  PetscFunctionReturn(0);
}

PetscErrorCode MatrixFill::end(Mat) {
  PetscFunctionBeginUser;
  if (block_size_ > 1) {
    PetscCall(MatSeqBAIJRestoreArray(a_, &diagonal_));
    if (b_) PetscCall(MatSeqBAIJRestoreArray(b_, &off_diagonal_));
    PetscFunctionReturn(0);
  }
  PetscCall(MatSeqAIJRestoreArray(a_, &diagonal_));
  if (b_) PetscCall(MatSeqAIJRestoreArray(b_, &off_diagonal_));
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
