// Super truss element (thesis 3.5): the kinematic map reproduces the lattice undeformed and
// moves it rigidly under rigid motion of the end sections (no strain), the tangents match finite
// differences at deformed, moving, large-rotation states, the power identity holds, and the
// mass matrix carries the lattice's mass.
#include "elements/super_truss.hpp"

#include "element_checks.hpp"

#include <Eigen/Dense>

namespace latticedyn {
namespace {

TrussSectionSpec rectangle(int order = 3, double length = 6.0, double E = 2.06e11) {
  TrussSectionSpec s;
  s.length = length;
  s.order = order;
  s.end1 = {{1.5, 1.4}, {-1.5, 1.4}, {-1.5, -1.4}, {1.5, -1.4}};
  s.end2 = {{1.3, 1.2}, {-1.3, 1.2}, {-1.3, -1.2}, {1.3, -1.2}};  // shrinking: tapered main beams
  s.main_beams = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  s.cross_beams1 = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  s.cross_beams2 = s.cross_beams1;
  s.material = Material{7800, E, 0.25};
  s.main_section = s.cross_section = round_tube_section(0.1, 0.08);
  s.sub_section = round_tube_section(0.05, 0.04);
  return s;
}

std::vector<SlotState<double>> reference(double L) {
  std::vector<SlotState<double>> s(4);
  s[2].pos = Vec3(L, 0, 0);
  return s;
}

TEST(SuperTruss, MapReproducesTheUndeformedLattice) {
  const TrussSectionSpec spec = rectangle();
  const TrussGeometry g = build_truss_geometry(spec);
  const SuperTrussElement e(spec, g);
  std::vector<Vec3> p;
  std::vector<Mat3> R;
  e.node_poses(reference(spec.length), p, R);
  ASSERT_EQ(p.size(), g.nodes.size());
  for (std::size_t n = 0; n < p.size(); ++n) {
    EXPECT_NEAR((p[n] - g.nodes[n].position).norm(), 0.0, 1e-12) << n;
    EXPECT_NEAR((R[n] - g.nodes[n].frame).norm(), 0.0, 1e-12) << n;
  }
  const ElementEnergy en = e.energy(reference(spec.length), ElementContext{});
  EXPECT_LT(en.strain, 1e-20);
}

TEST(SuperTruss, RigidMotionHasNoStrain) {
  const TrussSectionSpec spec = rectangle();
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 Q = rotation_matrix<double>(3.0 * Vec3(u(rng), u(rng), u(rng)).normalized());
    const Vec3 c(u(rng), u(rng), u(rng));
    std::vector<SlotState<double>> s(4);
    s[0].pos = c;
    s[1].rot = Q;
    s[2].pos = c + Q * Vec3(spec.length, 0, 0);
    s[3].rot = Q;
    EXPECT_LT(e.energy(s, ElementContext{}).strain, 1e-12);
    VecX r(12);
    e.residual(s, ElementContext{}, r);
    EXPECT_LT(r.norm(), 1e-14 * spec.material.youngs_modulus * spec.main_section.area) << r.transpose();
  }
}

// A deformed state: the end sections moved and turned relative to each other (bending, torsion,
// stretch) on top of a large rigid rotation, everything moving and accelerating.
std::vector<SlotState<double>> deformed_state(std::mt19937& rng, double L) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const Mat3 Q = rotation_matrix<double>(2.5 * v3().normalized());
  const Vec3 c = v3();
  std::vector<SlotState<double>> s(4);
  s[0].pos = c;
  s[1].rot = Q * rotation_matrix<double>(0.05 * v3());
  s[2].pos = c + Q * Vec3(L * (1 + 0.01 * u(rng)), 0.05 * u(rng), 0.05 * u(rng));
  s[3].rot = Q * rotation_matrix<double>(0.05 * v3());
  for (auto& x : s) {
    x.vel = v3();
    x.acc = v3();
  }
  return s;
}

TEST(SuperTruss, TangentsMatchFiniteDifferences) {
  const TrussSectionSpec spec = rectangle(3, 6.0, 2e8);  // soft: elastic and inertial terms alike
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(42);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 3; ++trial)
    testing::expect_tangents_match_finite_differences(e, deformed_state(rng, spec.length), ctx, 1e-5);
}

TEST(SuperTruss, PowerEqualsRateOfEnergy) {
  const TrussSectionSpec spec = rectangle(3, 6.0, 2e8);
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(43);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 3; ++trial) testing::expect_power_identity(e, deformed_state(rng, spec.length), ctx);
}

TEST(SuperTruss, MassMatrixCarriesTheLatticeMass) {
  const TrussSectionSpec spec = rectangle();
  const TrussGeometry g = build_truss_geometry(spec);
  const SuperTrussElement e(spec, g);
  double mass = 0.0;
  for (const TrussMember& m : g.members) mass += spec.material.density * g.section(spec, m.kind).area * m.length;
  ElementTangents t;
  e.tangents(reference(spec.length), ElementContext{}, t);
  for (int axis = 0; axis < 3; ++axis) {
    VecX a = VecX::Zero(12);
    a(axis) = a(6 + axis) = 1.0;  // both end sections translate together
    const VecX f = t.M * a;
    EXPECT_NEAR(f(axis) + f(6 + axis), mass, 1e-9 * mass);
  }
  VecX r(12);
  e.residual(reference(spec.length), ElementContext{Vec3(0, 0, -9.81), 0.0}, r);
  EXPECT_NEAR(r(2) + r(8), 9.81 * mass, 1e-9 * mass);
}

}  // namespace
}  // namespace latticedyn
