// Rotation algebra of thesis Appendix B: skew matrices, the rotation vector (Rodrigues, B-7), its
// tangent operator T (B-8) with inverse and time derivative (B-11), the log map and Cardan angles.
#pragma once

#include "core/types.hpp"

#include <cmath>
#include <numbers>

namespace latticedyn {

/// Skew-symmetric matrix of a vector, skew(a) b = a x b.
template <class S>
Mat3T<S> skew(const Vec3T<S>& a) {
  Mat3T<S> m;
  m << S(0), -a(2), a(1),  //
      a(2), S(0), -a(0),   //
      -a(1), a(0), S(0);
  return m;
}

/// The axial vector of the skew-symmetric part of m (inverse of skew on skew matrices).
template <class S>
Vec3T<S> unskew(const Mat3T<S>& m) {
  return Vec3T<S>(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1)) * S(0.5);
}

namespace rotation_detail {

// Below this squared angle every coefficient is evaluated from its Taylor series in x = theta^2
// (truncation error < 1e-17); above it the closed forms lose at most ~eps/x to cancellation.
inline constexpr double kSeriesBelow = 1e-2;

template <class S>
S poly(const S& x, double c0, double c1, double c2, double c3, double c4) {
  return S(c0) + x * (S(c1) + x * (S(c2) + x * (S(c3) + x * S(c4))));
}

/// Coefficients of R = I + a Phi + b Phi^2 and T = I + c1 Phi + c2 Phi^2 as functions of
/// x = |phi|^2, with d1 = c1'(theta)/theta and d2 = c2'(theta)/theta for dT/dt.
template <class S>
struct Coefficients {
  S a, b, c2, d1, d2;
};

template <class S>
Coefficients<S> coefficients(const S& x) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (scalar_value(x) < kSeriesBelow) {
    return {poly(x, 1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880),
            poly(x, 0.5, -1.0 / 24, 1.0 / 720, -1.0 / 40320, 1.0 / 3628800),
            poly(x, 1.0 / 6, -1.0 / 120, 1.0 / 5040, -1.0 / 362880, 1.0 / 39916800),
            poly(x, 1.0 / 12, -1.0 / 180, 1.0 / 6720, -1.0 / 453600, 1.0 / 47900160),
            poly(x, -1.0 / 60, 1.0 / 1260, -1.0 / 60480, 1.0 / 4989600, -1.0 / 622702080)};
  }
  const S t = sqrt(x);
  const S s = sin(t);
  const S c = cos(t);
  const S one_minus_c = S(1) - c;
  return {s / t,
          one_minus_c / x,
          (t - s) / (x * t),
          (S(2) * one_minus_c - t * s) / (x * x),
          (one_minus_c * t - S(3) * (t - s)) / (x * x * t)};
}

/// c3's Taylor series in x, for x < kSeriesBelow, and that of dc3/dx.
template <class S>
S inverse_coefficient_series(const S& x) {
  return poly(x, 1.0 / 12, 1.0 / 720, 1.0 / 30240, 1.0 / 1209600, 1.0 / 47900160);
}
template <class S>
S inverse_coefficient_derivative_series(const S& x) {
  return poly(x, 1.0 / 720, 2.0 / 30240, 3.0 / 1209600, 4.0 / 47900160, 0.0);
}

/// c3(x) and dc3/dx in double, series or closed form.
void inverse_coefficient_and_derivative(double x, double* c3, double* dc3);

/// c3 of T^{-1} = I + Phi/2 + c3 Phi^2, c3 = (1 - (theta/2) cot(theta/2)) / theta^2.
template <class S>
S inverse_coefficient(const S& x) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (scalar_value(x) < kSeriesBelow) return inverse_coefficient_series(x);
  const S t = sqrt(x);
  return (S(1) - t * (S(1) + cos(t)) / (S(2) * sin(t))) / x;
}

}  // namespace rotation_detail

/// Rotation matrix of the rotation vector phi, Rodrigues' formula (2-4, B-7): R = exp(skew(phi)).
template <class S>
Mat3T<S> rotation_matrix(const Vec3T<S>& phi) {
  const S x = phi.squaredNorm();
  const auto k = rotation_detail::coefficients(x);
  const Mat3T<S> P = skew(phi);
  return Mat3T<S>::Identity() + k.a * P + k.b * (P * P);
}

/// Tangent operator T(phi) of (2-5, B-8): body angular velocity omega = T(phi) dphi/dt, and the
/// right perturbation exp(phi + d) = exp(phi) exp(T(phi) d) to first order.
template <class S>
Mat3T<S> tangent_operator(const Vec3T<S>& phi) {
  const S x = phi.squaredNorm();
  const auto k = rotation_detail::coefficients(x);
  const Mat3T<S> P = skew(phi);
  return Mat3T<S>::Identity() - k.b * P + k.c2 * (P * P);
}

/// T(phi)^{-1} = I + Phi/2 + c3 Phi^2; singular at |phi| = 2 pi, which rescaling keeps away.
template <class S>
Mat3T<S> tangent_operator_inverse(const Vec3T<S>& phi) {
  const S x = phi.squaredNorm();
  const Mat3T<S> P = skew(phi);
  return Mat3T<S>::Identity() + S(0.5) * P + rotation_detail::inverse_coefficient(x) * (P * P);
}

/// T(phi)^-T m = m - phi x m / 2 + c3 phi x (phi x m), without forming the matrix.
inline Vec3 tangent_inverse_transpose_times(const Vec3& phi, const Vec3& m) {
  const Vec3 pm = phi.cross(m);
  return m - 0.5 * pm + rotation_detail::inverse_coefficient(phi.squaredNorm()) * phi.cross(pm);
}

/// d(T(phi)^-T m)/dphi for a fixed vector m: the change of the generalized moment T^-T m that a
/// log-map coordinate phi carries when phi changes (the co-rotational beam's local rotations).
/// T^-T m = m - phi x m / 2 + c3 phi x (phi x m), so the derivative is
/// skew(m)/2 + c3 (phi m^T + (phi.m) I - 2 m phi^T) + 2 c3'(|phi|^2) (phi x (phi x m)) phi^T.
Mat3 tangent_inverse_transpose_derivative(const Vec3& phi, const Vec3& m);
/// The same with c3(|phi|^2) and its derivative given, for any scalar.
template <class S>
Mat3T<S> tangent_inverse_transpose_derivative(const Vec3T<S>& phi, const Vec3T<S>& m, const S& c3, const S& dc3) {
  const Vec3T<S> pm = phi.cross(m), ppm = phi.cross(pm);
  return skew(m) * S(0.5) +
         (phi * m.transpose() + Mat3T<S>::Identity() * phi.dot(m) - m * phi.transpose() * S(2.0)) * c3 +
         ppm * phi.transpose() * (dc3 * S(2.0));
}

/// Time derivative dT/dt of T(phi(t)) for dphi/dt = phi_dot (B-11, rederived; the thesis's
/// "(1 - sin theta)" is a conversion error for "(theta - sin theta)").
template <class S>
Mat3T<S> tangent_operator_rate(const Vec3T<S>& phi, const Vec3T<S>& phi_dot) {
  const S x = phi.squaredNorm();
  const auto k = rotation_detail::coefficients(x);
  const Mat3T<S> P = skew(phi);
  const Mat3T<S> Pd = skew(phi_dot);
  const S pp = phi.dot(phi_dot);
  return -k.b * Pd + k.c2 * (Pd * P + P * Pd) + pp * (k.d1 * P + k.d2 * (P * P));
}

/// The x-derivatives e1 = d1'(x), e2 = d2'(x) (x = |phi|^2) of dT/dt's coefficients: what the
/// phi-derivative of the angular acceleration T phi_ddot + T_dot phi_dot needs beyond T_dot.
struct RateCoefficientDerivatives {
  double e1, e2;
};
RateCoefficientDerivatives rate_coefficient_derivatives(double x);

/// Rotation vector of a rotation matrix (log map), |phi| <= pi; robust near 0 and near pi.
Vec3 rotation_vector(const Mat3& R);

/// Log map for rotations of less than pi/2 (e.g. an element's deformational rotations), templated
/// for automatic differentiation: phi = theta / sin(theta) unskew(R), with theta / sin(theta) from
/// its series in sin^2 near 0 so that derivatives stay exact there.
namespace rotation_detail {
// theta / sin(theta) as asin(s)/s = 1 + s^2/6 + 3 s^4/40 + 5 s^6/112 + 35 s^8/1152 in s^2 =
// sin^2(theta), for s^2 below kSmallAngleSeriesBelow (cos(theta) > 0 there).
inline constexpr double kSmallAngleSeriesBelow = 1e-4;
template <class S>
S angle_over_sine_series(const S& s2) {
  return poly(s2, 1.0, 1.0 / 6, 3.0 / 40, 5.0 / 112, 35.0 / 1152);
}
}  // namespace rotation_detail

template <class S>
Vec3T<S> small_rotation_vector(const Mat3T<S>& R) {
  using std::atan2;
  using std::sqrt;
  const Vec3T<S> v = unskew(R);  // sin(theta) n
  const S s2 = v.squaredNorm();
  if (scalar_value(s2) < rotation_detail::kSmallAngleSeriesBelow) return v * rotation_detail::angle_over_sine_series(s2);
  const S s = sqrt(s2);
  const S c = (R.trace() - S(1)) / S(2);
  return v * (atan2(s, c) / s);
}

/// The same rotation with |phi| <= pi: subtracts the multiple of 2 pi along the axis. Used after
/// a time step so that T(phi) never approaches its singularity at |phi| = 2 pi.
Vec3 rescaled_rotation_vector(const Vec3& phi);

/// Elementary rotations about x, y, z (B-13..B-15).
template <class S>
Mat3T<S> rotation_x(const S& a) {
  using std::cos;
  using std::sin;
  Mat3T<S> m;
  m << S(1), S(0), S(0), S(0), cos(a), -sin(a), S(0), sin(a), cos(a);
  return m;
}
template <class S>
Mat3T<S> rotation_y(const S& a) {
  using std::cos;
  using std::sin;
  Mat3T<S> m;
  m << cos(a), S(0), sin(a), S(0), S(1), S(0), -sin(a), S(0), cos(a);
  return m;
}
template <class S>
Mat3T<S> rotation_z(const S& a) {
  using std::cos;
  using std::sin;
  Mat3T<S> m;
  m << cos(a), -sin(a), S(0), sin(a), cos(a), S(0), S(0), S(0), S(1);
  return m;
}

/// Cardan (Tait-Bryan) angles in the sequence I -z-> 1 -y-> 2 -x-> B of (B-12), stored as
/// angles = [phi_x, psi_y, theta_z]: R = Rz(theta) Ry(psi) Rx(phi) (B-16).
template <class S>
Mat3T<S> cardan_zyx_matrix(const Vec3T<S>& angles) {
  return rotation_z(angles(2)) * rotation_y(angles(1)) * rotation_x(angles(0));
}

/// T of the Cardan angles: body angular velocity (or curvature) = T(angles) d(angles)/dt (B-17,
/// B-19; rederived: the thesis's second and third rows carry psi where phi belongs).
template <class S>
Mat3T<S> cardan_zyx_tangent(const Vec3T<S>& angles) {
  using std::cos;
  using std::sin;
  const S sf = sin(angles(0)), cf = cos(angles(0));
  const S sp = sin(angles(1)), cp = cos(angles(1));
  Mat3T<S> T;
  T << S(1), S(0), -sp,  //
      S(0), cf, sf * cp,   //
      S(0), -sf, cf * cp;
  return T;
}

/// dT/dt of the Cardan tangent for angle rates `rates`.
template <class S>
Mat3T<S> cardan_zyx_tangent_rate(const Vec3T<S>& angles, const Vec3T<S>& rates) {
  using std::cos;
  using std::sin;
  const S sf = sin(angles(0)), cf = cos(angles(0));
  const S sp = sin(angles(1)), cp = cos(angles(1));
  const S df = rates(0), dp = rates(1);
  Mat3T<S> Td;
  Td << S(0), S(0), -cp * dp,                  //
      S(0), -sf * df, cf * cp * df - sf * sp * dp,  //
      S(0), -cf * df, -sf * cp * df - cf * sp * dp;
  return Td;
}

/// First and second derivatives of the Cardan tangent T(angles) with respect to the angles, from
/// the sines and cosines of phi_x and psi_y (T depends on no other): dT[0] = dT/dphi,
/// dT[1] = dT/dpsi, ddT[0] = d2T/dphi2, ddT[1] = d2T/dphi dpsi, ddT[2] = d2T/dpsi2.
void cardan_zyx_tangent_derivatives(double sin_phi, double cos_phi, double sin_psi, double cos_psi, Mat3 dT[2],
                                    Mat3 ddT[3]);

/// Cardan angles of a rotation matrix, unique for |psi| < pi/2 (B-20).
Vec3 cardan_zyx_angles(const Mat3& R);

inline double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }

}  // namespace latticedyn
