// Non-template parts of the rotation algebra: the log map R -> phi, rescaling of rotation
// vectors to |phi| <= pi, and Cardan angles of a matrix.
#include "core/rotation.hpp"

#include <algorithm>
#include <initializer_list>
#include <iterator>

namespace latticedyn {

Vec3 rotation_vector(const Mat3& R) {
  // v = sin(theta) n from the skew part, cos(theta) from the trace; atan2 keeps theta accurate
  // over the whole range, where acos or asin alone lose digits near 0 or pi.
  const Vec3 v = unskew<double>(R);
  const double s = v.norm();
  const double c = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const double theta = std::atan2(s, c);
  if (theta < 1e-4) {
    // theta / sin(theta) = 1 + theta^2/6 + 7 theta^4/360 + ...
    const double t2 = theta * theta;
    return v * (1.0 + t2 / 6.0 + 7.0 * t2 * t2 / 360.0);
  }
  if (theta < std::numbers::pi - 1e-3) return v * (theta / s);
  // Near pi the skew part vanishes; the axis comes from the symmetric part
  // (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) n n^T, read off its largest column.
  const Mat3 B = 0.5 * (R + R.transpose()) - c * Mat3::Identity();
  int k = 0;
  B.diagonal().maxCoeff(&k);
  Vec3 n = B.col(k) / std::sqrt(std::max(B(k, k) * (1.0 - c), 1e-300));
  n.normalize();
  if (n.dot(v) < 0.0) n = -n;  // sin(theta) >= 0 on [0, pi]: v points along +n
  return theta * n;
}

RateCoefficientDerivatives rate_coefficient_derivatives(double x) {
  // The closed forms cancel like eps / theta^6 (e1) and eps / theta^7 (e2): their Taylor series
  // (eight terms, truncation < 1e-19 relative at x = 1) up to x = 1.
  if (x < 1.0) {
    auto horner = [x](std::initializer_list<double> c) {
      double r = 0.0;
      for (auto it = std::rbegin(c); it != std::rend(c); ++it) r = r * x + *it;
      return r;
    };
    return {horner({-1.0 / 180, 1.0 / 3360, -1.0 / 151200, 1.0 / 11975040, -1.0 / 1452971520, 1.0 / 249080832000,
                    -1.0 / 57164050944000, 1.0 / 16895152834560000}),
            horner({1.0 / 1260, -1.0 / 30240, 1.0 / 1663200, -1.0 / 155675520, 1.0 / 21794572800, -1.0 / 4234374144000,
                    1.0 / 1086116967936000, -1.0 / 354798209525760000})};
  }
  const double t = std::sqrt(x), s = std::sin(t), c = std::cos(t), t6 = x * x * x;
  return {(-x * c + 5 * t * s + 8 * c - 8) / (2 * t6), (x * s + 7 * t * c + 8 * t - 15 * s) / (2 * t6 * t)};
}

void rotation_detail::inverse_coefficient_and_derivative(double x, double* c3, double* dc3) {
  if (x < kSeriesBelow) {
    *c3 = inverse_coefficient_series(x);
    *dc3 = inverse_coefficient_derivative_series(x);
    return;
  }
  // c3 = (1 - g)/t^2 with g = t (1 + cos t) / (2 sin t), t = |phi|.
  const double t = std::sqrt(x), s = std::sin(t), c = std::cos(t);
  const double g = t * (1 + c) / (2 * s);
  const double dg = (1 + c) / (2 * s) - t * (1 + c) / (2 * s * s);
  *c3 = (1 - g) / x;
  *dc3 = (-dg / x - 2 * (1 - g) / (x * t)) / (2 * t);
}

Mat3 tangent_inverse_transpose_derivative(const Vec3& phi, const Vec3& m) {
  double c3, dc3;
  rotation_detail::inverse_coefficient_and_derivative(phi.squaredNorm(), &c3, &dc3);
  return tangent_inverse_transpose_derivative(phi, m, c3, dc3);
}

Vec3 rescaled_rotation_vector(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta <= std::numbers::pi) return phi;
  const double two_pi = 2.0 * std::numbers::pi;
  const double reduced = theta - two_pi * std::round(theta / two_pi);
  return phi * (reduced / theta);
}

void cardan_zyx_tangent_derivatives(double sf, double cf, double sp, double cp, Mat3 dT[2], Mat3 ddT[3]) {
  dT[0] << 0, 0, 0, 0, -sf, cf * cp, 0, -cf, -sf * cp;
  dT[1] << 0, 0, -cp, 0, 0, -sf * sp, 0, 0, -cf * sp;
  ddT[0] << 0, 0, 0, 0, -cf, -sf * cp, 0, sf, -cf * cp;
  ddT[1] << 0, 0, 0, 0, 0, -cf * sp, 0, 0, sf * sp;
  ddT[2] << 0, 0, sp, 0, 0, -sf * cp, 0, 0, -cf * cp;
}

Vec3 cardan_zyx_angles(const Mat3& R) {
  const double psi = -std::asin(std::clamp(R(2, 0), -1.0, 1.0));
  const double phi = std::atan2(R(2, 1), R(2, 2));
  const double theta = std::atan2(R(1, 0), R(0, 0));
  return Vec3(phi, psi, theta);
}

}  // namespace latticedyn
