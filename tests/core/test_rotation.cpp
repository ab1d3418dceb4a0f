// Property tests of the rotation algebra (thesis Appendix B): orthonormality, T and dT/dt against
// finite differences of R, log(exp(phi)) = phi near 0 and pi, rescaling and Cardan angles.
#include "core/rotation.hpp"

#include "core/fast_atan2.hpp"

#include <gtest/gtest.h>
#include <unsupported/Eigen/AutoDiff>

#include <random>
#include <vector>

namespace latticedyn {
namespace {

std::vector<Vec3> sample_rotation_vectors() {
  std::vector<Vec3> out;
  std::mt19937 rng(7);
  std::normal_distribution<double> nd;
  const std::vector<double> angles = {0.0,  1e-12, 1e-8, 1e-4, 0.0999, 0.1, 0.1001, 0.5,
                                      1.0,  2.0,   3.0,  3.14, 3.1415, 3.5, 5.0,    6.0};
  for (double a : angles) {
    for (int k = 0; k < 4; ++k) {
      Vec3 n(nd(rng), nd(rng), nd(rng));
      n.normalize();
      out.push_back(a * n);
    }
  }
  return out;
}

double max_abs(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

TEST(Rotation, SkewIsCrossProductAndUnskewInvertsIt) {
  const Vec3 a(0.3, -1.2, 2.0), b(-0.7, 0.4, 1.1);
  EXPECT_LT((skew(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((unskew<double>(skew(a)) - a).norm(), 1e-15);
}

TEST(Rotation, RodriguesIsOrthonormalWithUnitDeterminant) {
  for (const Vec3& phi : sample_rotation_vectors()) {
    const Mat3 R = rotation_matrix(phi);
    EXPECT_LT(max_abs(R.transpose() * R - Mat3::Identity()), 1e-14) << phi.transpose();
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
    EXPECT_LT((R * phi - phi).norm(), 1e-14 * (1 + phi.norm())) << "axis is invariant";
  }
}

TEST(Rotation, RodriguesMatchesElementaryRotations) {
  EXPECT_LT(max_abs(rotation_matrix(Vec3(0.7, 0, 0)) - rotation_x(0.7)), 1e-15);
  EXPECT_LT(max_abs(rotation_matrix(Vec3(0, -1.3, 0)) - rotation_y(-1.3)), 1e-15);
  EXPECT_LT(max_abs(rotation_matrix(Vec3(0, 0, 2.9)) - rotation_z(2.9)), 1e-15);
}

TEST(Rotation, SeriesAndClosedFormAgreeAtTheSwitch) {
  const Vec3 n = Vec3(1, 2, -2).normalized();
  const double t = std::sqrt(rotation_detail::kSeriesBelow);
  const Vec3 below = (t * (1 - 4e-16)) * n, above = (t * (1 + 4e-16)) * n;
  EXPECT_LT(max_abs(rotation_matrix(below) - rotation_matrix(above)), 1e-14);
  EXPECT_LT(max_abs(tangent_operator(below) - tangent_operator(above)), 1e-14);
  EXPECT_LT(max_abs(tangent_operator_inverse(below) - tangent_operator_inverse(above)), 1e-14);
  const Vec3 rate(0.3, -0.2, 0.9);
  EXPECT_LT(max_abs(tangent_operator_rate(below, rate) - tangent_operator_rate(above, rate)), 1e-13);
}

// omega_body = unskew(R^T dR/dt) must equal T(phi) dphi/dt (B-8).
TEST(Rotation, TangentOperatorMatchesFiniteDifferencesOfR) {
  const Vec3 rate(0.4, -1.1, 0.7);
  const double h = 1e-6;
  for (const Vec3& phi : sample_rotation_vectors()) {
    if (phi.norm() > 6.0) continue;  // T is singular at 2 pi
    const Mat3 Rdot = (rotation_matrix<double>(phi + h * rate) - rotation_matrix<double>(phi - h * rate)) / (2 * h);
    const Vec3 omega_fd = unskew<double>(rotation_matrix(phi).transpose() * Rdot);
    const Vec3 omega = tangent_operator(phi) * rate;
    EXPECT_LT((omega - omega_fd).norm(), 1e-8) << "phi = " << phi.transpose();
  }
}

TEST(Rotation, TangentInverseIsInverse) {
  for (const Vec3& phi : sample_rotation_vectors()) {
    if (phi.norm() > 6.0) continue;
    const Mat3 P = tangent_operator(phi) * tangent_operator_inverse(phi);
    EXPECT_LT(max_abs(P - Mat3::Identity()), 1e-11) << phi.transpose();
  }
}

TEST(Rotation, TangentRateMatchesFiniteDifferencesOfT) {
  const Vec3 rate(-0.3, 0.8, 0.5);
  const double h = 1e-6;
  for (const Vec3& phi : sample_rotation_vectors()) {
    if (phi.norm() > 6.0) continue;
    const Mat3 fd = (tangent_operator<double>(phi + h * rate) - tangent_operator<double>(phi - h * rate)) / (2 * h);
    EXPECT_LT(max_abs(tangent_operator_rate(phi, rate) - fd), 1e-8) << phi.transpose();
  }
}

TEST(Rotation, AutomaticDerivativeOfRodriguesFollowsT) {
  // dR/dphi_i = R skew(T e_i): the right-trivialised derivative is the tangent operator.
  using AD = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  const Vec3 phi(0.9, -0.4, 1.7);
  Vec3T<AD> p;
  for (int i = 0; i < 3; ++i) p(i) = AD(phi(i), 3, i);
  const Mat3T<AD> R = rotation_matrix(p);
  const Mat3 R0 = rotation_matrix(phi);
  const Mat3 T = tangent_operator(phi);
  for (int i = 0; i < 3; ++i) {
    Mat3 dR;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) dR(r, c) = R(r, c).derivatives()(i);
    EXPECT_LT(max_abs(dR - R0 * skew<double>(T.col(i))), 1e-13);
  }
}

TEST(Rotation, LogMapInvertsRodrigues) {
  for (const Vec3& phi : sample_rotation_vectors()) {
    if (phi.norm() >= std::numbers::pi) continue;
    const Vec3 back = rotation_vector(rotation_matrix(phi));
    EXPECT_LT((back - phi).norm(), 1e-12 * std::max(1.0, 1.0 / std::max(1e-3, std::numbers::pi - phi.norm())))
        << phi.transpose();
  }
}

TEST(Rotation, LogMapIsRobustNearPi) {
  const Vec3 n = Vec3(0.2, -0.9, 0.4).normalized();
  for (double d : {1e-2, 1e-4, 1e-7, 1e-10, 0.0}) {
    const Vec3 phi = (std::numbers::pi - d) * n;
    const Vec3 back = rotation_vector(rotation_matrix(phi));
    EXPECT_LT(max_abs(rotation_matrix(back) - rotation_matrix(phi)), 1e-12) << d;
    EXPECT_LE(back.norm(), std::numbers::pi + 1e-12);
    if (d > 0) {
      EXPECT_LT((back - phi).norm(), 1e-6) << d;
    }
  }
}

TEST(Rotation, LogMapIsRobustNearZero) {
  for (double a : {0.0, 1e-300, 1e-16, 1e-10, 1e-5}) {
    const Vec3 phi = a * Vec3(0.6, 0.0, -0.8);
    EXPECT_LT((rotation_vector(rotation_matrix(phi)) - phi).norm(), 1e-18 + 1e-15 * a);
  }
}

TEST(Rotation, SmallRotationLogMapMatchesTheGeneralOneAndIsDifferentiable) {
  using AD = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  for (double a : {0.0, 1e-9, 1e-3, 0.0099, 0.0101, 0.3, 1.2, 1.5}) {
    const Vec3 phi = a * Vec3(0.3, -0.8, 0.52).normalized();
    const Mat3 R = rotation_matrix(phi);
    EXPECT_LT((small_rotation_vector<double>(R) - rotation_vector(R)).norm(), 1e-14 + 1e-13 * a) << a;
    // d log(R exp(d)) / d d at 0 is T(phi)^{-1}: check the AD derivative against it.
    Vec3T<AD> d;
    for (int i = 0; i < 3; ++i) d(i) = AD(0.0, 3, i);
    const Mat3T<AD> Rd = R.cast<AD>() * (Mat3T<AD>::Identity() + skew(d));
    const Vec3T<AD> p = small_rotation_vector<AD>(Rd);
    Mat3 J;
    for (int i = 0; i < 3; ++i) J.row(i) = p(i).derivatives().transpose();
    EXPECT_LT(max_abs(J - tangent_operator_inverse(phi)), 1e-10) << a;
  }
}

TEST(Rotation, RescalingKeepsTheRotationAndBoundsTheAngle) {
  for (const Vec3& phi : sample_rotation_vectors()) {
    const Vec3 r = rescaled_rotation_vector(phi);
    EXPECT_LE(r.norm(), std::numbers::pi + 1e-15);
    EXPECT_LT(max_abs(rotation_matrix(r) - rotation_matrix(phi)), 1e-13);
    if (phi.norm() <= std::numbers::pi) {
      EXPECT_EQ(r, phi);
    }
  }
  const Vec3 many_turns = (4 * std::numbers::pi + 0.3) * Vec3::UnitZ();
  EXPECT_NEAR(rescaled_rotation_vector(many_turns).z(), 0.3, 1e-12);
}

TEST(Rotation, CardanMatrixIsTheZYXSequence) {
  const Vec3 a(0.3, -0.5, 1.2);
  const Mat3 R = cardan_zyx_matrix(a);
  EXPECT_LT(max_abs(R - rotation_z(1.2) * rotation_y(-0.5) * rotation_x(0.3)), 1e-15);
  // B-16, third row: [-sin psi, sin phi cos psi, cos phi cos psi]
  EXPECT_NEAR(R(2, 0), -std::sin(-0.5), 1e-15);
  EXPECT_NEAR(R(2, 1), std::sin(0.3) * std::cos(-0.5), 1e-15);
  EXPECT_LT((cardan_zyx_angles(R) - a).norm(), 1e-14);
}

TEST(Rotation, CardanTangentAndRateMatchFiniteDifferences) {
  const Vec3 a(0.4, 0.7, -2.1), rate(0.9, -0.6, 0.3);
  const double h = 1e-6;
  const Mat3 Rdot = (cardan_zyx_matrix<double>(a + h * rate) - cardan_zyx_matrix<double>(a - h * rate)) / (2 * h);
  const Vec3 omega_fd = unskew<double>(cardan_zyx_matrix(a).transpose() * Rdot);
  EXPECT_LT((cardan_zyx_tangent(a) * rate - omega_fd).norm(), 1e-9);
  const Mat3 Tdot_fd = (cardan_zyx_tangent<double>(a + h * rate) - cardan_zyx_tangent<double>(a - h * rate)) / (2 * h);
  EXPECT_LT(max_abs(cardan_zyx_tangent_rate(a, rate) - Tdot_fd), 1e-9);
}

TEST(Rotation, CardanTangentDerivativesMatchFiniteDifferences) {
  const Vec3 a(0.4, 0.7, -2.1);
  const double h = 1e-5;
  Mat3 dT[2], ddT[3];
  cardan_zyx_tangent_derivatives(std::sin(a(0)), std::cos(a(0)), std::sin(a(1)), std::cos(a(1)), dT, ddT);
  for (int k = 0; k < 3; ++k) {  // T does not depend on theta_z
    const Vec3 e = h * Vec3::Unit(k);
    const Mat3 fd = (cardan_zyx_tangent<double>(a + e) - cardan_zyx_tangent<double>(a - e)) / (2 * h);
    EXPECT_LT(max_abs((k < 2 ? dT[k] : Mat3::Zero()) - fd), 1e-9) << k;
  }
  // Second derivatives from central differences of the first.
  auto first = [&](const Vec3& x, int k) {
    Mat3 d[2], dd[3];
    cardan_zyx_tangent_derivatives(std::sin(x(0)), std::cos(x(0)), std::sin(x(1)), std::cos(x(1)), d, dd);
    return d[k];
  };
  const Vec3 e0 = h * Vec3::UnitX(), e1 = h * Vec3::UnitY();
  EXPECT_LT(max_abs(ddT[0] - (first(a + e0, 0) - first(a - e0, 0)) / (2 * h)), 1e-9);
  EXPECT_LT(max_abs(ddT[1] - (first(a + e1, 0) - first(a - e1, 0)) / (2 * h)), 1e-9);
  EXPECT_LT(max_abs(ddT[1] - (first(a + e0, 1) - first(a - e0, 1)) / (2 * h)), 1e-9);
  EXPECT_LT(max_abs(ddT[2] - (first(a + e1, 1) - first(a - e1, 1)) / (2 * h)), 1e-9);
}

// d(T^-T m)/dphi in closed form against central differences, on both sides of the switch from the
// series of c3 to its closed form, and T^-T m without the matrix against the matrix.
TEST(Rotation, TangentInverseTransposeDerivativeMatchesFiniteDifferences) {
  const Vec3 m(0.3, -1.2, 0.8);
  for (const double size : {1e-3, 0.05, 0.11, 0.8, 2.5}) {
    const Vec3 phi = size * Vec3(0.6, -0.48, 0.64);
    EXPECT_LT((tangent_inverse_transpose_times(phi, m) - tangent_operator_inverse<double>(phi).transpose() * m).norm(), 1e-15);
    Mat3 fd;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = h * Vec3::Unit(k);
      fd.col(k) = (tangent_operator_inverse<double>(Vec3(phi + e)).transpose() * m -
                   tangent_operator_inverse<double>(Vec3(phi - e)).transpose() * m) / (2 * h);
    }
    EXPECT_LT(max_abs(tangent_inverse_transpose_derivative(phi, m) - fd), 1e-8) << "|phi| = " << size;
  }
}

// e1, e2 are the x-derivatives of d1, d2: central differences of the coefficients on either side
// of the series threshold x = 1 and across the coefficients' own threshold x = 1e-2, and the series
// meets the closed form at x = 1 (both evaluated there).
TEST(Rotation, RateCoefficientDerivativesAreDerivativesOfTheRateCoefficients) {
  // Five-point differences with a wide step (d1 and d2 themselves round off at ~1e-12 between
  // x = 1e-2 and 5e-2, which differences would amplify; there the exact values below instead).
  for (const double x : {1e-6, 5e-3, 0.5, 0.999, 1.001, 2.0, 6.0, 9.8}) {
    const double h = std::min(0.25 * x, 0.05);
    auto d = [](double y) { return rotation_detail::coefficients(y); };
    const auto p1 = d(x + h), m1 = d(x - h), p2 = d(x + 2 * h), m2 = d(x - 2 * h);
    const RateCoefficientDerivatives e = rate_coefficient_derivatives(x);
    EXPECT_NEAR(e.e1, (8 * (p1.d1 - m1.d1) - (p2.d1 - m2.d1)) / (12 * h), 1e-10) << "x = " << x;
    EXPECT_NEAR(e.e2, (8 * (p1.d2 - m1.d2) - (p2.d2 - m2.d2)) / (12 * h), 1e-10) << "x = " << x;
  }
  // 40-digit evaluations of the closed forms (mpmath): e1 = (8 cos t - 8 + 5 t sin t - t^2 cos t) / (2 t^6),
  // e2 = (t^2 sin t + 7 t cos t + 8 t - 15 sin t) / (2 t^7), t = sqrt(x).
  EXPECT_NEAR(rate_coefficient_derivatives(0.02).e1, -0.0055496058194378739885, 1e-17);
  EXPECT_NEAR(rate_coefficient_derivatives(0.02).e2, 0.00079298965843827688990, 1e-18);
  EXPECT_NEAR(rate_coefficient_derivatives(4.0).e1, -0.0044657271713418171409, 1e-16);
  EXPECT_NEAR(rate_coefficient_derivatives(4.0).e2, 0.00067059606741214036202, 1e-16);
  const RateCoefficientDerivatives below = rate_coefficient_derivatives(std::nextafter(1.0, 0.0)),
                                   at = rate_coefficient_derivatives(1.0);
  EXPECT_NEAR(below.e1, at.e1, 1e-14);
  EXPECT_NEAR(below.e2, at.e2, 1e-14);
}

// fast_atan2 is std::atan2 to the last bit or two: on its series (x > 0, |y| < x/20, up to the
// edge) and everywhere else, every quadrant and the axes.
TEST(FastAtan2, AgreesWithTheLibraryToRoundOff) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200000; ++k) {
    const double x = k % 2 ? 1.0 + u(rng) : 3.0 * u(rng);
    const double y = k % 3 ? 0.0499999 * std::abs(x) * u(rng) : 3.0 * u(rng);
    const double exact = std::atan2(y, x);
    EXPECT_LE(std::abs(fast_atan2(y, x) - exact), 4.5e-16 * std::abs(exact)) << y << " " << x;
  }
  for (double y : {0.0, -0.0, 1e-300, -1e-300}) EXPECT_EQ(fast_atan2(y, 1.0), std::atan2(y, 1.0));
  EXPECT_EQ(fast_atan2(0.0, -1.0), std::atan2(0.0, -1.0));
  EXPECT_EQ(fast_atan2(1.0, 0.0), std::atan2(1.0, 0.0));
}

}  // namespace
}  // namespace latticedyn
