// Strut tie (thesis 3.2, C.3): tangents against finite differences (with smoothing and rotary
// inertia), power identity, zero force under rigid motion, axial force of a stretched bar,
// consistent mass and gravity load.
#include "elements/strut_tie.hpp"

#include "element_checks.hpp"

namespace latticedyn {
namespace {

StrutTieProperties sample(double h = 0.0) {
  StrutTieProperties p;
  p.material = Material{7800.0, 2.06e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.05, 0.03);
  p.rest_length = 2.0;
  p.smoothing = h;
  return p;
}

// A soft bar in random states with strains of order one, so that elastic, damping, inertial and
// gravity terms are all of similar size and each part of every tangent is exercised.
TEST(StrutTie, TangentsMatchFiniteDifferences) {
  std::mt19937 rng(11);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (double h : {0.0, 0.05}) {
    StrutTieProperties p = sample(h);
    p.material.youngs_modulus = 1e4;
    p.section = round_tube_section(0.3, 0.1);  // thick: rotary inertia matters
    const StrutTie bar(p);
    for (int trial = 0; trial < 10; ++trial)
      testing::expect_tangents_match_finite_differences(bar, testing::random_state(bar, rng, 1.5), ctx);
  }
}

// The closed-form tangents against the automatically differentiated ones, everywhere.
TEST(StrutTie, ClosedFormTangentsEqualAutomaticOnes) {
  std::mt19937 rng(17);
  const ElementContext ctx{Vec3(0.1, 0, -9.81), 0.0};
  for (double h : {0.0, 0.05}) {
    StrutTieProperties p = sample(h);
    p.material.youngs_modulus = 1e4;
    p.section = round_tube_section(0.3, 0.1);
    const StrutTie bar(p);
    for (int trial = 0; trial < 20; ++trial) {
      const auto s = testing::random_state(bar, rng, 1.5);
      ElementTangents hand, ad;
      bar.tangents(s, ctx, hand);
      bar.tangents_by_ad(s, ctx, ad);
      EXPECT_LT((hand.residual - ad.residual).norm(), 1e-12 * (1 + ad.residual.norm()));
      EXPECT_LT((hand.K - ad.K).norm(), 1e-12 * (1 + ad.K.norm())) << "K\n" << hand.K << "\nAD\n" << ad.K;
      EXPECT_LT((hand.C - ad.C).norm(), 1e-12 * (1 + ad.C.norm())) << "C\n" << hand.C << "\nAD\n" << ad.C;
      EXPECT_LT((hand.M - ad.M).norm(), 1e-12 * (1 + ad.M.norm())) << "M\n" << hand.M << "\nAD\n" << ad.M;
    }
  }
}

// Steel at realistic strains (1e-3): the stiffness dominates and must still be exact.
TEST(StrutTie, TangentsMatchFiniteDifferencesForSteel) {
  std::mt19937 rng(13);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  const StrutTie bar(sample(1e-3));
  for (int trial = 0; trial < 10; ++trial) {
    auto s = testing::random_state(bar, rng, 1.0);
    const Vec3 n = (s[1].pos - s[0].pos).normalized();
    s[1].pos = s[0].pos + 2.0 * (1 + 1e-3) * n;
    testing::expect_tangents_match_finite_differences(bar, s, ctx, 1e-5);
  }
}

TEST(StrutTie, PowerEqualsRateOfEnergyWithoutSmoothing) {
  // A soft bar so that strain, kinetic and gravity energies are of similar size.
  StrutTieProperties p = sample();
  p.material.youngs_modulus = 1e3;
  const StrutTie bar(p);
  std::mt19937 rng(12);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial) testing::expect_power_identity(bar, testing::random_state(bar, rng, 1.5), ctx);
}

TEST(StrutTie, RigidMotionCarriesNoForce) {
  const StrutTie bar(sample(1e-3));
  std::vector<SlotState<double>> s(2);
  const Mat3 R = rotation_matrix<double>(Vec3(0.4, -1.2, 2.5));
  const Vec3 c(3, -1, 2), w(0.7, -0.3, 1.1), v0(0.5, 0.2, -0.4);
  const Vec3 x1 = R * Vec3(-1, 0, 0), x2 = R * Vec3(1, 0, 0);  // length 2 = rest length
  s[0].pos = c + x1;
  s[1].pos = c + x2;
  s[0].vel = v0 + w.cross(x1);  // rigid velocity field
  s[1].vel = v0 + w.cross(x2);
  s[0].acc = w.cross(w.cross(x1));  // steady rotation: centripetal accelerations
  s[1].acc = w.cross(w.cross(x2));
  const auto N = bar.axial_force(s, ElementContext{});
  ASSERT_TRUE(N.has_value());
  EXPECT_NEAR(*N, 0.0, 1e-3);  // N; EA = 1e9 N, so a strain of 1e-12
}

TEST(StrutTie, StretchedBarPullsItsEndsTogether) {
  const StrutTieProperties p = sample();
  const StrutTie bar(p);
  std::vector<SlotState<double>> s(2);
  const double stretch = 1e-4;  // strain
  s[1].pos = Vec3(0, 0, p.rest_length * (1 + stretch));
  VecX r(6);
  bar.residual(s, ElementContext{}, r);
  const double N = p.material.youngs_modulus * p.section.area * stretch;
  EXPECT_NEAR(r(2), -N, 1e-9 * N);  // residual r = ... - N n on end 1 (n from 1 to 2)
  EXPECT_NEAR(r(5), N, 1e-9 * N);
  EXPECT_NEAR(*bar.axial_force(s, ElementContext{}), N, 1e-9 * N);
}

TEST(StrutTie, ConsistentMassAndGravityLoad) {
  const StrutTieProperties p = sample();
  const StrutTie bar(p);
  std::vector<SlotState<double>> s(2);
  s[1].pos = Vec3(p.rest_length, 0, 0);
  const Vec3 g(0, 0, -9.81);
  ElementTangents t;
  bar.tangents(s, ElementContext{g, 0.0}, t);
  const double m = p.material.density * p.section.area * p.rest_length;
  EXPECT_NEAR(t.M(0, 0), m / 3, 1e-12 * m);  // rho A L/6 * 2 (C-82)
  EXPECT_NEAR(t.M(0, 3), m / 6, 1e-12 * m);
  EXPECT_NEAR(t.residual(2), 0.5 * m * 9.81, 1e-9 * m);  // -F_ext,g (C-86): half the weight per end
  EXPECT_NEAR(t.residual(5), 0.5 * m * 9.81, 1e-9 * m);
  // Rotary inertia of the sections about the axis' normals: rho I L on the transverse DoFs.
  const double rot = p.material.density * p.section.Iy * p.rest_length / (p.rest_length * p.rest_length);
  EXPECT_NEAR(t.M(1, 1), m / 3 + rot, 1e-9 * m);
}

TEST(StrutTie, RejectsMeaninglessParameters) {
  StrutTieProperties p = sample();
  p.rest_length = 0.0;
  EXPECT_THROW(StrutTie{p}, std::invalid_argument);
  p = sample();
  p.smoothing = -1.0;
  EXPECT_THROW(StrutTie{p}, std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
