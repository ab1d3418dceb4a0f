// Rigid body (thesis 3.1, C.1): tangents against finite differences, symmetric positive definite
// mass matrix of the thesis's form (C-3), power identity, free fall, cylinder mass properties.
#include "elements/rigid_body.hpp"

#include "element_checks.hpp"

#include <numbers>

namespace latticedyn {
namespace {

RigidBodyProperties sample_properties() {
  RigidBodyProperties p;
  p.mass = 12.5;
  p.centroid = Vec3(0.4, -0.2, 0.7);
  p.inertia_centroid << 3.0, 0.2, -0.1,  //
      0.2, 2.5, 0.3,                       //
      -0.1, 0.3, 4.0;
  return p;
}

TEST(RigidBody, TangentsMatchFiniteDifferences) {
  const RigidBody body(sample_properties());
  std::mt19937 rng(1);
  const ElementContext ctx{Vec3(0.3, -0.2, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(body, testing::random_state(body, rng, 5.0), ctx);
}

TEST(RigidBody, MassMatrixIsSymmetricPositiveDefiniteOfThesisForm) {
  const RigidBodyProperties p = sample_properties();
  const RigidBody body(p);
  std::mt19937 rng(2);
  const auto s = testing::random_state(body, rng);
  ElementTangents t;
  body.tangents(s, ElementContext{}, t);
  EXPECT_LT((t.M - t.M.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(t.M).eigenvalues().minCoeff(), 0.0);
  // (C-3): [m I, -m R c~; m c~ R^T, Theta_0]
  const Mat3& R = s[1].rot;
  EXPECT_LT((t.M.topLeftCorner<3, 3>() - p.mass * Mat3::Identity()).norm(), 1e-12);
  EXPECT_LT((t.M.topRightCorner<3, 3>() + p.mass * R * skew<double>(p.centroid)).norm(), 1e-12);
  EXPECT_LT((t.M.bottomRightCorner<3, 3>() - body.inertia_origin()).norm(), 1e-12);
}

TEST(RigidBody, PowerEqualsRateOfEnergy) {
  const RigidBody body(sample_properties());
  std::mt19937 rng(3);
  const ElementContext ctx{Vec3(0.0, 0.0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial) testing::expect_power_identity(body, testing::random_state(body, rng, 3.0), ctx);
}

TEST(RigidBody, FreeFallHasZeroResidual) {
  const RigidBody body(sample_properties());
  std::vector<SlotState<double>> s(2);
  s[1].rot = rotation_matrix<double>(Vec3(0.3, 1.0, -2.0));
  const Vec3 g(0, 0, -9.81);
  s[0].acc = g;
  s[0].vel = Vec3(1, 2, 3);
  VecX r(6);
  body.residual(s, ElementContext{g, 0.0}, r);
  EXPECT_LT(r.norm(), 1e-12);
}

TEST(RigidBody, RejectsUnphysicalMassProperties) {
  RigidBodyProperties p = sample_properties();
  p.mass = -1;
  EXPECT_THROW(RigidBody{p}, std::invalid_argument);
  p = sample_properties();
  p.inertia_centroid = Vec3(1.0, 1.0, 3.0).asDiagonal();  // 1 + 1 < 3
  EXPECT_THROW(RigidBody{p}, std::invalid_argument);
}

// Table D-12: "round tube" load of length 2 and radius 2.82095 weighs about 390 t in steel.
TEST(RigidBody, CylinderMassPropertiesMatchClosedForm) {
  const RigidBodyProperties p = cylinder_body(7800, 2.0, 2.82095, 0.0);
  EXPECT_NEAR(p.mass, 390000.0, 100.0);
  EXPECT_NEAR(p.centroid.x(), 1.0, 1e-15);
  EXPECT_NEAR(p.inertia_centroid(0, 0), 0.5 * p.mass * 2.82095 * 2.82095, 1e-6 * p.mass);
  EXPECT_NEAR(p.inertia_centroid(1, 1), p.mass * (3 * 2.82095 * 2.82095 + 4.0) / 12, 1e-6 * p.mass);
}

}  // namespace
}  // namespace latticedyn
