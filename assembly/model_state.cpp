// Derived quantities of a gathered model state.
#include "assembly/model_state.hpp"

#include "assembly/constraint_kernels.hpp"
#include "core/rotation.hpp"

#include <unsupported/Eigen/AutoDiff>

#include <array>
#include <tuple>

namespace latticedyn {

ModelState::ModelState(const Model& model, const DofMap& dofs)
    : model_(model), dofs_(dofs), blocks_(model.blocks.size()) {}

void ModelState::set(double time, std::span<const double> u, std::span<const double> v,
                     std::span<const double> a, Parametrization param) {
  time_ = time;
  u_.assign(u.begin(), u.end());
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    const int g = dofs_.block_dof(static_cast<int>(b));
    const double* pu = g >= 0 ? u.data() + g : nullptr;
    const double* pv = g >= 0 && !v.empty() ? v.data() + g : nullptr;
    const double* pa = g >= 0 && !a.empty() ? a.data() + g : nullptr;
    block_kinematics(model_.blocks[b], pu, pv, pa, param, blocks_[b]);
  }
}

std::vector<SlotState<double>> ModelState::element_slots(int e) const {
  std::vector<SlotState<double>> s;
  gather_slots(model_.elements[e], blocks_, s);
  return s;
}

ElementContext ModelState::context() const { return ElementContext{model_.gravity, time_}; }

std::pair<Vec3, Mat3> ModelState::joint_frame_of(int j) const {
  std::pair<Vec3, Mat3> f;
  const Joint& jt = model_.joints[j];
  joint_frame(jt, blocks_[jt.translation_block], jt.rotation_block >= 0 ? &blocks_[jt.rotation_block] : nullptr,
              f.first, f.second);
  return f;
}

Vec3 ModelState::joint_velocity(int j) const {
  const Joint& jt = model_.joints[j];
  Vec3 v = blocks_[jt.translation_block].vel;
  if (jt.rotation_block >= 0) {
    const BlockState& r = blocks_[jt.rotation_block];
    v += r.rot * r.vel.cross(jt.offset);
  }
  return v;
}

Vec3 ModelState::joint_angular_velocity(int j) const {
  const Joint& jt = model_.joints[j];
  if (jt.rotation_block < 0) return Vec3::Zero();
  const BlockState& r = blocks_[jt.rotation_block];
  return r.rot * r.vel;
}

std::optional<double> ModelState::axial_force(int e) const {
  const auto s = element_slots(e);
  return model_.elements[e].element->axial_force(s, context());
}

ElementEnergy ModelState::energy() const {
  ElementEnergy total;
  const ElementContext ctx = context();
  for (std::size_t e = 0; e < model_.elements.size(); ++e) {
    const auto s = element_slots(static_cast<int>(e));
    const ElementEnergy x = model_.elements[e].element->energy(s, ctx);
    total.kinetic += x.kinetic;
    total.gravity_potential += x.gravity_potential;
    total.strain += x.strain;
    total.fluid += x.fluid;
  }
  return total;
}

Eigen::VectorXd ModelState::constraint_values(int c) const {
  const Constraint& con = model_.constraints[c];
  JointPairFrames<double> f;
  std::tie(f.r1, f.R1) = joint_frame_of(con.joint1);
  std::tie(f.r2, f.R2) = joint_frame_of(con.joint2);
  const double u = con.drive >= 0 ? model_.drives[con.drive].evaluate(time_).value : 0.0;
  Eigen::VectorXd g(con.rows());
  latticedyn::constraint_values<double>(con, f, u, g.data());
  return g;
}

Eigen::VectorXd ModelState::multipliers(int c) const {
  const int first = dofs_.multiplier_dof(c);
  const int rows = model_.constraints[c].rows();
  Eigen::VectorXd l(rows);
  for (int i = 0; i < rows; ++i) l(i) = u_.empty() ? 0.0 : u_[first + i];
  return l;
}

ConstraintReaction ModelState::constraint_reaction(int c) const {
  // g depends on the joints' frames only, so its derivative with respect to a small motion of the
  // second frame (translation d, inertial rotation theta: R2 -> (I + skew(theta)) R2) is the
  // virtual work of the constraint forces on that side.
  using S = Eigen::AutoDiffScalar<Eigen::Matrix<double, 6, 1>>;
  const Constraint& con = model_.constraints[c];
  const auto [r1, R1] = joint_frame_of(con.joint1);
  const auto [r2, R2] = joint_frame_of(con.joint2);
  Vec3T<S> d, theta;
  for (int i = 0; i < 3; ++i) {
    d(i) = S(0.0, 6, i);
    theta(i) = S(0.0, 6, 3 + i);
  }
  JointPairFrames<S> f;
  f.r1 = r1.cast<S>();
  f.R1 = R1.cast<S>();
  f.r2 = r2.cast<S>() + d;
  f.R2 = (Mat3T<S>::Identity() + skew(theta)) * R2.cast<S>();
  const S u(con.drive >= 0 ? model_.drives[con.drive].evaluate(time_).value : 0.0);
  std::array<S, 6> g;  // the most rows a constraint has (fixed; a driven revolute)
  latticedyn::constraint_values<S>(con, f, u, g.data());
  const Eigen::VectorXd lambda = multipliers(c);
  Eigen::Matrix<double, 6, 1> wrench = Eigen::Matrix<double, 6, 1>::Zero();
  for (int i = 0; i < con.rows(); ++i) wrench -= lambda(i) * g[static_cast<std::size_t>(i)].derivatives();
  return ConstraintReaction{r2, wrench.head<3>(), wrench.tail<3>()};
}

std::pair<double, int> ModelState::max_constraint_violation() const {
  double worst = 0.0;
  int where = -1;
  for (std::size_t c = 0; c < model_.constraints.size(); ++c) {
    const double v = constraint_values(static_cast<int>(c)).cwiseAbs().maxCoeff();
    if (v > worst || where < 0) {
      worst = v;
      where = static_cast<int>(c);
    }
  }
  return {worst, where};
}

}  // namespace latticedyn
