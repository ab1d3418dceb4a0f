// What every term of the equations of motion reads on one rank at one evaluation: where each block
// and multiplier sits in the rank's local vector, the blocks' kinematic states and chain maps.
#pragma once

#include "assembly/block_kinematics.hpp"

#include <mutex>
#include <string>
#include <vector>

namespace latticedyn {

struct LocalState {
  std::vector<int> block_offset;       ///< per model block: its offset in the local vector, -1 if not needed
  std::vector<int> multiplier_offset;  ///< per constraint: its first multiplier's offset, -1 if not local
  std::vector<BlockState> state;       ///< per block, at the force balance
  std::vector<BlockState> state_c;     ///< per block, where the constraint rows are evaluated
  std::vector<BlockChain> chain, chain_c;  ///< their chain maps to the stored coordinates (Jacobians)
  int offset(int block) const { return block_offset[block]; }
  /// rows_I (cq K col_K_J + C col_C_J + M col_M_J): a 3 x 3 tangent block between blocks I and J
  /// through their chain maps (a scalar block uses the top-left entry).
  Mat3 chain_block(int bi, int bj, double cq, const Mat3& K, const Mat3& C, const Mat3& M) const {
    const BlockChain& ci = chain[bi];
    const BlockChain& cj = chain[bj];
    return ci.rows * (cq * K * cj.col_K + C * cj.col_C + M * cj.col_M);
  }
};

/// The first failure of an evaluation (an element outside its domain, a load or constraint that
/// threw), kept to end the run with if cutting the step does not help. record() is thread-safe.
class FirstError {
 public:
  void record(const std::string& what) {
    std::lock_guard<std::mutex> lock(guard_);
    if (text_.empty()) text_ = what;
  }
  /// Records the exception being handled (call from a catch block): an element outside its
  /// domain says so; anything else names `where` it came from.
  void record_current_exception(const std::string& where);
  void clear() { text_.clear(); }
  const std::string& text() const { return text_; }

 private:
  std::mutex guard_;
  std::string text_;
};

}  // namespace latticedyn
