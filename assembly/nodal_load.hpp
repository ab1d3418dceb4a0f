// Generalized force of a nodal force/moment on a joint (thesis 4.3, (4-8), (4-9)) in the velocity
// variables of the joint's blocks, with its derivative for follower (body-frame) loads.
#pragma once

#include "assembly/constraint_evaluator.hpp"

namespace latticedyn {

struct LoadEval {
  std::array<int, 2> blocks{-1, -1};  ///< free blocks (translation, rotation), -1 if fixed/none
  Eigen::Matrix<double, 6, 1> f = Eigen::Matrix<double, 6, 1>::Zero();  ///< [force; body moment]
  Eigen::Matrix<double, 6, 6> K = Eigen::Matrix<double, 6, 6>::Zero();  ///< df/dq
};

/// f_t = F_I, f_r = s x (R^T F_I) + R^T M_I with F_I, M_I the force and moment in the inertial
/// frame (given there, or in the joint frame and rotated by R_J); everything times `scale`.
LoadEval evaluate_load(const Model& model, const NodalLoad& load,
                       const std::function<const BlockState&(int)>& block_state, double scale,
                       bool with_tangent);

}  // namespace latticedyn
