// A complete state of the model on one process (gathered from the distributed vectors) with the
// derived quantities output and reports need: joint frames, axial forces, energy, violations.
#pragma once

#include "assembly/block_kinematics.hpp"
#include "assembly/dof_map.hpp"

#include <span>

namespace latticedyn {

/// What a constraint does to the side of its second joint: the force and the moment about that
/// joint's origin, both inertial. Where the constraint holds, the first joint's side gets the
/// opposite force and, about the second joint's origin, the opposite moment.
struct ConstraintReaction {
  Vec3 point = Vec3::Zero();   ///< the second joint's origin, m
  Vec3 force = Vec3::Zero();   ///< N
  Vec3 moment = Vec3::Zero();  ///< N m, about `point`
};

class ModelState {
 public:
  ModelState(const Model& model, const DofMap& dofs);

  /// u, v, a in global numbering (full length); v, a may be empty (zero rates).
  void set(double time, std::span<const double> u, std::span<const double> v,
           std::span<const double> a, Parametrization param);

  double time() const { return time_; }
  const Model& model() const { return model_; }
  const BlockState& block(int b) const { return blocks_[b]; }
  std::span<const double> coordinates() const { return u_; }
  /// The coordinates in model order (DofMap::to_model_order): the same on any number of ranks.
  std::vector<double> coordinates_in_model_order() const { return dofs_.to_model_order(u_); }

  std::vector<SlotState<double>> element_slots(int element) const;
  ElementContext context() const;

  /// Position and orientation (joint -> inertial) of a joint.
  std::pair<Vec3, Mat3> joint_frame_of(int joint) const;
  Vec3 joint_position(int joint) const { return joint_frame_of(joint).first; }
  Vec3 joint_velocity(int joint) const;          ///< inertial velocity of the joint point
  Vec3 joint_angular_velocity(int joint) const;  ///< in the inertial frame

  std::optional<double> axial_force(int element) const;
  ElementEnergy energy() const;  ///< summed over all elements
  /// Values of the constraint equations g (zero when satisfied) and the multipliers.
  Eigen::VectorXd constraint_values(int constraint) const;
  Eigen::VectorXd multipliers(int constraint) const;
  /// The constraint's reaction on its second joint, -(dg/dp2)^T lambda with p2 that joint's pose
  /// (position, inertial rotation): the constraint forces -G^T lambda of the equations of motion
  /// gathered into one wrench, for any constraint type and whether or not the joints' bodies move.
  ConstraintReaction constraint_reaction(int constraint) const;
  /// Largest |g| over all constraints and the constraint where it occurs (-1 if none).
  std::pair<double, int> max_constraint_violation() const;

 private:
  const Model& model_;
  const DofMap& dofs_;
  double time_ = 0.0;
  std::vector<double> u_;
  std::vector<BlockState> blocks_;
};

}  // namespace latticedyn
