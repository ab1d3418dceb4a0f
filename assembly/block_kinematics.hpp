// From the stored coordinates of a DoF block to its kinematic state in velocity variables, for
// the two ways the integrators store rates: rotation-vector rates (phi_dot, phi_ddot: TSALPHA2,
// statics) or velocity variables (omega, omega_dot: the state-space Baumgarte route).
#pragma once

#include "assembly/constraint_evaluator.hpp"
#include "assembly/rotation_chain.hpp"

#include <array>
#include <span>

namespace latticedyn {

enum class Parametrization { rotation_vector_rates, velocity_variables };

/// Chain-rule maps of one block for a Jacobian J = cq dr/dU + cv dr/dV + ca dr/dA: a tangent
/// block (K, C, M) between row block I and column block J maps to
///   rows_I * (cq K col_K_J + C col_C_J + M col_M_J).
struct BlockChain {
  Mat3 rows = Mat3::Identity();   ///< T^T for rotation rows in rotation_vector_rates, else I
  Mat3 col_K = Mat3::Identity();  ///< d(dtheta)/d(phi) = T
  Mat3 col_C = Mat3::Zero();      ///< cq P + cv T
  Mat3 col_M = Mat3::Zero();      ///< cq Q + cv S + ca T
};

/// u, v, a point at the block's first coordinate (v, a may be null: zero rates). Fixed blocks
/// take their initial state. With `chain` non-null the chain maps are filled for (cq, cv, ca).
void block_kinematics(const DofBlock& block, const double* u, const double* v, const double* a,
                      Parametrization param, BlockState& state, BlockChain* chain = nullptr,
                      double cq = 1.0, double cv = 0.0, double ca = 0.0);

/// Element slot state seen through a binding's frame offset (rotation slots: R O, O^T omega).
BlockState slot_state(const BlockState& block, SlotKind kind, const Mat3& offset);

/// The slot states of an element from the states of all blocks (indexed by model block id).
void gather_slots(const ElementEntry& entry, const std::vector<BlockState>& blocks,
                  std::vector<SlotState<double>>& slots);

/// Consecutive elements of one type evaluated together (Element::residual_batch, tangents_batch)
/// and their slot states.
struct ElementRun {
  int count = 0;
  std::array<const Element*, kMaxElementBatch> elements{};
  std::array<std::span<const SlotState<double>>, kMaxElementBatch> states{};
  std::size_t size() const { return static_cast<std::size_t>(count); }
  std::span<const Element* const> element_span() const { return {elements.data(), size()}; }
  std::span<const std::span<const SlotState<double>>> state_span() const { return {states.data(), size()}; }
};

/// The elements model.elements[ids[first + k]], k < count (at most kMaxElementBatch), with their
/// slot states, which stay valid until the calling thread's next gather_run.
ElementRun gather_run(const Model& model, const std::vector<int>& ids, int first, int count,
                      const std::vector<BlockState>& blocks);

}  // namespace latticedyn
