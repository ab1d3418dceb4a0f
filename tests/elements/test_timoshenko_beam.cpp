// Co-rotational Timoshenko beam (thesis 3.3, C.2): tangents against finite differences in large
// rotations, no strain under rigid motion, power identity, and the exact linear stiffness of a
// thick cantilever (bending plus shear, Timoshenko 1921) that the thesis's GA/4 would miss.
#include "elements/timoshenko_beam.hpp"

#include "element_checks.hpp"
#include "elements/energy_ad.hpp"

#include <Eigen/Dense>

namespace latticedyn {
namespace {

BeamProperties steel_tube(double L = 2.0) {
  BeamProperties p;
  p.material = Material{7800.0, 2.06e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.1, 0.08);
  p.length = L;
  return p;
}

// A state near the reference (axis along x, frames = identity) moved by a large rigid motion and
// deformed by end rotations of up to `twist` rad and a stretch.
std::vector<SlotState<double>> deformed_state(std::mt19937& rng, double L, double twist, double rigid_angle) {
  std::uniform_real_distribution<double> u(-1, 1);
  auto v3 = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const Mat3 Q = rotation_matrix<double>(rigid_angle * v3().normalized());
  const Vec3 c = 3 * v3();
  std::vector<SlotState<double>> s(4);
  s[0].pos = c;
  s[2].pos = c + Q * Vec3(L * (1 + 0.05 * u(rng)), 0.1 * L * u(rng), 0.1 * L * u(rng));
  s[1].rot = Q * rotation_matrix<double>(twist * v3());
  s[3].rot = Q * rotation_matrix<double>(twist * v3());
  for (auto& x : s) {
    x.vel = v3();
    x.acc = v3();
  }
  return s;
}

TEST(TimoshenkoBeam, TangentsMatchFiniteDifferencesInLargeRotations) {
  std::mt19937 rng(21);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  BeamProperties p = steel_tube();
  p.material.youngs_modulus = 2e6;  // soft: elastic and inertial terms of similar size
  const TimoshenkoBeam beam(p);
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(beam, deformed_state(rng, 2.0, 0.4, 2.5), ctx, 2e-6);
}

// The closed-form force and tangent (corotational_force) against the gradient and the Hessian of
// the same strain energy by second-order automatic differentiation (EnergyAD: Hessian plus
// skew(g)/2 on the rotation blocks), on stiff steel and at local rotations of up to about 1 rad,
// where the log map and T^-1 leave their series.
TEST(TimoshenkoBeam, ClosedFormTangentEqualsAutomaticDifferentiation) {
  std::mt19937 rng(24);
  for (const double twist : {0.01, 0.3, 0.9}) {
    const TimoshenkoBeam beam(steel_tube());
    for (int trial = 0; trial < 10; ++trial) {
      const auto s = deformed_state(rng, 2.0, twist, 2.5);
      const Vec3 d = s[2].pos - s[0].pos;
      Vec9 f;
      Mat9 K;
      beam.elastic_force(d, s[1].rot, s[3].rot, f, &K);
      EnergyAD<9>::SecondOrder ad;
      const auto U = beam.strain_energy<EnergyAD<9>::SecondOrder::S>(ad.vec(d, 0), ad.rot(s[1].rot, 3), ad.rot(s[3].rot, 6));
      EnergyAD<9>::Gradient g;
      EnergyAD<9>::Stiffness Kad;
      EnergyAD<9>::extract(U, ad, nullptr, &g, &Kad);
      EXPECT_LT((f - g).cwiseAbs().maxCoeff(), 1e-11 * g.cwiseAbs().maxCoeff()) << "twist " << twist;
      EXPECT_LT((K - Kad).cwiseAbs().maxCoeff(), 1e-10 * Kad.cwiseAbs().maxCoeff())
          << "twist " << twist << "\nclosed form:\n" << K << "\nAD:\n" << Kad;
    }
  }
}

TEST(TimoshenkoBeam, RigidMotionHasNoStrain) {
  const TimoshenkoBeam beam(steel_tube());
  std::mt19937 rng(22);
  for (int trial = 0; trial < 10; ++trial) {
    auto s = deformed_state(rng, 2.0, 0.0, 3.0);
    // Undo the stretch and offsets: a pure rigid motion of the reference.
    const Mat3 Q = s[1].rot;
    s[3].rot = Q;
    s[2].pos = s[0].pos + Q * Vec3(2.0, 0, 0);
    for (auto& x : s) x.acc.setZero(), x.vel.setZero();
    const ElementEnergy e = beam.energy(s, ElementContext{});
    EXPECT_LT(e.strain, 1e-20);
    VecX r(12);
    beam.residual(s, ElementContext{}, r);
    EXPECT_LT(r.norm(), 1e-6) << r.transpose();
  }
}

TEST(TimoshenkoBeam, PowerEqualsRateOfEnergy) {
  BeamProperties p = steel_tube();
  p.material.youngs_modulus = 2e6;
  const TimoshenkoBeam beam(p);
  std::mt19937 rng(23);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 10; ++trial) testing::expect_power_identity(beam, deformed_state(rng, 2.0, 0.3, 2.0), ctx);
}

// Batches of one to four beams of different sections and lengths (a lattice's members, evaluated
// on the lanes of Pack4) give each beam's own residual and tangents to round-off, near the
// reference (the log map's series) and at large local rotations (its closed form).
TEST(TimoshenkoBeam, BatchEqualsSingleEvaluations) {
  std::mt19937 rng(5);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  std::vector<TimoshenkoBeam> beams;
  for (int k = 0; k < 4; ++k) {
    BeamProperties p = steel_tube(1.5 + 0.5 * k);
    p.section = round_tube_section(0.05 + 0.02 * k, 0.04);
    beams.emplace_back(p);
  }
  for (const double twist : {1e-4, 0.8})
    for (int count = 1; count <= 4; ++count) {
      std::vector<std::vector<SlotState<double>>> states;
      std::vector<const Element*> elements;
      std::vector<std::span<const SlotState<double>>> spans;
      for (int k = 0; k < count; ++k) states.push_back(deformed_state(rng, beams[k].properties().length, twist, 2.0));
      for (int k = 0; k < count; ++k) {
        elements.push_back(&beams[k]);
        spans.emplace_back(states[k]);
      }
      std::vector<VecX> residuals(count);
      std::vector<ElementTangents> tangents(count);
      beams[0].residual_batch(elements, spans, ctx, residuals);
      beams[0].tangents_batch(elements, spans, ctx, tangents);
      for (int k = 0; k < count; ++k) {
        VecX r(12);
        ElementTangents t;
        beams[k].residual(states[k], ctx, r);
        beams[k].tangents(states[k], ctx, t);
        const double scale = t.K.cwiseAbs().maxCoeff();
        EXPECT_LT((residuals[k] - r).cwiseAbs().maxCoeff(), 1e-12 * r.cwiseAbs().maxCoeff()) << count << " " << k;
        EXPECT_LT((tangents[k].residual - r).cwiseAbs().maxCoeff(), 1e-12 * r.cwiseAbs().maxCoeff());
        EXPECT_LT((tangents[k].K - t.K).cwiseAbs().maxCoeff(), 1e-12 * scale) << count << " " << k;
        EXPECT_EQ(tangents[k].C, t.C);
        EXPECT_EQ(tangents[k].M, t.M);
      }
    }
}

// Linear stiffness of one element clamped at end 1, tip force P across the axis:
// w = P L^3 / (3 E I) + P L / (kappa G A) (Timoshenko beam theory; e.g. Gere & Timoshenko,
// Mechanics of Materials, shear deflection of a cantilever). Thick beam: L = 5 h.
TEST(TimoshenkoBeam, ThickCantileverDeflectionIncludesShear) {
  BeamProperties p;
  p.material = Material{7800.0, 2.0e11, 0.3, {}, 0.0};
  p.section = round_tube_section(0.2, 0.0);
  p.length = 1.0;  // L / (2 r) = 2.5: shear matters
  const TimoshenkoBeam beam(p);
  std::vector<SlotState<double>> s(4);
  s[2].pos = Vec3(p.length, 0, 0);
  ElementTangents t;
  beam.tangents(s, ElementContext{}, t);
  const Eigen::Matrix<double, 6, 6> K22 = t.K.block<6, 6>(6, 6);
  Eigen::Matrix<double, 6, 1> f = Eigen::Matrix<double, 6, 1>::Zero();
  const double P = 1e3;
  f(1) = P;  // along y
  const Eigen::Matrix<double, 6, 1> u = K22.lu().solve(f);
  const double E = p.material.youngs_modulus, G = p.material.shear_modulus(), I = p.section.Iz, A = p.section.area;
  const double kappa = p.section.shear_coefficient(0.3);
  const double bending = P * std::pow(p.length, 3) / (3 * E * I), shear = P * p.length / (kappa * G * A);
  EXPECT_NEAR(u(1), bending + shear, 1e-9 * (bending + shear));
  EXPECT_GT(shear, 0.05 * bending) << "the case must be thick enough to tell the shear models apart";
  // The thesis's shear stiffness G A / 4 (design notes) would give four times the shear deflection.
  EXPECT_GT(std::abs(bending + 4 * shear - u(1)), 100 * 1e-9 * (bending + shear));
  // Axial and torsional stiffness.
  f.setZero();
  f(0) = P;
  EXPECT_NEAR(K22.lu().solve(f)(0), P * p.length / (E * A), 1e-12);
  f.setZero();
  f(3) = P;
  EXPECT_NEAR(K22.lu().solve(f)(3), P * p.length / (G * p.section.torsion_constant), 1e-12);
}

}  // namespace
}  // namespace latticedyn
