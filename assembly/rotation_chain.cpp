// Chain-rule matrices of the rotation-vector parametrisation in closed form. With x = |phi|^2,
// T = I - b Phi + c2 Phi^2 and T_dot = -b Phi_dot + c2 (Phi_dot Phi + Phi Phi_dot)
// + (phi.phi_dot)(d1 Phi + d2 Phi^2) (core/rotation.hpp), b' = -d1/2, c2' = d2/2, e_i = d_i'(x):
//   P(v) = d(T v)/dphi = b skew(v) + c2 ((phi.v) I + phi v^T - 2 v phi^T)
//          + (d1 phi x v + d2 phi x (phi x v)) phi^T,
//   T_dot v = g(phi, v) = c2 (|v|^2 phi - (phi.v) v) + (phi.v) d1 phi x v + d2 ((phi.v)^2 phi - (phi.v) x v)
//     for v = phi_dot (its quadratic part), so Q = P(phi_ddot) + dg/dphi, and, since
//     T_dot(u) v = P(v) u, S = d(omega_dot)/d(phi_dot) = T_dot + P(phi_dot).
#include "assembly/rotation_chain.hpp"

#include "core/rotation.hpp"

namespace latticedyn {

namespace {

Mat3 tangent_times_derivative(const rotation_detail::Coefficients<double>& k, const Vec3& phi, const Vec3& v) {
  const Vec3 pv = phi.cross(v);
  return k.b * skew<double>(v) + k.c2 * (phi.dot(v) * Mat3::Identity() + phi * v.transpose() - 2.0 * v * phi.transpose()) +
         (k.d1 * pv + k.d2 * phi.cross(pv)) * phi.transpose();
}

}  // namespace

RotationChain rotation_chain(const Mat3& R_ref, const Vec3& phi, const Vec3& phi_dot,
                             const Vec3& phi_ddot, bool with_derivatives) {
  RotationChain c;
  const double x = phi.squaredNorm(), pp = phi.dot(phi_dot);
  const auto k = rotation_detail::coefficients(x);
  const Mat3 Phi = skew(phi), Phi2 = Phi * Phi, Pd = skew(phi_dot);
  c.R = R_ref * (Mat3::Identity() + k.a * Phi + k.b * Phi2);
  c.T = Mat3::Identity() - k.b * Phi + k.c2 * Phi2;
  const Mat3 Tdot = -k.b * Pd + k.c2 * (Pd * Phi + Phi * Pd) + pp * (k.d1 * Phi + k.d2 * Phi2);
  c.omega = c.T * phi_dot;
  c.omega_dot = c.T * phi_ddot + Tdot * phi_dot;
  if (!with_derivatives) {
    c.P.setZero();
    c.Q.setZero();
    c.S.setZero();
    return c;
  }
  const RateCoefficientDerivatives e = rate_coefficient_derivatives(x);
  const Vec3& v = phi_dot;
  const double vv = v.squaredNorm();
  const Vec3 pv = phi.cross(v);
  const Mat3 I = Mat3::Identity();
  c.P = tangent_times_derivative(k, phi, v);
  // dg/dphi term by term: c2 (|v|^2 phi - pp v), pp d1 (phi x v), d2 (pp^2 phi - pp x v).
  const Mat3 dg = (vv * phi - pp * v) * (k.d2 * phi.transpose()) + k.c2 * (vv * I - v * v.transpose()) +
                  pv * (k.d1 * v.transpose() + (2.0 * pp * e.e1) * phi.transpose()) - (pp * k.d1) * Pd +
                  (pp * pp * phi - pp * x * v) * ((2.0 * e.e2) * phi.transpose()) +
                  k.d2 * (pp * pp * I + (2.0 * pp) * phi * v.transpose() - x * v * v.transpose() -
                          (2.0 * pp) * v * phi.transpose());
  c.Q = tangent_times_derivative(k, phi, phi_ddot) + dg;
  c.S = Tdot + c.P;
  return c;
}

Mat3 tangent_transpose_derivative(const Vec3& phi, const Vec3& y) {
  // T^T y = y + b phi x y + c2 phi x (phi x y) (Phi^T = -Phi): P(y) with b -> -b.
  auto k = rotation_detail::coefficients(phi.squaredNorm());
  k.b = -k.b;
  k.d1 = -k.d1;
  return tangent_times_derivative(k, phi, y);
}

}  // namespace latticedyn
