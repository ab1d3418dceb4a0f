// Lagrange's equations of the second kind (thesis 2.2.2, 2-14 and 2-15) for a tree of rigid bodies:
// the joints' relative coordinates are the generalized coordinates, M(q) q_ddot = f(q, q_dot, t).
#pragma once

#include "assembly/constraint_evaluator.hpp"
#include "assembly/model.hpp"
#include "core/types.hpp"

#include <string>
#include <vector>

namespace latticedyn {

/// The minimum-DoF form of a model whose bodies are rigid and whose constraints form a tree rooted
/// at the ground (a kinematic chain or tree, no closed loop). Each constraint between a parent and
/// a child body contributes the coordinates its joint leaves free:
///   revolute   1: the angle of joint 2 relative to joint 1 about the axis (the constraint's theta)
///   prismatic  1: the displacement of joint 2 along joint 1's axis
///   spherical  3: the rotation vector psi of the child's joint frame, R_c = R_p Q0 exp(psi)
///   fixed      0
/// A driven revolute or prismatic coordinate follows its drive (rheonomic); the others are free.
/// Each body's blocks move as q_e(q) (2-14): velocities T_e q_dot, accelerations T_e q_ddot +
/// T_e_dot q_dot, both by second-order time jets through the same kinematics. The equations are
/// the element residuals of the multibody model (rigid bodies, gravity, damping, nodal loads)
/// projected with T_e^T (2-15), so the two formulations share every force term.
class MinimumDofModel {
 public:
  /// Throws ModelError naming the body or constraint when the model is not a tree of rigid bodies.
  explicit MinimumDofModel(const Model& model);

  const Model& model() const { return model_; }
  int num_coordinates() const { return static_cast<int>(coordinate_names_.size()); }
  int num_free() const { return static_cast<int>(free_.size()); }
  /// "shoulder" (revolute, prismatic) or "wrist.x" (a spherical joint's rotation vector component).
  const std::string& coordinate_name(int i) const { return coordinate_names_[i]; }
  /// Indices of the free coordinates among all of them.
  const std::vector<int>& free_coordinates() const { return free_; }

  /// Free coordinates and rates from the state of the blocks (e.g. the model's initial state or a
  /// static equilibrium), the driven ones from their drives at t. Throws ModelError naming the
  /// constraint when the poses violate a joint or the velocities do not fit the coordinates.
  void coordinates_from_blocks(double t, const std::vector<BlockState>& blocks, VecX& q, VecX& qdot) const;

  /// States of all blocks of the model (fixed ones at their initial state): poses, velocity
  /// variables (r_dot, body omega) and accelerations T q_ddot + T_dot q_dot (q_ddot of the free
  /// coordinates; null: zero, which leaves the velocity-product terms alone).
  void block_states(double t, const VecX& q, const VecX& qdot, const VecX* qddot, std::vector<BlockState>& out) const;

  /// Mass matrix and right-hand side of M(q) q_ddot = f(q, q_dot, t) in the free coordinates.
  void equations(double t, const VecX& q, const VecX& qdot, MatX& M, VecX& f) const;
  /// q_ddot of the free coordinates. Throws ModelError if M(q) is singular (a coordinate that
  /// moves no mass).
  VecX accelerations(double t, const VecX& q, const VecX& qdot) const;

 private:
  struct Link {             // one body of the tree and the constraint that joins it to its parent
    int body = -1;
    int translation_block = -1, rotation_block = -1;
    int parent = -1;        // index into links_, -1: the ground
    int constraint = -1;
    int parent_joint = -1, child_joint = -1;
    bool parent_is_joint1 = true;
    int first_coordinate = 0, num_coordinates = 0;
    Mat3 sphere_reference = Mat3::Identity();  // spherical: Q0
  };

  template <class S>
  void poses(const std::vector<S>& q, std::vector<Vec3T<S>>& r, std::vector<Mat3T<S>>& R) const;
  /// Block states for one set of time jets of all coordinates.
  void jet_states(const VecX& q, const VecX& qdot, const VecX& qddot, std::vector<BlockState>& out) const;
  /// All coordinates (free given, driven from their drives) with their rates and accelerations.
  void full_motion(double t, const VecX& q, const VecX& qdot, const VecX* qddot, VecX& Q, VecX& Qd,
                   VecX& Qdd) const;
  /// Sum over blocks of T_b^T R_b: the generalized residual of the free coordinates for block
  /// states whose accelerations are set; `columns` holds each block's T (3 x num_free).
  void generalized_residual(double t, const std::vector<BlockState>& blocks, const std::vector<MatX>& columns,
                            VecX& g) const;
  /// The velocity columns of every block for the given coordinates (indices among all): T_b
  /// (3 x coordinates.size()), the velocity a unit rate of each coordinate gives the block.
  void velocity_columns(double t, const VecX& q, const std::vector<int>& coordinates, std::vector<MatX>& columns) const;
  /// The child joint's frame relative to the parent joint's: rotation D and offset d (in the
  /// parent joint's frame), from the blocks' states.
  void relative_pose(const Link& L, const std::vector<BlockState>& blocks, Mat3& D, Vec3& d) const;

  const Model& model_;
  std::vector<Link> links_;                // parents before children
  std::vector<std::string> coordinate_names_;
  std::vector<int> free_, driven_;         // coordinate indices
  std::vector<int> coordinate_drive_;      // per coordinate: drive index or -1
  std::vector<int> block_link_;            // per model block: the link moving it, -1 (fixed)
  double length_scale_ = 1.0;
};

}  // namespace latticedyn
