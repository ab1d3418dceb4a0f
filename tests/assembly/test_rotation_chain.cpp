// The rotation-vector chain rule against central finite differences: omega = T(phi) phi_dot and
// omega_dot = T phi_ddot + T_dot phi_dot with their derivatives P, Q, S, and d(T^T y)/dphi, for
// small rotations (series coefficients) and large ones (closed forms).
#include "assembly/rotation_chain.hpp"

#include "core/rotation.hpp"

#include <gtest/gtest.h>

namespace latticedyn {
namespace {

struct Rates {
  Vec3 omega, omega_dot;
};

Rates rates(const Vec3& phi, const Vec3& phi_dot, const Vec3& phi_ddot) {
  const Mat3 T = tangent_operator(phi);
  return {T * phi_dot, T * phi_ddot + tangent_operator_rate(phi, phi_dot) * phi_dot};
}

class RotationChainTest : public ::testing::TestWithParam<double> {};

TEST_P(RotationChainTest, DerivativesEqualFiniteDifferences) {
  const double scale = GetParam();
  const Vec3 phi = scale * Vec3(0.8, -0.5, 0.35), phi_dot(0.7, 1.3, -0.4), phi_ddot(-2.0, 0.5, 1.1);
  const Mat3 R_ref = rotation_matrix(Vec3(0.2, 0.1, -0.3));
  const RotationChain c = rotation_chain(R_ref, phi, phi_dot, phi_ddot, true);
  const Rates r = rates(phi, phi_dot, phi_ddot);
  EXPECT_LT((c.R - R_ref * rotation_matrix(phi)).norm(), 1e-15);
  EXPECT_LT((c.T - tangent_operator(phi)).norm(), 1e-15);
  EXPECT_LT((c.omega - r.omega).norm(), 1e-14);
  EXPECT_LT((c.omega_dot - r.omega_dot).norm(), 1e-13);
  const double h = 1e-6;
  Mat3 P, Q, S;
  for (int j = 0; j < 3; ++j) {
    const Vec3 e = h * Vec3::Unit(j);
    const Rates p = rates(phi + e, phi_dot, phi_ddot), m = rates(phi - e, phi_dot, phi_ddot);
    P.col(j) = (p.omega - m.omega) / (2 * h);
    Q.col(j) = (p.omega_dot - m.omega_dot) / (2 * h);
    const Rates pv = rates(phi, phi_dot + e, phi_ddot), mv = rates(phi, phi_dot - e, phi_ddot);
    S.col(j) = (pv.omega_dot - mv.omega_dot) / (2 * h);
  }
  EXPECT_LT((c.P - P).norm(), 1e-8 * (1 + P.norm()));
  EXPECT_LT((c.Q - Q).norm(), 1e-8 * (1 + Q.norm()));
  EXPECT_LT((c.S - S).norm(), 1e-8 * (1 + S.norm()));
  // Residual-only evaluations give the same values without derivatives.
  const RotationChain v = rotation_chain(R_ref, phi, phi_dot, phi_ddot, false);
  EXPECT_LT((v.R - c.R).norm(), 1e-15);
  EXPECT_LT((v.omega_dot - c.omega_dot).norm(), 1e-13);
  EXPECT_EQ(v.Q.norm(), 0.0);

  const Vec3 y(3.0, -1.0, 2.0);
  Mat3 Y;
  for (int j = 0; j < 3; ++j) {
    const Vec3 e = h * Vec3::Unit(j);
    Y.col(j) = (tangent_operator(Vec3(phi + e)).transpose() * y - tangent_operator(Vec3(phi - e)).transpose() * y) / (2 * h);
  }
  EXPECT_LT((tangent_transpose_derivative(phi, y) - Y).norm(), 1e-8 * (1 + Y.norm()));
}

// 0.05: |phi|^2 below the series threshold; 1 and 3: closed forms, up to |phi| = 3.1.
INSTANTIATE_TEST_SUITE_P(Angles, RotationChainTest, ::testing::Values(0.05, 1.0, 3.0));

}  // namespace
}  // namespace latticedyn
