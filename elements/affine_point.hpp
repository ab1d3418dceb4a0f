// A point that moves affinely with two frames, p = sum_i alpha_i r_i + R_i c_i: every lattice node
// of a super truss is one (end-section nodes and the Hermite main beams alike), so its velocity,
// acceleration, Jacobian and their derivatives are those of points on two rigid bodies.
#pragma once

#include "core/rotation.hpp"
#include "elements/element.hpp"

#include <span>

namespace latticedyn {

/// p = alpha_1 r_1 + R_1 c_1 + alpha_2 r_2 + R_2 c_2 for the two end frames (r_i, R_i) of slots
/// [translation 1, rotation 1, translation 2, rotation 2]; c_i in frame i.
struct AffinePoint {
  double alpha[2] = {0.0, 0.0};
  Vec3 c[2] = {Vec3::Zero(), Vec3::Zero()};

  AffinePoint& operator+=(const AffinePoint& o) {
    for (int i = 0; i < 2; ++i) alpha[i] += o.alpha[i], c[i] += o.c[i];
    return *this;
  }
  AffinePoint operator*(double s) const {
    AffinePoint p = *this;
    for (int i = 0; i < 2; ++i) p.alpha[i] *= s, p.c[i] *= s;
    return p;
  }
  AffinePoint operator-(const AffinePoint& o) const { return *this + o * -1.0; }
  AffinePoint operator+(AffinePoint o) const { return o += *this; }
  /// The 8 coefficients (alpha_1, alpha_2, c_1, c_2) as a vector, and back.
  Eigen::Matrix<double, 8, 1> coefficients() const {
    Eigen::Matrix<double, 8, 1> z;
    z << alpha[0], alpha[1], c[0], c[1];
    return z;
  }
  static AffinePoint from_coefficients(const Eigen::Matrix<double, 8, 1>& z) {
    AffinePoint p;
    p.alpha[0] = z(0), p.alpha[1] = z(1), p.c[0] = z.segment<3>(2), p.c[1] = z.segment<3>(5);
    return p;
  }
};

/// The two end frames' state as the point kinematics reads it (slots 0..3 of the element).
struct EndFrames {
  const SlotState<double>* s;  ///< s[0] r1, s[1] R1, s[2] r2, s[3] R2
  const Vec3& r(int i) const { return s[2 * i].pos; }
  const Mat3& R(int i) const { return s[2 * i + 1].rot; }
  const Vec3& v(int i) const { return s[2 * i].vel; }
  const Vec3& w(int i) const { return s[2 * i + 1].vel; }
  const Vec3& a(int i) const { return s[2 * i].acc; }
  const Vec3& dw(int i) const { return s[2 * i + 1].acc; }
};

inline Vec3 position(const AffinePoint& p, const EndFrames& f) {
  return p.alpha[0] * f.r(0) + f.R(0) * p.c[0] + p.alpha[1] * f.r(1) + f.R(1) * p.c[1];
}

/// pd = J dq with dq = [v1, w1, v2, w2]: J = [alpha_1 I, -R_1 skew(c_1), alpha_2 I, -R_2 skew(c_2)].
inline Mat312 jacobian(const AffinePoint& p, const EndFrames& f) {
  Mat312 J;
  for (int i = 0; i < 2; ++i) {
    J.block<3, 3>(0, 6 * i) = p.alpha[i] * Mat3::Identity();
    J.block<3, 3>(0, 6 * i + 3) = -f.R(i) * skew<double>(p.c[i]);
  }
  return J;
}

/// R_i (w_i' x c_i + w_i x (w_i x c_i)): the part of frame i's motion in the acceleration.
inline Vec3 rotational_acceleration(const AffinePoint& p, const EndFrames& f, int i) {
  const Vec3& w = f.w(i);
  return f.R(i) * (f.dw(i).cross(p.c[i]) + w.cross(w.cross(p.c[i])));
}

inline Vec3 acceleration(const AffinePoint& p, const EndFrames& f) {
  return p.alpha[0] * f.a(0) + p.alpha[1] * f.a(1) + rotational_acceleration(p, f, 0) + rotational_acceleration(p, f, 1);
}

/// d(acceleration)/d(dq): R_i ((w_i . c_i) I + w_i c_i^T - 2 c_i w_i^T) in the w_i columns.
inline Mat312 acceleration_velocity_derivative(const AffinePoint& p, const EndFrames& f) {
  Mat312 D = Mat312::Zero();
  for (int i = 0; i < 2; ++i) {
    const Vec3& w = f.w(i);
    const Vec3& c = p.c[i];
    D.block<3, 3>(0, 6 * i + 3) = f.R(i) * (w.dot(c) * Mat3::Identity() + w * c.transpose() - 2 * c * w.transpose());
  }
  return D;
}

/// d(acceleration)/dq at fixed rates, rotations perturbed on the right: -R_i skew(...) in the
/// rotation columns.
inline Mat312 acceleration_position_derivative(const AffinePoint& p, const EndFrames& f) {
  Mat312 D = Mat312::Zero();
  for (int i = 0; i < 2; ++i) {
    const Vec3& w = f.w(i);
    const Vec3& c = p.c[i];
    D.block<3, 3>(0, 6 * i + 3) = -f.R(i) * skew<double>(Vec3(f.dw(i).cross(c) + w.cross(w.cross(c))));
  }
  return D;
}

/// r += J^T F: the generalized force of a force F (inertial frame) acting at the point.
inline void add_point_force(const AffinePoint& p, const EndFrames& f, const Vec3& F, Vec12& r) {
  for (int i = 0; i < 2; ++i) {
    r.segment<3>(6 * i) += p.alpha[i] * F;
    r.segment<3>(6 * i + 3) += p.c[i].cross(f.R(i).transpose() * F);
  }
}

/// K += d(J(q (+) eps)^T F)/d eps at fixed F: skew(c_i) skew(R_i^T F) on the rotation blocks.
inline void add_point_force_geometric(const AffinePoint& p, const EndFrames& f, const Vec3& F, Mat12& K) {
  for (int i = 0; i < 2; ++i)
    K.block<3, 3>(6 * i + 3, 6 * i + 3) += skew<double>(p.c[i]) * skew<double>(Vec3(f.R(i).transpose() * F));
}

}  // namespace latticedyn
