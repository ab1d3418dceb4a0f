// Section forces and stresses: the closed forms of beam theory for round tubes and frames (bending
// sigma = M c / I, torsion tau = T r / J and Bredt's T / (2 A_m t), the shear maximum 2 Q / A of a
// thin tube and 4/3 Q / A of a solid round), the resultants of a co-rotational beam and a cubic
// spline beam put in the deflected shape of a cantilever under end loads (Timoshenko & Gere:
// w = P L^3/(3 EI) + P L/(kappa G A), theta = P L^2/(2 EI)), and the members of a super truss
// recovered from its coordinates.
#include "elements/cubic_spline_beam.hpp"
#include "elements/section_stress.hpp"
#include "elements/super_truss.hpp"
#include "elements/timoshenko_beam.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace latticedyn {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(SectionStress, RoundTubeBendingTorsionAndShear) {
  const double ro = 0.1, ri = 0.08;
  const SectionProperties c = round_tube_section(ro, ri);
  SectionForces f;
  f.My = 3e4;
  f.Mz = -4e4;  // resultant 5e4 N m
  SectionStress s = section_stress(c, 0.3, f);
  EXPECT_NEAR(s.normal, 5e4 * ro / c.Iy, 1e-9 * s.normal);  // the resultant moment's extreme fibre
  EXPECT_NEAR(s.von_mises, s.normal, 1e-9 * s.normal);
  f = SectionForces{};
  f.T = 2e4;
  s = section_stress(c, 0.3, f);
  EXPECT_NEAR(s.shear, 2e4 * ro / c.torsion_constant, 1e-12 * s.shear);
  EXPECT_NEAR(s.von_mises, std::sqrt(3.0) * s.shear, 1e-9 * s.shear);
  f = SectionForces{};
  f.N = -1e5;
  EXPECT_NEAR(section_stress(c, 0.3, f).normal, 1e5 / c.area, 1e-12 * 1e5 / c.area);
  // The shear force's maximum: 2 Q / A for a thin tube, 4/3 Q / A for a solid round.
  f = SectionForces{};
  f.Qz = 1e4;
  const SectionProperties thin = round_tube_section(0.1, 0.0999);
  EXPECT_NEAR(section_stress(thin, 0.3, f).shear, 2 * 1e4 / thin.area, 1e-3 * 2e4 / thin.area);
  const SectionProperties solid = round_tube_section(0.1, 0.0);
  EXPECT_NEAR(section_stress(solid, 0.3, f).shear, 4.0 / 3.0 * 1e4 / solid.area, 1e-12 * 1e4 / solid.area);
  // A shear force off the 5-degree grid of checked points (|Q| = 5e3 at -53.13 degrees): the
  // exact extreme, which the grid alone would miss by up to 1e-3.
  f = SectionForces{};
  f.Qy = 3e3;
  f.Qz = -4e3;
  EXPECT_NEAR(section_stress(solid, 0.3, f).shear, 4.0 / 3.0 * 5e3 / solid.area, 1e-12 * 5e3 / solid.area);
  // No bending and no shear force: the directions are arbitrary, the stresses those of N and T.
  f = SectionForces{};
  f.N = 1e5;
  f.T = 1e3;
  s = section_stress(c, 0.3, f);
  EXPECT_NEAR(s.normal, 1e5 / c.area, 1e-12 * 1e5 / c.area);
  EXPECT_NEAR(s.shear, 1e3 * ro / c.torsion_constant, 1e-12 * s.shear);
}

// The largest of g over the circle by brute force: every local maximum of 4,000 samples refined by
// golden-section search inside its two neighbouring intervals (g is a trigonometric polynomial of
// degree 2, smooth, with at most two maxima), to about 1e-15 of g.
template <class G>
double brute_force_maximum(const G& g) {
  constexpr int n = 4000;
  const double h = 2 * kPi / n;
  double best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double here = g(i * h);
    if (here < g((i - 1) * h) || here < g((i + 1) * h)) continue;
    double a = (i - 1) * h, b = (i + 1) * h;
    const double r = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 80; ++it) {
      const double x1 = b - r * (b - a), x2 = a + r * (b - a);
      const bool rising = g(x1) < g(x2);
      (rising ? a : b) = rising ? x1 : x2;
    }
    best = std::max({best, here, g(0.5 * (a + b))});
  }
  return best;
}

// Against a plain evaluation of the round tube's outer fibre: sigma = N/A + My z/Iy - Mz y/Iz and
// tau = T ro/J + k (Qz cos - Qy sin)/A at (y, z) = ro (cos, sin). The normal and the shear stress
// are the exact maxima over the circle (|a0| + |(a1, a2)| for a0 + a1 cos + a2 sin), and so is von
// Mises: within 1e-12 of the brute-force maximum, where the 72 points checked before 2026-12-05
// fell short by up to 1e-3. Hand-picked cases (pure bending, torsion, shear, the trust-region
// subproblem's "hard case" where b has no component along A's leading eigenvector) and 3,000
// random ones with every resultant's scale drawn over six decades.
TEST(SectionStress, RoundTubeAgainstTheFibreItself) {
  const double ro = 0.05, ri = 0.04;
  const SectionProperties c = round_tube_section(ro, ri);
  const double k = 4.0 / 3.0 * (ro * ro + ro * ri + ri * ri) / (ro * ro + ri * ri);
  std::vector<SectionForces> cases = {{1e5, 2e3, -3e3, 4e2, 7e3, 2e3},  {-2e5, -1e4, 5e3, -3e3, -1e3, 4e3},
                                      {0.0, 0.0, 0.0, 0.0, 1e4, -1e4},  {3e4, 0.0, 0.0, 5e3, 0.0, 0.0},
                                      {0.0, 5e3, 5e3, 0.0, 0.0, 0.0},    {-1e3, 0.0, 2e4, 1e3, -2e3, 0.0},
                                      {0.0, 0.0, 2e3, 1e3, 1e4, 0.0},    {0.0, 0.0, 2e3, 4e4, 1e3, 0.0},
                                      {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}};
  std::mt19937_64 rng(20261205);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), decades(0.0, 6.0);
  for (int i = 0; i < 3000; ++i) {
    auto draw = [&] { return unit(rng) * std::pow(10.0, decades(rng)); };
    cases.push_back({draw(), draw(), draw(), draw(), draw(), draw()});
  }
  double worst_grid_gap = 0.0;
  for (const SectionForces& f : cases) {
    const double s0 = f.N / c.area, s1 = -f.Mz * ro / c.Iz, s2 = f.My * ro / c.Iy;
    const double t0 = f.T * ro / c.torsion_constant, t1 = k * f.Qz / c.area, t2 = -k * f.Qy / c.area;
    auto vm2_at = [&](double phi) {
      const double sigma = s0 + s1 * std::cos(phi) + s2 * std::sin(phi), tau = t0 + t1 * std::cos(phi) + t2 * std::sin(phi);
      return sigma * sigma + 3 * tau * tau;
    };
    const double exact = std::sqrt(brute_force_maximum(vm2_at));
    double grid = 0.0;
    for (int i = 0; i < 72; ++i) grid = std::max(grid, std::sqrt(vm2_at(2 * kPi * i / 72)));
    const SectionStress s = section_stress(c, 0.3, f);
    const double scale = std::abs(s0) + std::hypot(s1, s2) + std::abs(t0) + std::hypot(t1, t2);
    EXPECT_NEAR(s.normal, std::abs(s0) + std::hypot(s1, s2), 1e-13 * scale);
    EXPECT_NEAR(s.shear, std::abs(t0) + std::hypot(t1, t2), 1e-13 * scale);
    EXPECT_NEAR(s.von_mises, exact, 1e-12 * exact) << "N " << f.N << " Qy " << f.Qy << " Qz " << f.Qz << " T " << f.T
                                                   << " My " << f.My << " Mz " << f.Mz;
    if (exact > 0) worst_grid_gap = std::max(worst_grid_gap, 1 - grid / exact);
  }
  // The cases are hard enough to tell: a grid of 72 points misses some maxima visibly.
  EXPECT_GT(worst_grid_gap, 1e-4);
}

TEST(SectionStress, FrameBendingAndBredtTorsion) {
  const double h = 0.4, b = 0.2, t = 0.01;
  const SectionProperties c = frame_section(h, b, t);
  SectionForces f;
  f.N = 2e5;
  f.My = 5e4;
  f.Mz = 1e4;
  const SectionStress s = section_stress(c, 0.3, f);
  EXPECT_NEAR(s.normal, 2e5 / c.area + 5e4 * h / 2 / c.Iy + 1e4 * b / 2 / c.Iz, 1e-9 * s.normal);  // a corner
  f = SectionForces{};
  f.T = 1e4;
  EXPECT_NEAR(section_stress(c, 0.3, f).shear, 1e4 / (2 * (b - t) * (h - t) * t), 1e-9);
}

TEST(SectionStress, UtilizationAgainstTheYieldStress) {
  Material m{7800, 2.06e11, 0.3, {}, 355e6};
  const SectionProperties c = round_tube_section(0.05, 0.04);
  SectionForces f;
  f.N = 0.5 * 355e6 * c.area;
  const MemberStress bar = bar_stress(c, m, f.N);
  EXPECT_NEAR(bar.utilization, 0.5, 1e-12);
  const MemberStress beam = member_stress(c, m, f, SectionForces{});
  EXPECT_NEAR(beam.utilization, 0.5, 1e-9);
  m.yield_stress = 0.0;
  EXPECT_TRUE(std::isnan(member_stress(c, m, f, f).utilization));
  const SectionProperties custom = custom_section(c.area, c.Iy, c.Iz, c.torsion_constant);
  EXPECT_TRUE(std::isnan(member_stress(custom, m, f, f).von_mises)) << "no fibres given: no stress";
}

// A cantilever along x loaded at its tip by F = (Fx, -Py, -Pz) and a torque T0: the section
// forces are N = Fx, Qy = -Py, Qz = -Pz, T = T0, My(s) = Pz (L - s), Mz(s) = -Py (L - s).
struct TipLoad {
  double L = 2.0, Fx = 3e2, Py = 1e2, Pz = 2e2, T0 = 5e1;
};

TEST(SectionForces, TimoshenkoBeamCantileverUnderTipLoads) {
  BeamProperties p;
  p.material = Material{7800, 2.06e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.05, 0.04);
  const TipLoad q;
  p.length = q.L;
  const TimoshenkoBeam beam(p);
  const double E = 2.06e11, G = E / 2.6, I = p.section.Iy, A = p.section.area, kappa = beam.properties().shear_coefficient;
  const double L = q.L;
  std::vector<SlotState<double>> s(4);
  // The exact end displacements and rotations of the loaded cantilever (the element is exact).
  // The chord stretched by Fx L / (E A): its length, not its x extent (the deflection shortens that).
  const double v = -(q.Py * L * L * L / (3 * E * I) + q.Py * L / (kappa * G * A));
  const double w = -(q.Pz * L * L * L / (3 * E * I) + q.Pz * L / (kappa * G * A));
  const double l = L + q.Fx * L / (E * A);
  s[2].pos = Vec3(std::sqrt(l * l - v * v - w * w), v, w);
  s[3].rot = rotation_matrix<double>(
      Vec3(q.T0 * L / (G * p.section.torsion_constant), q.Pz * L * L / (2 * E * I), -q.Py * L * L / (2 * E * I)));
  ElementOutput out;
  beam.output(s, ElementContext{}, out);
  ASSERT_EQ(out.members.size(), 1u);
  const auto& e = out.members[0].end;
  const double tol = 1e-3;  // the co-rotational frame's small rotation
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(e[k].N, q.Fx, tol * q.Fx);
    EXPECT_NEAR(e[k].Qy, -q.Py, tol * q.Py);
    EXPECT_NEAR(e[k].Qz, -q.Pz, tol * q.Pz);
    EXPECT_NEAR(e[k].T, q.T0, tol * q.T0);
  }
  EXPECT_NEAR(e[0].My, q.Pz * L, tol * q.Pz * L);
  EXPECT_NEAR(e[0].Mz, -q.Py * L, tol * q.Py * L);
  EXPECT_NEAR(e[1].My, 0.0, tol * q.Pz * L);
  EXPECT_NEAR(e[1].Mz, 0.0, tol * q.Py * L);
  // The root section's stress: the resultant moment at the outer fibre plus N/A at most.
  const double m_root = std::hypot(q.Pz, q.Py) * L;
  EXPECT_GT(out.members[0].von_mises, m_root * 0.05 / I);
  EXPECT_LT(out.members[0].von_mises, 1.01 * (m_root * 0.05 / I + q.Fx / A) + 2 * q.T0 * 0.05 / p.section.torsion_constant);
}

// The cubic spline beam in the Euler-Bernoulli deflection of the cantilever under a tip load
// -P e_z, w = -P x^2 (3 L - x) / (6 EI), which its cubic represents exactly.
TEST(SectionForces, CubicSplineBeamCantileverUnderATipLoad) {
  CubicSplineBeamProperties p;
  p.beam.material = Material{7800, 2.06e11, 0.3, {}, 0.0};
  p.beam.section = round_tube_section(0.05, 0.04);
  const double L = 2.0, P = 2e3, EI = 2.06e11 * p.beam.section.Iy;
  p.beam.length = L;
  const CubicSplineBeam beam(p);
  std::vector<SlotState<double>> s(6);
  const double slope = -P * L * L / (2 * EI);  // w'(L)
  s[3].pos = Vec3(L, 0, -P * L * L * L / (3 * EI));
  s[4].rot = rotation_matrix<double>(Vec3(0, -std::atan(slope), 0));
  s[2].pos = Vec3(1, 0, 0);
  s[5].pos = Vec3(std::sqrt(1 + slope * slope), 0, 0);  // |r'| at the tip: no stretch
  ElementOutput out;
  beam.output(s, ElementContext{}, out);
  ASSERT_EQ(out.members.size(), 1u);
  const auto& e = out.members[0].end;
  EXPECT_NEAR(e[0].My, P * L, 1e-3 * P * L);
  EXPECT_NEAR(e[1].My, 0.0, 1e-3 * P * L);
  EXPECT_NEAR(e[0].Qz, -P, 1e-3 * P);
  EXPECT_NEAR(e[0].N, 0.0, 1e-3 * P);
}

// The super truss recovers every member's resultants from its coordinates: its axial forces are
// the polylines', a rigid motion leaves every member unstressed, and a bent truss loads its chords.
TEST(SectionForces, SuperTrussRecoversItsMembers) {
  TrussSectionSpec spec = rectangular_truss_section(6.0, 3, 1.5, 1.4);
  spec.material = Material{7800, 2.06e11, 0.25, {}, 355e6};
  spec.main_section = spec.cross_section = round_tube_section(0.1, 0.08);
  spec.sub_section = round_tube_section(0.05, 0.04);
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::vector<SlotState<double>> s(4);
  const Mat3 Q = rotation_matrix<double>(Vec3(0.3, -1.1, 0.7));
  s[0].pos = Vec3(1, 2, 3);
  s[1].rot = s[3].rot = Q;
  s[2].pos = s[0].pos + Q * Vec3(6.0, 0, 0);
  ElementOutput out;
  e.output(s, ElementContext{}, out);
  ASSERT_EQ(out.members.size(), out.polylines.size());
  for (const MemberStress& m : out.members) EXPECT_LT(m.von_mises, 1e-3);  // Pa: round-off only
  s[3].rot = Q * rotation_matrix<double>(Vec3(0, 0.01, 0));  // bend about y
  e.output(s, ElementContext{}, out);
  double largest = 0.0;
  for (std::size_t m = 0; m < out.members.size(); ++m) {
    EXPECT_NEAR(out.members[m].end[0].N, out.polyline_axial_forces[m], 1e-9 * std::abs(out.polyline_axial_forces[m]) + 1e-6);
    EXPECT_NEAR(out.members[m].utilization, out.members[m].von_mises / 355e6, 1e-12);
    largest = std::max(largest, out.members[m].von_mises);
  }
  EXPECT_GT(largest, 1e6);
}

}  // namespace
}  // namespace latticedyn
