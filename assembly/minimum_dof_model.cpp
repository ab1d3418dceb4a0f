// Minimum-DoF equations of a tree of rigid bodies: the tree from the constraints, the kinematics
// q -> block poses through time jets, and the projected element residuals.
#include "assembly/minimum_dof_model.hpp"

#include "assembly/block_kinematics.hpp"
#include "assembly/constraint_blocks.hpp"
#include "assembly/nodal_load.hpp"
#include "core/jet.hpp"
#include "core/rotation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <cmath>
#include <cstdio>
#include <numeric>

namespace latticedyn {

namespace {

int coordinates_of(ConstraintType type) {
  switch (type) {
    case ConstraintType::revolute:
    case ConstraintType::prismatic:
      return 1;
    case ConstraintType::spherical:
      return 3;
    case ConstraintType::fixed:
      break;
  }
  return 0;
}

template <class S>
Mat3T<S> axis_rotation(int axis, const S& angle) {
  return axis == 0 ? rotation_x(angle) : axis == 1 ? rotation_y(angle) : rotation_z(angle);
}

// Body angular velocity and acceleration from R(t): Omega = vee(R^T R_dot), Omega_dot = vee(R^T
// R_ddot) (the symmetric part R_dot^T R_dot drops out of the skew part).
Vec3 skew_part(const Mat3& A) { return unskew(Mat3(0.5 * (A - A.transpose()))); }

std::string describe(const Constraint& c) {
  return "constraint '" + c.name + "' (" + to_string(c.type) + ")";
}

}  // namespace

MinimumDofModel::MinimumDofModel(const Model& model) : model_(model), block_link_(model.blocks.size(), -1) {
  // Every body but the ground is one rigid body element on a translation and a rotation block.
  std::vector<int> body_translation(model.bodies.size(), -1), body_rotation(model.bodies.size(), -1);
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const ElementEntry& entry = model.elements[e];
    const std::string name = entry.body >= 0 ? model.bodies[entry.body].name : "?";
    if (entry.element->type_name() != "rigid_body")
      throw ModelError("body '" + name + "' (" + std::string(entry.element->type_name()) +
                       ") has coordinates of its own: the minimum-DoF formulation takes rigid bodies only");
    if (entry.body < 0 || body_translation[entry.body] >= 0)
      throw ModelError("body '" + name + "' has more than one element: the minimum-DoF formulation takes one rigid body "
                       "element per body");
    body_translation[entry.body] = entry.slots[0].block;
    body_rotation[entry.body] = entry.slots[1].block;
    if (!entry.slots[1].offset.isIdentity(0.0))
      throw ModelError("body '" + name + "': a rigid body element with a frame offset is not supported by the "
                       "minimum-DoF formulation");
  }
  for (std::size_t b = 1; b < model.bodies.size(); ++b)
    if (body_translation[b] < 0)
      throw ModelError("body '" + model.bodies[b].name + "' (" + model.bodies[b].type +
                       ") is not a rigid body: the minimum-DoF formulation takes rigid bodies only");
  for (const DofBlock& blk : model.blocks) {
    const Vec3 p = blk.position0;
    length_scale_ = std::max(length_scale_, p.norm());
  }

  // The tree, breadth first from the ground and from bodies whose blocks are fixed.
  std::vector<int> link_of_body(model.bodies.size(), -2);  // -2: not placed, -1: fixed, else link
  link_of_body[0] = -1;
  for (std::size_t b = 1; b < model.bodies.size(); ++b)
    if (model.blocks[body_translation[b]].fixed) link_of_body[b] = -1;
  std::vector<bool> used(model.constraints.size(), false);
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t ci = 0; ci < model.constraints.size(); ++ci) {
      if (used[ci]) continue;
      const Constraint& c = model.constraints[ci];
      const int b1 = model.joints[c.joint1].body, b2 = model.joints[c.joint2].body;
      const bool placed1 = link_of_body[b1] != -2, placed2 = link_of_body[b2] != -2;
      if (placed1 == placed2) continue;
      Link L;
      L.parent_is_joint1 = placed1;
      L.body = placed1 ? b2 : b1;
      L.parent = link_of_body[placed1 ? b1 : b2];
      L.parent_joint = placed1 ? c.joint1 : c.joint2;
      L.child_joint = placed1 ? c.joint2 : c.joint1;
      L.constraint = static_cast<int>(ci);
      L.translation_block = body_translation[L.body];
      L.rotation_block = body_rotation[L.body];
      L.first_coordinate = num_coordinates();
      L.num_coordinates = coordinates_of(c.type);
      const Joint& jc = model.joints[L.child_joint];
      if (jc.rotation_block != L.rotation_block || jc.translation_block != L.translation_block)
        throw ModelError(describe(c) + ": its joint on body '" + model.bodies[L.body].name +
                         "' is not on the body's own frame");
      for (int k = 0; k < L.num_coordinates; ++k) {
        static const char* kAxes[] = {".x", ".y", ".z"};
        coordinate_names_.push_back(L.num_coordinates == 1 ? c.name : c.name + kAxes[k]);
        coordinate_drive_.push_back(c.drive);
        (c.drive >= 0 ? driven_ : free_).push_back(L.first_coordinate + k);
      }
      link_of_body[L.body] = static_cast<int>(links_.size());
      block_link_[L.translation_block] = block_link_[L.rotation_block] = static_cast<int>(links_.size());
      links_.push_back(L);
      used[ci] = true;
      grew = true;
    }
  }
  for (std::size_t b = 1; b < model.bodies.size(); ++b)
    if (link_of_body[b] == -2)
      throw ModelError("body '" + model.bodies[b].name +
                       "' is not joined to the ground through constraints: the minimum-DoF formulation needs every "
                       "body in a tree of joints rooted at the ground");
  for (std::size_t ci = 0; ci < model.constraints.size(); ++ci)
    if (!used[ci])
      throw ModelError(describe(model.constraints[ci]) +
                       " closes a kinematic loop (or joins two fixed bodies): the minimum-DoF formulation needs a "
                       "tree of joints; use integrator generalized_alpha for closed loops");

  // Spherical joints measure their rotation vector from the initial relative orientation.
  std::vector<BlockState> initial(model.blocks.size());
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    initial[b].pos = model.blocks[b].position0;
    initial[b].rot = model.blocks[b].orientation0;
  }
  for (Link& L : links_) {
    if (model.constraints[L.constraint].type != ConstraintType::spherical) continue;
    Vec3 d;
    relative_pose(L, initial, L.sphere_reference, d);
  }
}

void MinimumDofModel::relative_pose(const Link& L, const std::vector<BlockState>& blocks, Mat3& D, Vec3& d) const {
  const Joint& jp = model_.joints[L.parent_joint];
  const Joint& jc = model_.joints[L.child_joint];
  Vec3 pp, pc;
  Mat3 Rp, Rc;
  joint_frame(jp, blocks[jp.translation_block], jp.rotation_block >= 0 ? &blocks[jp.rotation_block] : nullptr, pp, Rp);
  joint_frame(jc, blocks[jc.translation_block], &blocks[jc.rotation_block], pc, Rc);
  D = Rp.transpose() * Rc;
  d = Rp.transpose() * (pc - pp);
}

template <class S>
void MinimumDofModel::poses(const std::vector<S>& q, std::vector<Vec3T<S>>& r, std::vector<Mat3T<S>>& R) const {
  r.resize(links_.size());
  R.resize(links_.size());
  for (std::size_t i = 0; i < links_.size(); ++i) {
    const Link& L = links_[i];
    const Joint& jp = model_.joints[L.parent_joint];
    Vec3T<S> pp;
    Mat3T<S> Rp;
    if (L.parent >= 0) {
      constraint_detail::frame_of<S>(jp, r[L.parent], &R[L.parent], pp, Rp);
    } else {  // a joint on the ground or on a fixed body: its blocks keep their initial state
      const Vec3T<S> r0 = cast_to<S>(model_.blocks[jp.translation_block].position0);
      if (jp.rotation_block >= 0) {
        const Mat3T<S> R0 = cast_to<S>(model_.blocks[jp.rotation_block].orientation0);
        constraint_detail::frame_of<S>(jp, r0, &R0, pp, Rp);
      } else {
        constraint_detail::frame_of<S>(jp, r0, nullptr, pp, Rp);
      }
    }
    const Constraint& c = model_.constraints[L.constraint];
    Mat3T<S> D = Mat3T<S>::Identity();
    Vec3T<S> d = Vec3T<S>::Zero();
    const int k = L.first_coordinate;
    switch (c.type) {
      case ConstraintType::revolute: {
        const Mat3T<S> Ra = axis_rotation<S>(c.axis, q[k]);
        D = L.parent_is_joint1 ? Ra : Mat3T<S>(Ra.transpose());
        break;
      }
      case ConstraintType::prismatic:
        d(c.axis) = L.parent_is_joint1 ? q[k] : S(-q[k]);
        break;
      case ConstraintType::spherical: {
        const Vec3T<S> psi(q[k], q[k + 1], q[k + 2]);
        const Mat3T<S> Q0 = cast_to<S>(L.sphere_reference);
        D = Q0 * rotation_matrix(psi);
        break;
      }
      case ConstraintType::fixed:
        break;
    }
    const Joint& jc = model_.joints[L.child_joint];
    const Mat3T<S> Rc = Rp * D;
    const Vec3T<S> pc = pp + Rp * d;
    R[i] = Rc * cast_to<S>(jc.frame).transpose();
    r[i] = pc - R[i] * cast_to<S>(jc.offset);
  }
}

void MinimumDofModel::full_motion(double t, const VecX& q, const VecX& qdot, const VecX* qddot, VecX& Q, VecX& Qd,
                                  VecX& Qdd) const {
  const int n = num_coordinates();
  Q.setZero(n);
  Qd.setZero(n);
  Qdd.setZero(n);
  for (int k = 0; k < num_free(); ++k) {
    Q(free_[k]) = q(k);
    Qd(free_[k]) = qdot(k);
    if (qddot) Qdd(free_[k]) = (*qddot)(k);
  }
  for (int i : driven_) {
    const DriveValue u = model_.drives[coordinate_drive_[i]].evaluate(t);
    Q(i) = u.value;
    Qd(i) = u.rate;
    Qdd(i) = u.accel;
  }
}

void MinimumDofModel::jet_states(const VecX& Q, const VecX& Qd, const VecX& Qdd, std::vector<BlockState>& out) const {
  using J = Jet<double>;
  std::vector<J> q(Q.size());
  for (Eigen::Index i = 0; i < Q.size(); ++i) q[i] = J(Q(i), Qd(i), Qdd(i));
  std::vector<Vec3T<J>> r;
  std::vector<Mat3T<J>> R;
  poses(q, r, R);
  for (std::size_t i = 0; i < links_.size(); ++i) {
    BlockState& bt = out[links_[i].translation_block];
    BlockState& br = out[links_[i].rotation_block];
    Mat3 R0, R1, R2;
    for (int a = 0; a < 3; ++a) {
      bt.pos(a) = r[i](a).x;
      bt.vel(a) = r[i](a).dx;
      bt.acc(a) = r[i](a).ddx;
      for (int b = 0; b < 3; ++b) {
        R0(a, b) = R[i](a, b).x;
        R1(a, b) = R[i](a, b).dx;
        R2(a, b) = R[i](a, b).ddx;
      }
    }
    br.pos.setZero();
    br.rot = R0;
    br.vel = skew_part(R0.transpose() * R1);
    br.acc = skew_part(R0.transpose() * R2);
  }
}

void MinimumDofModel::block_states(double t, const VecX& q, const VecX& qdot, const VecX* qddot,
                                   std::vector<BlockState>& out) const {
  out.assign(model_.blocks.size(), BlockState{});
  for (std::size_t b = 0; b < model_.blocks.size(); ++b) {
    out[b].pos = model_.blocks[b].position0;
    out[b].rot = model_.blocks[b].orientation0;
  }
  VecX Q, Qd, Qdd;
  full_motion(t, q, qdot, qddot, Q, Qd, Qdd);
  jet_states(Q, Qd, Qdd, out);
}

void MinimumDofModel::velocity_columns(double t, const VecX& q, const std::vector<int>& coordinates,
                                       std::vector<MatX>& columns) const {
  const int n = static_cast<int>(coordinates.size());
  columns.assign(model_.blocks.size(), MatX());
  for (std::size_t b = 0; b < model_.blocks.size(); ++b)
    if (block_link_[b] >= 0) columns[b].setZero(3, n);
  VecX Q, Qd, Qdd;
  full_motion(t, q, VecX::Zero(num_free()), nullptr, Q, Qd, Qdd);
  std::vector<BlockState> s(model_.blocks.size());
  for (int k = 0; k < n; ++k) {
    VecX unit = VecX::Zero(Q.size());
    unit(coordinates[k]) = 1.0;
    jet_states(Q, unit, VecX::Zero(Q.size()), s);
    for (std::size_t b = 0; b < model_.blocks.size(); ++b)
      if (block_link_[b] >= 0) columns[b].col(k) = s[b].vel;
  }
}

void MinimumDofModel::generalized_residual(double t, const std::vector<BlockState>& blocks,
                                           const std::vector<MatX>& columns, VecX& g) const {
  std::vector<Vec3> rb(model_.blocks.size(), Vec3::Zero());
  const ElementContext ctx{model_.gravity, t};
  std::vector<SlotState<double>> slots;
  VecX r;
  for (const ElementEntry& entry : model_.elements) {
    gather_slots(entry, blocks, slots);
    r.resize(entry.element->num_dofs());
    entry.element->residual(slots, ctx, r);
    for (std::size_t k = 0; k < entry.slots.size(); ++k) {
      const int b = entry.slots[k].block;
      if (block_link_[b] >= 0) rb[b] += r.segment<3>(3 * static_cast<Eigen::Index>(k));
    }
  }
  auto state_of = [&blocks](int b) -> const BlockState& { return blocks[b]; };
  for (const NodalLoad& load : model_.loads) {
    const double scale = load.drive >= 0 ? model_.drives[load.drive].evaluate(t).value : 1.0;
    const LoadEval le = evaluate_load(model_, load, state_of, scale, false);
    for (int k = 0; k < 2; ++k)
      if (le.blocks[k] >= 0 && block_link_[le.blocks[k]] >= 0) rb[le.blocks[k]] -= le.f.segment<3>(3 * k);
  }
  g.setZero(num_free());
  for (std::size_t b = 0; b < model_.blocks.size(); ++b)
    if (block_link_[b] >= 0) g += columns[b].transpose() * rb[b];
}

void MinimumDofModel::equations(double t, const VecX& q, const VecX& qdot, MatX& M, VecX& f) const {
  const int nf = num_free();
  std::vector<BlockState> bias;
  block_states(t, q, qdot, nullptr, bias);  // accelerations T_dot q_dot (and the drives' T q_ddot)
  std::vector<MatX> columns;
  velocity_columns(t, q, free_, columns);
  VecX g0;
  generalized_residual(t, bias, columns, g0);
  // The residual is linear in the accelerations: column k of M is the response to q_ddot = e_k.
  M.resize(nf, nf);
  std::vector<BlockState> unit = bias;
  VecX gk;
  for (int k = 0; k < nf; ++k) {
    for (std::size_t b = 0; b < model_.blocks.size(); ++b)
      if (block_link_[b] >= 0) unit[b].acc = bias[b].acc + columns[b].col(k);
    generalized_residual(t, unit, columns, gk);
    M.col(k) = gk - g0;
  }
  M = 0.5 * (M + M.transpose()).eval();  // symmetric up to round-off; keep it exactly so
  f = -g0;
}

VecX MinimumDofModel::accelerations(double t, const VecX& q, const VecX& qdot) const {
  MatX M;
  VecX f;
  equations(t, q, qdot, M, f);
  const Eigen::LDLT<MatX> ldlt(M);
  const VecX D = ldlt.vectorD();
  const double largest = D.size() ? D.cwiseAbs().maxCoeff() : 0.0;
  if (ldlt.info() != Eigen::Success || (D.size() && !(D.minCoeff() > 1e-13 * largest))) {
    int k = 0;
    M.diagonal().cwiseAbs().minCoeff(&k);
    throw ModelError("the mass matrix of the minimum coordinates is singular at t = " + std::to_string(t) +
                     ": coordinate '" + coordinate_name(free_[k]) + "' moves (almost) no mass");
  }
  return ldlt.solve(f);
}

void MinimumDofModel::coordinates_from_blocks(double t, const std::vector<BlockState>& blocks, VecX& q,
                                              VecX& qdot) const {
  const int nf = num_free();
  VecX Q = VecX::Zero(num_coordinates());
  for (const Link& L : links_) {
    Mat3 D;
    Vec3 d;
    relative_pose(L, blocks, D, d);
    const Constraint& c = model_.constraints[L.constraint];
    const int a = c.axis, p = (a + 1) % 3, s = (a + 2) % 3, k = L.first_coordinate;
    switch (c.type) {
      case ConstraintType::revolute:  // theta = atan2(e_q1 . e_p2, e_p1 . e_p2), joint 2 relative to joint 1
        Q(k) = L.parent_is_joint1 ? std::atan2(D(s, p), D(p, p)) : std::atan2(D(p, s), D(p, p));
        break;
      case ConstraintType::prismatic:
        Q(k) = L.parent_is_joint1 ? d(a) : -d(a);
        break;
      case ConstraintType::spherical:
        Q.segment<3>(k) = rotation_vector(Mat3(L.sphere_reference.transpose() * D));
        break;
      case ConstraintType::fixed:
        break;
    }
  }
  q.resize(nf);
  for (int k = 0; k < nf; ++k) q(k) = Q(free_[k]);

  // The poses these coordinates (and the drives) give must be the ones we started from.
  std::vector<BlockState> check;
  block_states(t, q, VecX::Zero(nf), nullptr, check);
  for (const Link& L : links_) {
    const double off = std::max((check[L.translation_block].pos - blocks[L.translation_block].pos).norm() / length_scale_,
                                (check[L.rotation_block].rot - blocks[L.rotation_block].rot).norm());
    if (off > 1e-7) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " does not hold in the starting state at t = %g: body '%s' is %.3g (m per m of "
                    "model size, or rad) off the pose its joint%s allows", t, model_.bodies[L.body].name.c_str(), off,
                    model_.constraints[L.constraint].drive >= 0 ? " and its drive" : "");
      throw ModelError(describe(model_.constraints[L.constraint]) + buf);
    }
  }

  // Rates: the given velocities must be a motion of the joints (a least-squares fit of all the
  // coordinates' rates leaves nothing); the free rates are then fitted with the driven ones
  // taken from their drives, which thus prescribe their motion from the start (a drive that
  // starts moving bodies at rest).
  const std::vector<BlockState>& driven = check;  // the drives' motion alone (free rates zero)
  std::vector<int> every(num_coordinates());
  std::iota(every.begin(), every.end(), 0);
  std::vector<MatX> all_columns;  // every coordinate's columns; the free ones are a subset
  velocity_columns(t, q, every, all_columns);
  const int rows = 6 * static_cast<int>(links_.size()), n = num_coordinates();
  MatX Aall = MatX::Zero(rows, n);
  VecX rhs = VecX::Zero(rows), given = VecX::Zero(rows);
  double speed = 0.0;
  for (std::size_t i = 0; i < links_.size(); ++i) {
    const int bt = links_[i].translation_block, br = links_[i].rotation_block;
    Aall.block(6 * i, 0, 3, n) = all_columns[bt];
    Aall.block(6 * i + 3, 0, 3, n) = length_scale_ * all_columns[br];  // angular rows in m/s at the model's size
    given.segment<3>(6 * i) = blocks[bt].vel;
    given.segment<3>(6 * i + 3) = length_scale_ * blocks[br].vel;
    rhs.segment<3>(6 * i) = blocks[bt].vel - driven[bt].vel;
    rhs.segment<3>(6 * i + 3) = length_scale_ * (blocks[br].vel - driven[br].vel);
    speed = std::max({speed, blocks[bt].vel.norm(), length_scale_ * blocks[br].vel.norm()});
  }
  const VecX all_rates = n ? VecX(Aall.colPivHouseholderQr().solve(given)) : VecX();
  const double misfit = n ? (Aall * all_rates - given).cwiseAbs().maxCoeff() : given.cwiseAbs().maxCoeff();
  if (misfit > 1e-8 * std::max(1.0, speed)) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "the starting velocities at t = %g are no motion of the joints: %.3g m/s remain "
                  "after the best fit of the joint coordinates' rates", t, misfit);
    throw ModelError(buf);
  }
  const MatX A = Aall(Eigen::all, free_);
  qdot = nf ? VecX(A.colPivHouseholderQr().solve(rhs)) : VecX();
}

}  // namespace latticedyn
