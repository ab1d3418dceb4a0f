// Cubic spline beam (thesis 3.4, C.4): tangents against finite differences in large rotations,
// no strain under rigid motion, power identity, and the exact Euler-Bernoulli cantilever
// stiffness of one element (a cubic is the exact deflection under a tip force).
#include "elements/cubic_spline_beam.hpp"

#include "element_checks.hpp"

#include <Eigen/Dense>

namespace latticedyn {
namespace {

CubicSplineBeamProperties steel_tube(double L = 2.0) {
  CubicSplineBeamProperties p;
  p.beam.material = Material{7800.0, 2.06e11, 0.3, {}, 0.0};
  p.beam.section = round_tube_section(0.1, 0.08);
  p.beam.length = L;
  return p;
}

// Reference along x, moved by a large rigid motion and bent by end rotations up to `bend` rad
// (below the Cardan singularity at 90 degrees), stretched and twisted.
std::vector<SlotState<double>> deformed_state(std::mt19937& rng, double L, double bend, double rigid_angle) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const Mat3 Q = rotation_matrix<double>(rigid_angle * v3().normalized());
  const Vec3 c = 3 * v3();
  std::vector<SlotState<double>> s(6);
  s[0].pos = c;
  s[3].pos = c + Q * Vec3(L * (1 + 0.05 * u(rng)), 0.1 * L * u(rng), 0.1 * L * u(rng));
  s[1].rot = Q * rotation_matrix<double>(bend * v3());
  s[4].rot = Q * rotation_matrix<double>(bend * v3());
  s[2].pos = Vec3(1 + 0.05 * u(rng), 0, 0);
  s[5].pos = Vec3(1 + 0.05 * u(rng), 0, 0);
  for (auto& x : s) {
    x.vel = v3();
    x.acc = v3();
  }
  for (int k : {2, 5})  // scalar slots use the first component only
    for (auto* v : {&s[k].vel, &s[k].acc}) (*v)(1) = (*v)(2) = 0.0;
  return s;
}

// The unstressed reference state along x and its tangents.
ElementTangents reference_tangents(const CubicSplineBeam& beam, std::vector<SlotState<double>>& s) {
  s.assign(6, SlotState<double>{});
  s[3].pos = Vec3(beam.properties().beam.length, 0, 0);
  s[2].pos = s[5].pos = Vec3(1, 0, 0);
  ElementTangents t;
  beam.tangents(s, ElementContext{}, t);
  return t;
}

TEST(CubicSplineBeam, TangentsMatchFiniteDifferencesInLargeRotations) {
  std::mt19937 rng(31);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  CubicSplineBeamProperties p = steel_tube();
  p.beam.material.youngs_modulus = 2e6;  // soft: elastic and inertial terms of similar size
  const CubicSplineBeam beam(p);
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(beam, deformed_state(rng, 2.0, 0.4, 2.5), ctx, 2e-6);
}

TEST(CubicSplineBeam, RigidMotionHasNoStrain) {
  const CubicSplineBeam beam(steel_tube());
  std::mt19937 rng(32);
  for (int trial = 0; trial < 10; ++trial) {
    auto s = deformed_state(rng, 2.0, 0.0, 3.0);
    const Mat3 Q = s[1].rot;
    s[4].rot = Q;
    s[3].pos = s[0].pos + Q * Vec3(2.0, 0, 0);
    s[2].pos = s[5].pos = Vec3(1, 0, 0);
    for (auto& x : s) x.acc.setZero(), x.vel.setZero();
    EXPECT_LT(beam.energy(s, ElementContext{}).strain, 1e-20);
    VecX r(14);
    beam.residual(s, ElementContext{}, r);
    // Round-off of the strain at EA ~ 2e9 N.
    const double ea = beam.properties().beam.material.youngs_modulus * beam.properties().beam.section.area;
    EXPECT_LT(r.norm(), 1e-14 * ea) << r.transpose();
  }
}

TEST(CubicSplineBeam, PowerEqualsRateOfEnergy) {
  CubicSplineBeamProperties p = steel_tube();
  p.beam.material.youngs_modulus = 2e6;
  const CubicSplineBeam beam(p);
  std::mt19937 rng(33);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_power_identity(beam, deformed_state(rng, 2.0, 0.3, 2.0), ctx);
}

// Clamped at end 1 (r1, theta1 fixed; the stretch s1 stays free), loads at end 2. Euler-Bernoulli
// cantilever under a tip force P: w = P L^3/(3 EI), slope P L^2/(2 EI) (exact for a cubic);
// axial P L/(EA); torsion T L/(GJ) (linear twist).
TEST(CubicSplineBeam, CantileverStiffnessIsExact) {
  // The strain energy of a cubic Hermite axis is a polynomial of low degree in S at the reference
  // state: every Gauss order from 2 up integrates it exactly (the model's gauss_points key).
  for (int order : {2, 3, 4, 6}) {
    CubicSplineBeamProperties p = steel_tube(3.0);
    p.gauss_points = order;
    const CubicSplineBeam beam(p);
    std::vector<SlotState<double>> s;
    const ElementTangents t = reference_tangents(beam, s);
    const std::vector<int> free = {6, 7, 8, 9, 10, 11, 12, 13};
    MatX K(8, 8);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) K(i, j) = t.K(free[i], free[j]);
    const double E = p.beam.material.youngs_modulus, G = p.beam.material.shear_modulus(), L = p.beam.length;
    const double P = 1e3;
    auto solve = [&](int dof) {
      VecX f = VecX::Zero(8);
      f(dof) = P;
      return VecX(K.fullPivLu().solve(f));
    };
    SCOPED_TRACE("gauss_points " + std::to_string(order));
    const VecX uy = solve(2);  // force along y at end 2: deflection y, rotation about z
    EXPECT_NEAR(uy(2), P * L * L * L / (3 * E * p.beam.section.Iz), 1e-9 * uy(2));
    EXPECT_NEAR(uy(6), P * L * L / (2 * E * p.beam.section.Iz), 1e-9 * uy(6));
    const VecX uz = solve(3);
    EXPECT_NEAR(uz(3), P * L * L * L / (3 * E * p.beam.section.Iy), 1e-9 * uz(3));
    const VecX ux = solve(1);
    EXPECT_NEAR(ux(1), P * L / (E * p.beam.section.area), 1e-9 * ux(1));
    const VecX tx = solve(4);
    EXPECT_NEAR(tx(4), P * L / (G * p.beam.section.torsion_constant), 1e-9 * tx(4));
  }
}

// Mass: translation of the whole element at unit acceleration needs rho A L.
TEST(CubicSplineBeam, MassMatrixCarriesTheElementMass) {
  const CubicSplineBeamProperties p = steel_tube(2.5);
  const CubicSplineBeam beam(p);
  std::vector<SlotState<double>> s;
  const ElementTangents t = reference_tangents(beam, s);
  VecX a = VecX::Zero(14);
  a(1) = a(8) = 1.0;  // both ends accelerate along y, sections keep their direction
  const VecX f = t.M * a;
  EXPECT_NEAR(f(1) + f(8), p.beam.material.density * p.beam.section.area * p.beam.length, 1e-9);
  VecX r(14);
  beam.residual(s, ElementContext{Vec3(0, 0, -9.81), 0.0}, r);
  EXPECT_NEAR(r(2) + r(9), 9.81 * p.beam.material.density * p.beam.section.area * p.beam.length, 1e-9);
}

// Elements much shorter than their section (5 mm of a 0.2 m rod, 2.5 mm far from the origin): the
// stiffness and mass keep the Euler-Bernoulli Hermite values, 12 EI / L^3, 6 EI / L^2, 4 EI / L and
// 13/35 rho A L (Przemieniecki, Theory of Matrix Structural Analysis, 1968, 5.4 and 11.3), to
// round-off although stiffness and mass differ by 16 orders of magnitude.
TEST(CubicSplineBeam, ShortElementsKeepTheirStiffnessAndMass) {
  for (double L : {0.005, 0.0025}) {
    CubicSplineBeamProperties p;
    p.beam.material = Material{7800.0, 2.06e11, 0.3, {}, 0.0};
    p.beam.section = round_tube_section(0.1, 0.0);
    p.beam.length = L;
    const CubicSplineBeam beam(p);
    std::vector<SlotState<double>> s(6);
    s[0].pos = Vec3(0.5, 0, 0);
    s[3].pos = Vec3(0.5 + L, 0, 0);
    s[2].pos = s[5].pos = Vec3(1, 0, 0);
    ElementTangents t;
    beam.tangents(s, ElementContext{}, t);
    const double EI = 2.06e11 * p.beam.section.Iy, rhoAL = 7800 * p.beam.section.area * L;
    SCOPED_TRACE("L = " + std::to_string(L));
    // Slots: translation 1 (0-2), rotation 1 (3-5): bending in x-z couples z1 with the rotation about y.
    EXPECT_NEAR(t.K(2, 2), 12 * EI / (L * L * L), 1e-9 * 12 * EI / (L * L * L));
    EXPECT_NEAR(t.K(2, 4), -6 * EI / (L * L), 1e-9 * 6 * EI / (L * L));
    EXPECT_NEAR(t.K(4, 4), 4 * EI / L, 1e-8 * 4 * EI / L);
    EXPECT_NEAR(t.M(2, 2), 13.0 / 35 * rhoAL, 1e-12 * rhoAL);
    // Symmetric and positive semidefinite to round-off: six rigid motions at zero.
    EXPECT_LT((t.K - t.K.transpose()).norm(), 1e-12 * t.K.norm());
    const Eigen::SelfAdjointEigenSolver<MatX> eig(t.K);
    EXPECT_GT(eig.eigenvalues()(0), -1e-14 * t.K.norm());
    EXPECT_GT(eig.eigenvalues()(6), 1e-12 * t.K.norm());
  }
}

}  // namespace
}  // namespace latticedyn
