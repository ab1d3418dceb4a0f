// Maps a rotation block's coordinates (phi, phi_dot, phi_ddot) to the velocity variables the
// elements use (R, omega = T phi_dot, omega_dot = T phi_ddot + T_dot phi_dot) and supplies the
// chain-rule matrices that turn element tangents into Jacobians in phi.
#pragma once

#include "core/types.hpp"

namespace latticedyn {

struct RotationChain {
  Mat3 R;          ///< R_ref exp(skew(phi))
  Vec3 omega;      ///< body angular velocity
  Vec3 omega_dot;  ///< body angular acceleration
  Mat3 T;          ///< d(omega)/d(phi_dot) = d(omega_dot)/d(phi_ddot); also dtheta = T dphi
  Mat3 P;          ///< d(omega)/d(phi)
  Mat3 Q;          ///< d(omega_dot)/d(phi)
  Mat3 S;          ///< d(omega_dot)/d(phi_dot)
};

/// with_derivatives = false leaves P, Q, S zero (residual-only evaluations).
RotationChain rotation_chain(const Mat3& R_ref, const Vec3& phi, const Vec3& phi_dot,
                             const Vec3& phi_ddot, bool with_derivatives);

/// d(T(phi)^T y)/d(phi) for fixed y: the derivative of the transformation that maps a residual
/// in omega-variables to the phi-coordinates.
Mat3 tangent_transpose_derivative(const Vec3& phi, const Vec3& y);

}  // namespace latticedyn
