// Constraint equations g(joint frames, u) = 0 of thesis 4.4, templated on the scalar so that
// their Jacobian G, the geometric stiffness d(G^T lambda)/dq and Gamma follow by automatic
// differentiation; each type is written once, here.
#pragma once

#include "assembly/model.hpp"
#include "core/types.hpp"

namespace latticedyn {

/// Frames of the two joints: positions r1, r2 (inertial) and orientations R1, R2 (joint -> inertial).
template <class S>
struct JointPairFrames {
  Vec3T<S> r1, r2;
  Mat3T<S> R1, R2;
};

/// Writes the c.rows() constraint values into g; u is the drive value (ignored if not driven).
///  spherical  r1 - r2 = 0                                          (4-24)
///  fixed      r1 - r2 = 0, e_y1.e_z2 = e_z1.e_x2 = e_x1.e_y2 = 0    (4-13, 4-14)
///  revolute   r1 - r2 = 0, e_p1.e_a2 = e_q1.e_a2 = 0 about axis a  (4-16, 4-17)
///             driven: sin(theta - u) = e_q1.e_p2 cos u - e_p1.e_p2 sin u = 0, theta the angle of
///             joint 2 relative to joint 1 about a, (a, p, q) cyclic
///  prismatic  (r1 - r2).e_p1 = (r1 - r2).e_q1 = 0, frames aligned    (4-20, 4-21)
///             driven: (r2 - r1).e_a1 - u = 0
template <class S>
void constraint_values(const Constraint& c, const JointPairFrames<S>& f, const S& u, S* g) {
  using std::cos;
  using std::sin;
  const int a = c.axis, p = (a + 1) % 3, q = (a + 2) % 3;
  auto e1 = [&](int i) { return f.R1.col(i); };
  auto e2 = [&](int i) { return f.R2.col(i); };
  const Vec3T<S> d = f.r2 - f.r1;
  auto aligned_frames = [&](S* out) {
    out[0] = e1(1).dot(e2(2));
    out[1] = e1(2).dot(e2(0));
    out[2] = e1(0).dot(e2(1));
  };
  switch (c.type) {
    case ConstraintType::spherical:
      for (int i = 0; i < 3; ++i) g[i] = -d(i);
      break;
    case ConstraintType::fixed:
      for (int i = 0; i < 3; ++i) g[i] = -d(i);
      aligned_frames(g + 3);
      break;
    case ConstraintType::revolute:
      for (int i = 0; i < 3; ++i) g[i] = -d(i);
      g[3] = e1(p).dot(e2(a));
      g[4] = e1(q).dot(e2(a));
      if (c.drive >= 0) g[5] = e1(q).dot(e2(p)) * cos(u) - e1(p).dot(e2(p)) * sin(u);
      break;
    case ConstraintType::prismatic:
      g[0] = -d.dot(e1(p));  // (r1 - r2).e: same sign convention as the other position rows
      g[1] = -d.dot(e1(q));
      aligned_frames(g + 2);
      if (c.drive >= 0) g[5] = d.dot(e1(a)) - u;
      break;
  }
}

}  // namespace latticedyn
