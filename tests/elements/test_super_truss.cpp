// Super truss element (thesis 3.5): the kinematic map reproduces the lattice undeformed and
// moves it rigidly under rigid motion of the end sections (no strain); the closed-form residual
// equals one computed independently (node Jacobians and the energy gradient by automatic
// differentiation of the map, node accelerations and rates from its time jets), the elastic
// tangent equals the Hessian of the members' energy through the map by second-order AD, the
// tangents match finite differences at deformed, moving, large-rotation states (inertia alone and
// together with elasticity), the power identity holds, and the mass matrix carries the lattice's mass.
#include "elements/super_truss.hpp"

#include "element_checks.hpp"
#include "elements/energy_ad.hpp"

#include <Eigen/Dense>

namespace latticedyn {
namespace {

TrussSectionSpec rectangle(int order = 3, double length = 6.0, double E = 2.06e11) {
  TrussSectionSpec s = rectangular_truss_section(length, order, 1.5, 1.4);
  s.end2 = {{1.3, 1.2}, {-1.3, 1.2}, {-1.3, -1.2}, {1.3, -1.2}};  // shrinking: tapered main beams
  s.material = Material{7800, E, 0.25, {}, 0.0};
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

// The residual from scratch, by another route than the element's: the node Jacobians by forward
// AD of the map (Dual<12>), the elastic force as the gradient of the members' energy through the
// map, the node accelerations and angular rates from time jets of the map.
VecX independent_residual(const SuperTrussElement& e, const std::vector<SlotState<double>>& s, const ElementContext& ctx) {
  const SuperTrussMap& map = e.map();
  const int nn = map.num_nodes();
  EnergyAD<12>::FirstOrder ad;
  using D = EnergyAD<12>::FirstOrder::S;
  std::vector<Vec3T<D>> pd;
  std::vector<Mat3T<D>> Rd;
  map.node_poses<D>(ad.vec(s[0].pos, 0), ad.rot(s[1].rot, 3), ad.vec(s[2].pos, 6), ad.rot(s[3].rot, 9), pd, Rd);
  std::vector<Mat312> Jp(nn), Jw(nn);
  for (int n = 0; n < nn; ++n)
    for (int j = 0; j < 12; ++j) {
      Mat3 R, dR;
      for (int a = 0; a < 3; ++a) {
        Jp[n](a, j) = pd[n](a).g[j];
        for (int b = 0; b < 3; ++b) R(a, b) = Rd[n](a, b).v, dR(a, b) = Rd[n](a, b).g[j];
      }
      Jw[n].col(j) = unskew<double>(Mat3(R.transpose() * dR));
    }
  D U(0.0);
  for (const auto& m : e.members())
    U += m.beam->strain_energy<D>(Vec3T<D>(pd[m.b] - pd[m.a]), Mat3T<D>(Rd[m.a] * m.offset_a), Mat3T<D>(Rd[m.b] * m.offset_b));
  VecX r(12);
  for (int j = 0; j < 12; ++j) r(j) = U.g[j];
  using J = Jet<double>;
  Vec3T<J> r1, r2;
  for (int i = 0; i < 3; ++i) {
    r1(i) = J(s[0].pos(i), s[0].vel(i), s[0].acc(i));
    r2(i) = J(s[2].pos(i), s[2].vel(i), s[2].acc(i));
  }
  std::vector<Vec3T<J>> pj;
  std::vector<Mat3T<J>> Rj;
  map.node_poses<J>(r1, rotation_jet<double>(s[1].rot, s[1].vel, s[1].acc), r2,
                    rotation_jet<double>(s[3].rot, s[3].vel, s[3].acc), pj, Rj);
  const auto& lm = e.lumped_mass();
  for (const auto& pr : lm.pairs) {
    Vec3 acc;
    for (int i = 0; i < 3; ++i) acc(i) = pj[pr.b](i).ddx;
    r += Jp[pr.a].transpose() * (pr.m * acc);
  }
  for (int n = 0; n < nn; ++n) {
    Vec3 w, dw;
    body_rates<double>(Rj[n], w, dw);
    r += Jw[n].transpose() * (lm.rotary[n] * dw + w.cross(lm.rotary[n] * w)) - Jp[n].transpose() * (lm.weight[n] * ctx.gravity);
  }
  return r;
}

TEST(SuperTruss, ResidualEqualsAnIndependentEvaluation) {
  const TrussSectionSpec spec = rectangle(4, 6.0, 2e8);
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(44);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 3; ++trial) {
    const auto s = deformed_state(rng, spec.length);
    VecX r(12);
    e.residual(s, ctx, r);
    const VecX ref = independent_residual(e, s, ctx);
    EXPECT_LT((r - ref).cwiseAbs().maxCoeff(), 1e-11 * ref.cwiseAbs().maxCoeff()) << r.transpose() << "\n" << ref.transpose();
  }
}

// At rest and without weight the tangent K is the elastic one: the Hessian of the members' energy
// through the map by HyperDual<12> (plus skew(g)/2 on the rotation blocks: a right perturbation).
TEST(SuperTruss, ElasticTangentEqualsSecondOrderAutomaticDifferentiation) {
  const TrussSectionSpec spec = rectangle(4);
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(45);
  for (int trial = 0; trial < 3; ++trial) {
    auto s = deformed_state(rng, spec.length);
    for (auto& x : s) x.vel.setZero(), x.acc.setZero();
    ElementTangents t;
    e.tangents(s, ElementContext{}, t);
    EnergyAD<12>::SecondOrder ad;
    using HD = EnergyAD<12>::SecondOrder::S;
    std::vector<Vec3T<HD>> p;
    std::vector<Mat3T<HD>> R;
    e.map().node_poses<HD>(ad.vec(s[0].pos, 0), ad.rot(s[1].rot, 3), ad.vec(s[2].pos, 6), ad.rot(s[3].rot, 9), p, R);
    HD U(0.0);
    for (const auto& m : e.members())
      U += m.beam->strain_energy<HD>(Vec3T<HD>(p[m.b] - p[m.a]), Mat3T<HD>(R[m.a] * m.offset_a), Mat3T<HD>(R[m.b] * m.offset_b));
    EnergyAD<12>::Gradient g;
    EnergyAD<12>::Stiffness K;
    EnergyAD<12>::extract(U, ad, nullptr, &g, &K);
    EXPECT_LT((t.residual - g).cwiseAbs().maxCoeff(), 1e-10 * g.cwiseAbs().maxCoeff());
    EXPECT_LT((t.K - K).cwiseAbs().maxCoeff(), 1e-10 * K.cwiseAbs().maxCoeff()) << t.K << "\n\n" << K;
  }
}

// A tangent at rest (statics without regularization) skips the rate terms: K must not change.
TEST(SuperTruss, TangentAtRestKeepsTheStiffness) {
  const TrussSectionSpec spec = rectangle(4);
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(47);
  auto s = deformed_state(rng, spec.length);
  for (auto& x : s) x.vel.setZero(), x.acc.setZero();
  ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  ElementTangents full, rest;
  e.tangents(s, ctx, full);
  ctx.at_rest = true;
  e.tangents(s, ctx, rest);
  EXPECT_LT((full.K - rest.K).cwiseAbs().maxCoeff(), 1e-13 * full.K.cwiseAbs().maxCoeff());
  EXPECT_LT((full.residual - rest.residual).cwiseAbs().maxCoeff(), 1e-13 * full.residual.cwiseAbs().maxCoeff());
  EXPECT_GT(full.M.cwiseAbs().maxCoeff(), 0.0);
}

// Nearly no stiffness: the tangents are the inertia's (translational and rotary, through the
// map's rotations), checked tightly against finite differences at fast, large-rotation motions.
TEST(SuperTruss, InertialTangentsMatchFiniteDifferences) {
  TrussSectionSpec spec = rectangle(4, 6.0, 1.0);
  spec.sub_section = round_tube_section(0.3, 0.1);  // thick members: rotary inertia that shows
  const SuperTrussElement e(spec, build_truss_geometry(spec));
  std::mt19937 rng(46);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  for (int trial = 0; trial < 3; ++trial) {
    auto s = deformed_state(rng, spec.length);
    for (auto& x : s) x.vel *= 3.0;
    testing::expect_tangents_match_finite_differences(e, s, ctx, 1e-7);
  }
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
