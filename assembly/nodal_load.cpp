// Nodal loads: the generalized force templated on the scalar, differentiated by forward AD.
#include "assembly/nodal_load.hpp"

#include "core/rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace latticedyn {

namespace {

template <class S>
Eigen::Matrix<S, 6, 1> generalized_force(const NodalLoad& load, const Joint& j, const Mat3T<S>& R) {
  const Mat3T<S> RJ = R * cast_to<S>(j.frame);
  const Vec3T<S> F = load.force_frame == LoadFrame::inertial ? cast_to<S>(load.force) : Vec3T<S>(RJ * cast_to<S>(load.force));
  const Vec3T<S> M = load.moment_frame == LoadFrame::inertial ? cast_to<S>(load.moment) : Vec3T<S>(RJ * cast_to<S>(load.moment));
  Eigen::Matrix<S, 6, 1> f;
  f.template head<3>() = F;
  f.template tail<3>() = cast_to<S>(j.offset).cross(R.transpose() * F) + R.transpose() * M;
  return f;
}

}  // namespace

LoadEval evaluate_load(const Model& model, const NodalLoad& load,
                       const std::function<const BlockState&(int)>& block_state, double scale,
                       bool with_tangent) {
  const Joint& j = model.joints[load.joint];
  LoadEval out;
  if (!model.blocks[j.translation_block].fixed) out.blocks[0] = j.translation_block;
  if (j.rotation_block < 0) {
    // No orientation: only an inertial force acts (the builder rejects anything else).
    out.f.head<3>() = scale * load.force;
    return out;
  }
  if (!model.blocks[j.rotation_block].fixed) out.blocks[1] = j.rotation_block;
  const Mat3& R = block_state(j.rotation_block).rot;
  if (!with_tangent || out.blocks[1] < 0) {
    out.f = scale * generalized_force<double>(load, j, R);
    return out;
  }
  using AD = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  Vec3T<AD> dtheta;
  for (int i = 0; i < 3; ++i) dtheta(i) = AD(0.0, 3, i);
  const Mat3T<AD> Rp = R.cast<AD>() * (Mat3T<AD>::Identity() + skew(dtheta));
  const Eigen::Matrix<AD, 6, 1> f = generalized_force<AD>(load, j, Rp);
  for (int i = 0; i < 6; ++i) {
    out.f(i) = scale * f(i).value();
    out.K.block<1, 3>(i, 3) = scale * f(i).derivatives().transpose();
  }
  return out;
}

}  // namespace latticedyn
