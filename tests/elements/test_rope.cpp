// Cubic spline rope (thesis 7.2, C.5): tangents against finite differences (with a driven rest
// length), power identity, no force under rigid motion or compression (tension only), and the
// mass following the rest length in the span.
#include "elements/rope.hpp"

#include "element_checks.hpp"

namespace latticedyn {
namespace {

RopeProperties rope(double L0 = 5.0) {
  RopeProperties p;
  p.material = Material{7800.0, 1e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.02, 0.0);
  p.rest_length = L0;
  return p;
}

// A stretched, bent state: ends about 5.2 m apart, slopes longer than 1.
std::vector<SlotState<double>> taut_state(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<SlotState<double>> s(4);
  s[0].pos = v3();
  s[2].pos = s[0].pos + Vec3(5.2, 0.3 * u(rng), 0.3 * u(rng));
  s[1].pos = Vec3(1.04, 0, 0) + 0.05 * v3();
  s[3].pos = Vec3(1.04, 0, 0) + 0.05 * v3();
  for (auto& x : s) {
    x.vel = v3();
    x.acc = v3();
  }
  return s;
}

TEST(Rope, TangentsMatchFiniteDifferences) {
  std::mt19937 rng(31);
  RopeProperties p = rope();
  p.material.youngs_modulus = 1e5;  // soft: elastic and inertial terms of similar size
  const Rope cable(p);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(cable, taut_state(rng), ctx);
}

TEST(Rope, TangentsMatchFiniteDifferencesWithDrivenRestLength) {
  std::mt19937 rng(32);
  RopeProperties p = rope();
  p.material.youngs_modulus = 1e5;
  p.drive = Drive(Drive::Sine{1.0, 0.3, 0.2, 10.0});  // L0 = (10 + sin(...)) / 2, moving
  p.fraction = 0.5;
  const Rope cable(p);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.7};
  EXPECT_NE(cable.rest_length(0.7).rate, 0.0);
  EXPECT_NE(cable.rest_length(0.7).accel, 0.0);
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(cable, taut_state(rng), ctx);
}

// The taut state turned by a large rotation (up to 2.5 rad): positions, slopes and rates alike.
std::vector<SlotState<double>> rotated(std::vector<SlotState<double>> s, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
  const Mat3 R = rotation_matrix(Vec3(2.5 * std::abs(u(rng)) * axis));
  for (auto& x : s) {
    x.pos = R * x.pos;
    x.vel = R * x.vel;
    x.acc = R * x.acc;
  }
  return s;
}

// Partly slack: ends 4.9 m apart on a 5 m rope, slope stretched at one end and short and bent at
// the other, so that the Gauss points near end 1 are in tension and those near end 2 are not.
std::vector<SlotState<double>> partly_slack_state(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<SlotState<double>> s(4);
  s[0].pos = v3();
  s[2].pos = s[0].pos + Vec3(4.9, 0.1 * u(rng), 0.1 * u(rng));
  s[1].pos = Vec3(1.1, 0, 0) + 0.02 * v3();
  s[3].pos = Vec3(0.8, 0.3, 0) + 0.02 * v3();
  for (auto& x : s) {
    x.vel = v3();
    x.acc = v3();
  }
  return s;
}

TEST(Rope, TangentsMatchFiniteDifferencesAtLargeRotationsAndPartlySlack) {
  std::mt19937 rng(34);
  RopeProperties p = rope();
  p.material.youngs_modulus = 1e5;
  const Rope cable(p);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial) {
    testing::expect_tangents_match_finite_differences(cable, rotated(taut_state(rng), rng), ctx);
    testing::expect_tangents_match_finite_differences(cable, rotated(partly_slack_state(rng), rng), ctx);
  }
}

// The residual's strain energy gradient is in closed form, the tangents' by AD of the same energy:
// at steel's stiffness, taut and partly slack, they agree to round-off.
TEST(Rope, ClosedFormGradientMatchesAutomaticDifferentiation) {
  std::mt19937 rng(35);
  const Rope cable(rope());
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 20; ++trial) {
    const auto s = rotated(trial % 2 ? partly_slack_state(rng) : taut_state(rng), rng);
    VecX r(12);
    cable.residual(s, ctx, r);
    ElementTangents t;
    cable.tangents(s, ctx, t);
    ASSERT_GT(r.norm(), 1e3);  // tension of steel: the comparison is not between zeros
    EXPECT_LT((r - t.residual).cwiseAbs().maxCoeff(), 1e-13 * r.cwiseAbs().maxCoeff()) << "trial " << trial;
  }
}

TEST(Rope, RigidMotionCarriesNoForceInAnyOrientation) {
  std::mt19937 rng(35);
  const Rope cable(rope(5.0));
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<SlotState<double>> s(4);
    s[2].pos = Vec3(5.0, 0, 0);  // unstretched and straight
    s[1].pos = s[3].pos = Vec3(1, 0, 0);
    s = rotated(s, rng);
    const Vec3 shift(3 * trial, -1, 2);
    s[0].pos += shift;
    s[2].pos += shift;
    VecX r(12);
    cable.residual(s, ElementContext{}, r);
    EXPECT_LT(r.norm(), 1e-6) << trial;
    EXPECT_LT(std::abs(*cable.axial_force(s, ElementContext{})), 1e-6);  // EA = 1.3e8 N times round-off
  }
}

TEST(Rope, PowerEqualsRateOfEnergy) {
  std::mt19937 rng(33);
  RopeProperties p = rope();
  p.material.youngs_modulus = 1e5;
  const Rope cable(p);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial) testing::expect_power_identity(cable, taut_state(rng), ctx);
}

TEST(Rope, CarriesNoCompressionAndNoForceInRigidMotion) {
  const Rope cable(rope(5.0));
  std::vector<SlotState<double>> s(4);
  const Vec3 t = Vec3(0.3, -0.4, 0.866).normalized();
  s[2].pos = 5.0 * t;  // exactly the rest length: no strain
  s[1].pos = s[3].pos = t;
  VecX r(12);
  cable.residual(s, ElementContext{}, r);
  EXPECT_LT(r.norm(), 1e-6);
  EXPECT_EQ(*cable.axial_force(s, ElementContext{}), 0.0);
  // Pushed together to 80 %: compression is not carried.
  s[2].pos = 4.0 * t;
  s[1].pos = s[3].pos = 0.8 * t;
  cable.residual(s, ElementContext{}, r);
  EXPECT_LT(r.norm(), 1e-9);
  EXPECT_EQ(cable.energy(s, ElementContext{}).strain, 0.0);
  // Pulled to 101 %: tension E A 0.01.
  s[2].pos = 5.05 * t;
  s[1].pos = s[3].pos = 1.01 * t;
  const double EA = 1e11 * cable.properties().section.area;
  EXPECT_NEAR(*cable.axial_force(s, ElementContext{}), 0.01 * EA, 1e-9 * EA);
}

TEST(Rope, MassFollowsTheRestLengthInTheSpan) {
  RopeProperties p = rope();
  p.drive = Drive(Drive::TrapezoidalVelocity{0.0, 10.0, 2.0, 2.0, 20.0, 5.0});  // pay out 5 -> 25 m
  const Rope cable(p);
  const double rho_a = 7800.0 * p.section.area;
  for (double t : {0.0, 3.0, 10.0}) {
    std::vector<SlotState<double>> s(4);
    ElementTangents tg;
    cable.tangents(s, ElementContext{Vec3::Zero(), t}, tg);
    // Total translational mass: the sum of M over x-components of the two positions and slopes'
    // contribution for a rigid translation (r' fixed): e^T M e with e = x on both points.
    Eigen::VectorXd e = Eigen::VectorXd::Zero(12);
    e(0) = e(6) = 1.0;
    EXPECT_NEAR(e.dot(tg.M * e), rho_a * cable.rest_length(t).value, 1e-9) << t;
  }
  EXPECT_NEAR(cable.rest_length(10.0).value, 25.0, 1e-12);
}

}  // namespace
}  // namespace latticedyn
