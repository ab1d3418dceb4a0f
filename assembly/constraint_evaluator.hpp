// Evaluates a constraint at the current state: g, its Jacobian G in the blocks' velocity variables,
// the geometric stiffness d(G^T lambda)/dq and the acceleration-level terms of (4-3), (4-27), in
// closed form; and the same by automatic differentiation, the tests' reference.
#pragma once

#include "assembly/model.hpp"
#include "core/drive.hpp"
#include "elements/element.hpp"

#include <Eigen/Core>

#include <array>
#include <functional>

namespace latticedyn {

/// The kinematic state of a block in velocity variables (translation: r, r_dot, r_ddot; rotation:
/// R, body omega, omega_dot; scalar: first components).
using BlockState = SlotState<double>;

struct ConstraintEval {
  static constexpr int kMaxRows = 6;
  static constexpr int kMaxCols = 12;
  int rows = 0;
  int cols = 0;                          ///< 3 per free block involved
  std::array<int, 4> blocks{-1, -1, -1, -1};  ///< free blocks in column order (model ids)
  Eigen::Matrix<double, kMaxRows, 1> g = Eigen::Matrix<double, kMaxRows, 1>::Zero();
  Eigen::Matrix<double, kMaxRows, 1> g_u = Eigen::Matrix<double, kMaxRows, 1>::Zero();
  Eigen::Matrix<double, kMaxRows, kMaxCols> G = Eigen::Matrix<double, kMaxRows, kMaxCols>::Zero();
  /// d(G^T lambda)/dq for the lambda given (rotations perturbed on the right).
  Eigen::Matrix<double, kMaxCols, kMaxCols> H = Eigen::Matrix<double, kMaxCols, kMaxCols>::Zero();
  /// g_dot = G v + g_u u_dot and g_ddot - G dq_dot = Gamma (4-3), with the drive's rates.
  Eigen::Matrix<double, kMaxRows, 1> g_dot = Eigen::Matrix<double, kMaxRows, 1>::Zero();
  Eigen::Matrix<double, kMaxRows, 1> gamma = Eigen::Matrix<double, kMaxRows, 1>::Zero();
};

struct ConstraintInputs {
  const Model* model = nullptr;
  const Constraint* constraint = nullptr;
  /// State of a block by model id (fixed blocks included).
  std::function<const BlockState&(int)> block_state;
  DriveValue drive;                            ///< u, u_dot, u_ddot (zero if not driven)
  const double* lambda = nullptr;              ///< multipliers for H, or null
  bool with_velocity_terms = false;            ///< compute g_dot and gamma
};

/// In closed form: every row is linear in a joint's position (a point p = t + R s of its blocks) or
/// a dot product of two such vectors (points and frame axes R c), whose first and second
/// variations under right perturbations of the rotations are those of points of rigid bodies
/// (constraint_evaluator.cpp).
ConstraintEval evaluate_constraint(const ConstraintInputs& in);
/// The same by nested forward automatic differentiation of constraint_values (constraint_kernels.hpp).
ConstraintEval evaluate_constraint_ad(const ConstraintInputs& in);

/// The two joints' frames at the current state (for output and violation reports).
void joint_frame(const Joint& j, const BlockState& t, const BlockState* r, Vec3& pos, Mat3& rot);

}  // namespace latticedyn
