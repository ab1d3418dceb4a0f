// Rayleigh damping of every element type (alpha M + beta K on the deformation rates): the damping
// part of each residual has tangents that match finite differences, vanishes under rigid motion
// of a prestressed element (beta), dissipates power, and at the unstressed reference equals the
// linear alpha M + beta K (Chopra, Dynamics of Structures, 11.4); the coefficients from damping
// ratios reproduce those ratios.
#include "elements/cubic_spline_beam.hpp"
#include "elements/rayleigh_damping.hpp"
#include "elements/rigid_body.hpp"
#include "elements/rope.hpp"
#include "elements/strut_tie.hpp"
#include "elements/super_truss.hpp"
#include "elements/timoshenko_beam.hpp"

#include "element_checks.hpp"

#include <memory>

namespace latticedyn {
namespace {

// The damping part of an element: residual and tangents of the damped element minus those of
// the same element undamped.
class DampingPart final : public Element {
 public:
  DampingPart(std::shared_ptr<const Element> damped, std::shared_ptr<const Element> plain)
      : damped_(std::move(damped)), plain_(std::move(plain)) {}
  std::string_view type_name() const override { return "damping part"; }
  std::span<const SlotKind> slots() const override { return damped_->slots(); }
  void residual(std::span<const SlotState<double>> s, const ElementContext& ctx, Eigen::Ref<VecX> r) const override {
    VecX a(num_dofs()), b(num_dofs());
    damped_->residual(s, ctx, a);
    plain_->residual(s, ctx, b);
    r = a - b;
  }
  void tangents(std::span<const SlotState<double>> s, const ElementContext& ctx, ElementTangents& out) const override {
    ElementTangents b;
    damped_->tangents(s, ctx, out);
    plain_->tangents(s, ctx, b);
    out.residual -= b.residual;
    out.K -= b.K;
    out.C -= b.C;
    out.M -= b.M;
  }
  ElementEnergy energy(std::span<const SlotState<double>>, const ElementContext&) const override { return {}; }

 private:
  std::shared_ptr<const Element> damped_, plain_;
};

template <class E, class P>
DampingPart damping_part(P props, RayleighDamping d, Material P::*material) {
  P plain = props;
  (props.*material).damping = d;
  return DampingPart(std::make_shared<E>(props), std::make_shared<E>(plain));
}

BeamProperties soft_tube() {
  BeamProperties p;
  p.material = Material{7800.0, 2e6, 0.3, {}, 0.0};  // soft: damping, elastic and inertial terms alike
  p.section = round_tube_section(0.1, 0.08);
  p.length = 2.0;
  return p;
}

std::mt19937 rng(7);
double uniform() { return std::uniform_real_distribution<double>(-1, 1)(rng); }
Vec3 v3() { return Vec3(uniform(), uniform(), uniform()); }

// A deformed two-frame state (beam-like slots [r1, R1, r2, R2]) moved by a large rigid motion.
std::vector<SlotState<double>> beam_state(double L) {
  const Mat3 Q = rotation_matrix<double>(2.0 * v3());
  std::vector<SlotState<double>> s(4);
  s[0].pos = v3();
  s[2].pos = s[0].pos + Q * Vec3(L * (1 + 0.05 * uniform()), 0.1 * L * uniform(), 0.1 * L * uniform());
  s[1].rot = Q * rotation_matrix<double>(0.3 * v3());
  s[3].rot = Q * rotation_matrix<double>(0.3 * v3());
  for (auto& x : s) x.vel = v3(), x.acc = v3();
  return s;
}

std::vector<SlotState<double>> spline_state(double L) {
  const std::vector<SlotState<double>> b = beam_state(L);
  std::vector<SlotState<double>> s(6);
  s[0] = b[0], s[1] = b[1], s[3] = b[2], s[4] = b[3];
  for (int k : {2, 5}) {
    s[k].pos = Vec3(1 + 0.05 * uniform(), 0, 0);
    s[k].vel = Vec3(uniform(), 0, 0);
    s[k].acc = Vec3(uniform(), 0, 0);
  }
  return s;
}

std::vector<SlotState<double>> rope_state() {
  std::vector<SlotState<double>> s(4);
  s[0].pos = v3();
  s[2].pos = s[0].pos + Vec3(5.2, 0.3 * uniform(), 0.3 * uniform());
  s[1].pos = Vec3(1.04, 0, 0) + 0.05 * v3();
  s[3].pos = Vec3(1.04, 0, 0) + 0.05 * v3();
  for (auto& x : s) x.vel = v3(), x.acc = v3();
  return s;
}

// Rates of a rigid motion (velocity v0 at the origin, angular velocity w) of the state's
// configuration: points move with v0 + w x r, frames turn with R^T w, free vectors with w x a.
void rigid_rates(const Element& e, std::vector<SlotState<double>>& s) {
  const Vec3 v0 = v3(), w = v3();
  const auto kinds = e.slots();
  for (std::size_t k = 0; k < s.size(); ++k) {
    switch (kinds[k]) {
      case SlotKind::translation: s[k].vel = v0 + w.cross(s[k].pos); break;
      case SlotKind::rotation: s[k].vel = s[k].rot.transpose() * w; break;
      case SlotKind::vector: s[k].vel = w.cross(s[k].pos); break;
      case SlotKind::scalar: s[k].vel.setZero(); break;
    }
  }
}

const ElementContext kContext{Vec3(0, 0, -9.81), 0.3};

TEST(Damping, TimoshenkoBeamTangentsMatchFiniteDifferences) {
  const DampingPart part = damping_part<TimoshenkoBeam>(soft_tube(), {0.7, 0.02}, &BeamProperties::material);
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(part, beam_state(2.0), kContext, 2e-6);
}

TEST(Damping, CubicSplineBeamTangentsMatchFiniteDifferences) {
  CubicSplineBeamProperties p;
  p.beam = soft_tube();
  CubicSplineBeamProperties damped = p;
  damped.beam.material.damping = {0.7, 0.02};
  const DampingPart part(std::make_shared<CubicSplineBeam>(damped), std::make_shared<CubicSplineBeam>(p));
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(part, spline_state(2.0), kContext, 2e-6);
}

TEST(Damping, RopeTangentsMatchFiniteDifferencesWithDrivenRestLength) {
  RopeProperties p;
  p.material = Material{7800.0, 1e5, 0.3, {}, 0.0};
  p.section = round_tube_section(0.02, 0.0);
  p.drive = Drive(Drive::Sine{1.0, 0.3, 0.2, 10.0});  // L0 moving: eps_dot has a drive part
  p.fraction = 0.5;
  const DampingPart part = damping_part<Rope>(p, {0.0, 0.05}, &RopeProperties::material);
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(part, rope_state(), kContext, 2e-6);
}

TEST(Damping, StrutTieTangentsMatchFiniteDifferencesAndAutomaticOnes) {
  StrutTieProperties p;
  p.material = Material{7800.0, 1e4, 0.3, {}, 0.0};
  p.section = round_tube_section(0.3, 0.1);  // thick: the rotary part of alpha M v matters
  p.rest_length = 2.0;
  p.smoothing = 0.05;
  const DampingPart part = damping_part<StrutTie>(p, {0.7, 0.05}, &StrutTieProperties::material);
  p.material.damping = {0.7, 0.05};
  const StrutTie bar(p);
  for (int trial = 0; trial < 10; ++trial) {
    const auto s = testing::random_state(bar, rng, 1.5);
    testing::expect_tangents_match_finite_differences(part, s, kContext, 2e-6);
    ElementTangents closed, ad;
    bar.tangents(s, kContext, closed);
    bar.tangents_by_ad(s, kContext, ad);
    EXPECT_LT((closed.K - ad.K).cwiseAbs().maxCoeff(), 1e-9 * ad.K.cwiseAbs().maxCoeff());
    EXPECT_LT((closed.C - ad.C).cwiseAbs().maxCoeff(), 1e-9 * ad.C.cwiseAbs().maxCoeff());
    EXPECT_LT((closed.residual - ad.residual).cwiseAbs().maxCoeff(), 1e-9 * ad.residual.cwiseAbs().maxCoeff());
  }
}

TrussSectionSpec soft_truss(RayleighDamping d = {}) {
  TrussSectionSpec ts = rectangular_truss_section(6.0, 3, 1.5, 1.4);
  ts.material = Material{7800, 2e7, 0.25, d, 0.0};  // soft: damping, elastic and inertial forces alike
  ts.main_section = ts.cross_section = round_tube_section(0.1, 0.08);
  ts.sub_section = round_tube_section(0.05, 0.04);
  return ts;
}

DampingPart super_truss_part(RayleighDamping d) {
  const TrussSectionSpec damped = soft_truss(d), plain = soft_truss();
  return DampingPart(std::make_shared<SuperTrussElement>(damped, build_truss_geometry(damped)),
                     std::make_shared<SuperTrussElement>(plain, build_truss_geometry(plain)));
}

// A super truss damps each member's co-rotated deformation rates (beta) and its motion (alpha)
// through its map: the damping part's tangents against finite differences at deformed, moving,
// large-rotation states; beta leaves rigid motion of the bent truss alone; at rest alpha's
// damping matrix is alpha times the element's mass matrix.
TEST(Damping, SuperTrussTangentsMatchFiniteDifferencesAndRigidMotionIsNotDamped) {
  const DampingPart both = super_truss_part({0.3, 0.01}), beta = super_truss_part({0.0, 0.01});
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<SlotState<double>> s = beam_state(6.0);
    testing::expect_tangents_match_finite_differences(both, s, kContext, 2e-6);
    VecX moving(12), rigid(12);
    beta.residual(s, kContext, moving);
    rigid_rates(beta, s);
    beta.residual(s, kContext, rigid);
    EXPECT_GT(moving.norm(), 1.0);
    EXPECT_LT(rigid.norm(), 1e-9 * moving.norm());
  }
  const TrussSectionSpec plain = soft_truss();
  const SuperTrussElement element(plain, build_truss_geometry(plain));
  const DampingPart alpha = super_truss_part({0.3, 0.0});
  std::vector<SlotState<double>> s = beam_state(6.0);
  for (auto& x : s) x.vel.setZero();
  ElementTangents plain_t, alpha_t;
  element.tangents(s, kContext, plain_t);
  alpha.tangents(s, kContext, alpha_t);
  EXPECT_LT((alpha_t.C - 0.3 * plain_t.M).cwiseAbs().maxCoeff(), 1e-10 * plain_t.M.cwiseAbs().maxCoeff());
}

TEST(Damping, RigidBodyTangentsMatchFiniteDifferences) {
  RigidBodyProperties p;
  p.mass = 3.0;
  p.centroid = Vec3(0.4, -0.2, 0.3);
  p.inertia_centroid = Vec3(0.5, 0.7, 0.9).asDiagonal();
  RigidBodyProperties damped = p;
  damped.damping_alpha = 0.8;
  const DampingPart part(std::make_shared<RigidBody>(damped), std::make_shared<RigidBody>(p));
  for (int trial = 0; trial < 10; ++trial)
    testing::expect_tangents_match_finite_differences(part, testing::random_state(part, rng), kContext, 2e-6);
}

// beta acts on deformation rates: a bent, stretched element carried along by a rigid motion
// (prestressed, so beta K_T v would not vanish) feels no damping force.
TEST(Damping, StiffnessProportionalDampingLeavesRigidMotionOfAPrestressedElementAlone) {
  const RayleighDamping beta_only{0.0, 0.02};
  CubicSplineBeamProperties sp;
  sp.beam = soft_tube();
  CubicSplineBeamProperties sp_damped = sp;
  sp_damped.beam.material.damping = beta_only;
  RopeProperties rp;
  rp.material = Material{7800.0, 1e5, 0.3, {}, 0.0};
  rp.section = round_tube_section(0.02, 0.0);
  rp.rest_length = 5.0;
  StrutTieProperties tp;
  tp.material = Material{7800.0, 1e4, 0.3, {}, 0.0};
  tp.section = round_tube_section(0.3, 0.1);
  tp.rest_length = 2.0;
  const DampingPart parts[] = {
      damping_part<TimoshenkoBeam>(soft_tube(), beta_only, &BeamProperties::material),
      DampingPart(std::make_shared<CubicSplineBeam>(sp_damped), std::make_shared<CubicSplineBeam>(sp)),
      damping_part<Rope>(rp, beta_only, &RopeProperties::material),
      damping_part<StrutTie>(tp, beta_only, &StrutTieProperties::material)};
  for (const DampingPart& part : parts) {
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<SlotState<double>> s = part.num_dofs() == 14 ? spline_state(2.0)
                                         : part.slots()[1] == SlotKind::vector ? rope_state()
                                         : part.num_dofs() == 6 ? testing::random_state(part, rng, 1.5)
                                                                : beam_state(2.0);
      VecX moving(part.num_dofs());
      part.residual(s, kContext, moving);
      EXPECT_GT(moving.norm(), 1e-3) << "a deforming element must be damped";
      rigid_rates(part, s);
      VecX r(part.num_dofs());
      part.residual(s, kContext, r);
      EXPECT_LT(r.norm(), 1e-10 * moving.norm()) << part.num_dofs() << " dofs, trial " << trial;
    }
  }
}

// Dissipation: the damping force does negative work on every motion, v . f_d >= 0.
TEST(Damping, DampingForcesDissipate) {
  const DampingPart beam = damping_part<TimoshenkoBeam>(soft_tube(), {0.7, 0.02}, &BeamProperties::material);
  for (int trial = 0; trial < 10; ++trial) {
    const auto s = beam_state(2.0);
    VecX r(12), v(12);
    beam.residual(s, kContext, r);
    for (int k = 0; k < 4; ++k) v.segment<3>(3 * k) = s[k].vel;
    EXPECT_GT(v.dot(r), 0.0);
  }
}

// At the unstressed reference the beams' damping matrices are exactly alpha M + beta K.
TEST(Damping, AtTheReferenceTheDampingMatrixIsAlphaMPlusBetaK) {
  const RayleighDamping d{0.7, 0.02};
  BeamProperties p = soft_tube();
  const TimoshenkoBeam plain(p);
  p.material.damping = d;
  const TimoshenkoBeam damped(p);
  std::vector<SlotState<double>> s(4);
  s[2].pos = Vec3(2.0, 0, 0);
  ElementTangents a, b;
  plain.tangents(s, ElementContext{}, a);
  damped.tangents(s, ElementContext{}, b);
  const MatX expected = d.alpha * a.M + d.beta * a.K;
  EXPECT_LT((b.C - a.C - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());

  CubicSplineBeamProperties sp;
  sp.beam = soft_tube();
  const CubicSplineBeam splain(sp);
  sp.beam.material.damping = d;
  const CubicSplineBeam sdamped(sp);
  std::vector<SlotState<double>> t(6);
  t[3].pos = Vec3(2.0, 0, 0);
  t[2].pos = t[5].pos = Vec3(1, 0, 0);
  splain.tangents(t, ElementContext{}, a);
  sdamped.tangents(t, ElementContext{}, b);
  const MatX sexpected = d.alpha * a.M + d.beta * a.K;
  EXPECT_LT((b.C - a.C - sexpected).cwiseAbs().maxCoeff(), 1e-10 * sexpected.cwiseAbs().maxCoeff());
}

TEST(Damping, CoefficientsFromDampingRatios) {
  const RayleighDamping one = rayleigh_from_ratio(0.02, 10.0);
  EXPECT_DOUBLE_EQ(one.alpha, 0.0);
  EXPECT_NEAR(one.ratio(10.0), 0.02, 1e-15);
  const RayleighDamping two = rayleigh_from_ratios(0.05, 2.0, 0.02, 30.0);
  EXPECT_NEAR(two.ratio(2.0), 0.05, 1e-15);
  EXPECT_NEAR(two.ratio(30.0), 0.02, 1e-15);
  EXPECT_THROW(rayleigh_from_ratios(0.05, 2.0, 0.05, 2.0), std::invalid_argument);
  EXPECT_THROW(rayleigh_from_ratios(0.01, 2.0, 0.5, 3.0), std::invalid_argument);  // needs alpha < 0
  EXPECT_THROW(rayleigh_from_ratio(-0.1, 3.0), std::invalid_argument);
}

TEST(Damping, RefusedWhereItIsNotDefined) {
  RopeProperties rp;
  rp.material = Material{7800.0, 1e11, 0.3, {}, 0.0};
  rp.material.damping = {0.5, 0.0};
  rp.section = round_tube_section(0.02, 0.0);
  rp.rest_length = 5.0;
  EXPECT_THROW(Rope{rp}, std::invalid_argument);  // alpha on a rope
  BeamProperties bp = soft_tube();
  bp.material.damping = {-1.0, 0.0};
  EXPECT_THROW(TimoshenkoBeam{bp}, std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
