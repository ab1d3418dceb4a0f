// Hydraulic elements (thesis 5.1.2): the cylinder's force and chamber flows in closed form, the
// orifice equation, relief and spool openings, the pump and node volume; every tangent against
// central finite differences.
#include "elements/hydraulic_cylinder.hpp"
#include "elements/hydraulic_node_elements.hpp"
#include "elements/hydraulic_orifice.hpp"

#include "element_checks.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

namespace latticedyn {
namespace {

HydraulicCylinderProperties cylinder() {
  HydraulicCylinderProperties p;
  p.piston_diameter = 0.1;
  p.rod_diameter = 0.05;
  p.stroke = 1.0;
  p.retracted_length = 1.0;
  p.dead_volume_piston = 1e-4;
  p.dead_volume_rod = 2e-4;
  p.viscous_friction = 3e3;
  p.coulomb_friction = 400;
  p.leakage = 1e-12;
  p.mass = 40;
  return p;
}

// Ends 1.5 m apart along a skew axis, extending and turning, chambers at 80 and 30 bar.
std::vector<SlotState<double>> cylinder_state() {
  std::vector<SlotState<double>> s(4);
  const Vec3 e = Vec3(1, 2, 2).normalized();
  s[0].pos = Vec3(0.2, -0.1, 0.3);
  s[1].pos = s[0].pos + 1.5 * e;
  s[0].vel = Vec3(0.01, 0.02, -0.03);
  s[1].vel = s[0].vel + 0.05 * e + Vec3(0.04, -0.02, 0.0);
  s[0].acc = Vec3(0.1, 0.0, -0.2);
  s[1].acc = Vec3(-0.3, 0.2, 0.1);
  s[2].pos(0) = 8e6;
  s[3].pos(0) = 3e6;
  s[2].vel(0) = 2e7;
  s[3].vel(0) = -1e7;
  return s;
}

TEST(HydraulicCylinder, ForceAndChamberFlowsInClosedForm) {
  const HydraulicCylinderProperties p = cylinder();
  const HydraulicCylinder cyl(p);
  auto s = cylinder_state();
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  VecX r(8);
  cyl.residual(s, ctx, r);
  const double A1 = std::numbers::pi / 4 * 0.01, A2 = std::numbers::pi / 4 * (0.01 - 0.0025);
  const Vec3 d = s[1].pos - s[0].pos, e = d.normalized();
  const double rate = e.dot(s[1].vel - s[0].vel), stroke = d.norm() - 1.0;
  const double F = 8e6 * A1 - 3e6 * A2 - 3e3 * rate - 400 * std::tanh(rate / 0.01);
  EXPECT_LT((r.segment<3>(0) - (20 * (s[0].acc - ctx.gravity) + F * e)).norm(), 1e-9 * F);
  EXPECT_LT((r.segment<3>(3) - (20 * (s[1].acc - ctx.gravity) - F * e)).norm(), 1e-9 * F);
  // Pressure build-up: V/beta p_dot + dV/dt + leakage, times the row scale.
  const double V1 = 1e-4 + A1 * stroke, V2 = 2e-4 + A2 * (1.0 - stroke), beta = p.fluid.bulk_modulus;
  EXPECT_NEAR(r(6) / kHydraulicRowScale, V1 / beta * 2e7 + A1 * rate + 1e-12 * 5e6, 1e-15);
  EXPECT_NEAR(r(7) / kHydraulicRowScale, V2 / beta * -1e7 - A2 * rate - 1e-12 * 5e6, 1e-15);
  EXPECT_NEAR(*cyl.axial_force(s, ctx), -F, 1e-9 * F);  // pushing: compression
}

TEST(HydraulicCylinder, TangentsMatchFiniteDifferences) {
  const HydraulicCylinder cyl(cylinder());
  testing::expect_tangents_match_finite_differences(cyl, cylinder_state(), ElementContext{Vec3(0, 0, -9.81), 0.0});
}

// At rest with p_1 A_1 = p_2 A_2 the cylinder carries nothing, whatever its length and direction.
TEST(HydraulicCylinder, BalancedPressuresCarryNoForce) {
  const HydraulicCylinder cyl(cylinder());
  auto s = cylinder_state();
  for (auto& slot : s) slot.vel.setZero(), slot.acc.setZero();
  s[2].pos(0) = 6e6;
  s[3].pos(0) = 6e6 * 4.0 / 3.0;  // A_1 / A_2 = 4 / 3 for d = 2 d_rod
  VecX r(8);
  cyl.residual(s, ElementContext{}, r);
  EXPECT_LT(r.head<6>().norm(), 1e-8);
  // Only the leakage across the piston flows, from the higher to the lower pressure.
  EXPECT_NEAR(r(6), kHydraulicRowScale * 1e-12 * (6e6 - 8e6), 1e-12);
  EXPECT_NEAR(r(7), -r(6), 1e-12);
}

TEST(HydraulicCylinder, RefusesImpossibleGeometry) {
  HydraulicCylinderProperties p = cylinder();
  p.rod_diameter = 0.12;
  EXPECT_THROW(HydraulicCylinder{p}, std::invalid_argument);
  p = cylinder();
  p.dead_volume_rod = 0;
  EXPECT_THROW(HydraulicCylinder{p}, std::invalid_argument);
}

// The energy account of one element (what EnergyLedger sums): the power it takes from its nodes,
// sum p r_p / k over its pressure slots, plus the power its mechanical rows take, sum v . r, is
// what it dissipates and compresses, less what it supplies, plus the rate of its mechanical energy.
void expect_energy_account_identity(const Element& e, const std::vector<SlotState<double>>& s, const ElementContext& ctx) {
  VecX r(e.num_dofs());
  e.residual(s, ctx, r);
  double taken = 0.0;
  int o = 0;
  const auto kinds = e.slots();
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const int n = slot_size(kinds[k]);
    taken += kinds[k] == SlotKind::scalar ? s[k].pos(0) * r(o) / kHydraulicRowScale : s[k].vel.dot(r.segment<3>(o));
    o += n;
  }
  auto mechanical = [&](double t) {
    const ElementEnergy en = e.energy(testing::advance(e, s, t), ctx);
    return en.kinetic + en.gravity_potential + en.strain;
  };
  const double h = 1e-6;
  const double rate = (mechanical(h) - mechanical(-h)) / (2 * h);
  const ElementPower p = e.power(s, ctx);
  EXPECT_NEAR(taken, p.compression + p.dissipated - p.supplied + rate, 1e-7 * (1 + std::abs(taken))) << e.type_name();
}

TEST(HydraulicCylinder, EnergyAccountAndFlows) {
  const HydraulicCylinder cyl(cylinder());
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  auto s = cylinder_state();
  expect_energy_account_identity(cyl, s, ctx);
  // Dissipation in closed form: c s_dot^2 + F_c tanh(s_dot / v_f) s_dot + C_L dp^2.
  const Vec3 e = (s[1].pos - s[0].pos).normalized();
  const double rate = e.dot(s[1].vel - s[0].vel);
  EXPECT_NEAR(cyl.power(s, ctx).dissipated, 3e3 * rate * rate + 400 * std::tanh(rate / 0.01) * rate + 1e-12 * 25e12, 1e-9);
  // The flows are the chamber rows over the row scale.
  VecX r(8);
  cyl.residual(s, ctx, r);
  std::array<double, 2> q{};
  cyl.flows(s, ctx, q);
  EXPECT_EQ(cyl.flow_names()[0], "Q_piston");
  EXPECT_DOUBLE_EQ(q[0], r(6) / kHydraulicRowScale);
  EXPECT_DOUBLE_EQ(q[1], r(7) / kHydraulicRowScale);
  // The oil's energy is its own account, not strain: V p^2 / (2 beta) per chamber.
  const double A1 = cyl.properties().piston_area(), A2 = cyl.properties().rod_side_area(), beta = 1.4e9;
  const double stroke = cyl.stroke(s);
  EXPECT_NEAR(cyl.energy(s, ctx).fluid,
              ((1e-4 + A1 * stroke) * 64e12 + (2e-4 + A2 * (1 - stroke)) * 9e12) / (2 * beta), 1e-9);
  EXPECT_EQ(cyl.energy(s, ctx).strain, 0.0);  // inside the stroke: no end stop
}

// States driven past the end stops: at full stroke plus d and below zero stroke by d.
std::vector<SlotState<double>> at_stroke(double stroke) {
  auto s = cylinder_state();
  const Vec3 e = Vec3(1, 2, 2).normalized();
  s[1].pos = s[0].pos + (1.0 + stroke) * e;
  return s;
}

TEST(HydraulicCylinder, EndStopsPushBackSmoothly) {
  HydraulicCylinderProperties p = cylinder();
  p.end_stop_stiffness = 5e8;
  p.end_stop_damping = 2e5;
  const HydraulicCylinder cyl(p);
  const ElementContext ctx{Vec3(0, 0, -9.81), 0.0};
  const double w = p.end_stop_transition;
  // Past the transition the spring is linear: F_stop = -k (d - w/2) beyond, +k (d - w/2) below;
  // its energy k ((d^2 - w d) / 2 + w^2 / 6).
  for (double d : {2e-3, 5e-5}) {
    for (bool beyond : {true, false}) {
      auto s = at_stroke(beyond ? 1.0 + d : -d);
      for (auto& slot : s) slot.vel.setZero(), slot.acc.setZero();
      s[2].pos(0) = 0.0, s[3].pos(0) = 0.0;
      const double spring = d >= w ? d - 0.5 * w : d * d / (2 * w);
      const double energy = d >= w ? 0.5 * (d * d - w * d) + w * w / 6 : d * d * d / (6 * w);
      EXPECT_NEAR(*cyl.axial_force(s, ctx), (beyond ? 5e8 : -5e8) * spring, 1e-6 * 5e8 * spring);  // tension beyond
      EXPECT_NEAR(cyl.energy(s, ctx).strain, 5e8 * energy, 1e-9 * 5e8 * energy);
    }
  }
  // Tangents and the energy account past the stops and inside the transition (widened to 1 cm
  // there, so that the differences' step of 1.5e-5 m resolves the cubic ramp).
  HydraulicCylinderProperties wide = p;
  wide.end_stop_transition = 1e-2;
  const HydraulicCylinder soft(wide);
  for (double stroke : {1.0 + 3e-3, -3e-3}) {
    const auto s = at_stroke(stroke);
    for (const HydraulicCylinder* c : {&cyl, &soft}) {
      testing::expect_tangents_match_finite_differences(*c, s, ctx);
      expect_energy_account_identity(*c, s, ctx);
    }
    // The damper dissipates c_s weight s_dot^2 on top of the friction.
    const Vec3 e = (s[1].pos - s[0].pos).normalized();
    const double rate = e.dot(s[1].vel - s[0].vel);
    EXPECT_NEAR(cyl.power(s, ctx).dissipated - HydraulicCylinder(cylinder()).power(s, ctx).dissipated, 2e5 * rate * rate,
                1e-9);
  }
  // Without a stiffness the stop is the steel rod's: E A_rod / l_0.
  EXPECT_NEAR(HydraulicCylinder(cylinder()).end_stop_stiffness(), 2.1e11 * std::numbers::pi / 4 * 0.0025 / 1.0, 1.0);
  p.end_stop_transition = 0;
  EXPECT_THROW(HydraulicCylinder{p}, std::invalid_argument);
}

HydraulicOrificeProperties orifice() {
  HydraulicOrificeProperties p;
  p.area = 1e-5;
  p.discharge_coefficient = 0.62;
  p.transition_pressure = 1e4;
  return p;
}

std::vector<SlotState<double>> pressures(double p1, double p2) {
  std::vector<SlotState<double>> s(2);
  s[0].pos(0) = p1;
  s[1].pos(0) = p2;
  return s;
}

TEST(HydraulicOrifice, FollowsTheOrificeEquation) {
  const HydraulicOrifice o(orifice());
  // Q = C_d A sqrt(2 dp / rho) for dp >> p_t, the laminar core shifting it by (p_t / dp)^2 / 4.
  for (double dp : {1e6, 1e7, 3e7}) {
    const double exact = 0.62 * 1e-5 * std::sqrt(2 * dp / 870.0);
    EXPECT_NEAR(o.flow(dp + 1e5, 1e5, 0.0), exact, 0.3 * std::pow(1e4 / dp, 2) * exact);
    EXPECT_DOUBLE_EQ(o.flow(1e5, dp + 1e5, 0.0), -o.flow(dp + 1e5, 1e5, 0.0));
  }
  EXPECT_EQ(o.flow(2e6, 2e6, 0.0), 0.0);
  VecX r(2);
  o.residual(pressures(5e6, 1e6), ElementContext{}, r);
  EXPECT_DOUBLE_EQ(r(0), -r(1));  // what leaves node 1 reaches node 2
  for (double p1 : {2e6, 1e3, -5e5})
    testing::expect_tangents_match_finite_differences(o, pressures(p1, 1e5), ElementContext{});
}

TEST(HydraulicOrifice, ReliefValveOpensBetweenCrackingAndFullOpen) {
  HydraulicOrificeProperties p = orifice();
  p.opening = OrificeOpening::relief;
  p.cracking_pressure = 2e7;
  p.full_open_pressure = 2.2e7;
  const HydraulicOrifice relief(p), open(orifice());
  EXPECT_EQ(relief.flow(1.99e7, 0, 0), 0.0);
  EXPECT_DOUBLE_EQ(relief.flow(2.3e7, 0, 0), open.flow(2.3e7, 0, 0));
  EXPECT_NEAR(relief.flow(2.1e7, 0, 0), 0.5 * open.flow(2.1e7, 0, 0), 1e-12);  // the smooth ramp's middle
  testing::expect_tangents_match_finite_differences(relief, pressures(2.07e7, 1e5), ElementContext{});
  // Throttling dissipates dp Q, which is the power the valve takes from its nodes.
  expect_energy_account_identity(relief, pressures(2.07e7, 1e5), ElementContext{});
  expect_energy_account_identity(open, pressures(1e5, 3e6), ElementContext{});
  EXPECT_NEAR(open.power(pressures(3e6, 1e5), ElementContext{}).dissipated, 2.9e6 * open.flow(3e6, 1e5, 0), 1e-9);
  std::array<double, 1> q{};
  open.flows(pressures(3e6, 1e5), ElementContext{}, q);
  EXPECT_EQ(q[0], open.flow(3e6, 1e5, 0));
  EXPECT_EQ(open.flow_names()[0], "Q");
}

TEST(HydraulicOrifice, SpoolOpensOneWayOrTheOther) {
  HydraulicOrificeProperties p = orifice();
  p.drive = Drive(Drive::Sine{.amplitude = 1.0, .frequency = 0.25});  // u = sin(pi t / 2): +1 at t = 1, -1 at 3
  p.opening = OrificeOpening::spool_positive;
  const HydraulicOrifice forward(p);
  p.opening = OrificeOpening::spool_negative;
  const HydraulicOrifice backward(p);
  const HydraulicOrifice open(orifice());
  EXPECT_NEAR(forward.flow(1e7, 0, 1.0), open.flow(1e7, 0, 0), 1e-15);
  EXPECT_EQ(backward.flow(1e7, 0, 1.0), 0.0);
  EXPECT_EQ(forward.flow(1e7, 0, 3.0), 0.0);
  EXPECT_NEAR(backward.flow(1e7, 0, 3.0), open.flow(1e7, 0, 0), 1e-15);
  EXPECT_NEAR(forward.flow(1e7, 0, 1.0 / 3.0), 0.5 * open.flow(1e7, 0, 0), 1e-15);  // u = 1/2
  p.drive.reset();
  EXPECT_THROW(HydraulicOrifice{p}, std::invalid_argument);
}

TEST(HydraulicNodeElements, PumpAndVolumeRows) {
  const HydraulicPump pump(2e-4, Drive(Drive::Constant{0.5}));
  VecX r(1);
  pump.residual(pressures(1e7, 0), ElementContext{}, r);
  EXPECT_DOUBLE_EQ(r(0), -kHydraulicRowScale * 1e-4);  // brings 0.1 l/s into its node
  HydraulicFluid oil;
  const HydraulicVolume volume(2e-3, oil);
  auto s = pressures(1e7, 0);
  s.resize(1);
  s[0].vel(0) = 3e6;
  volume.residual(s, ElementContext{}, r);
  EXPECT_NEAR(r(0), kHydraulicRowScale * 2e-3 / oil.bulk_modulus * 3e6, 1e-12);
  EXPECT_NEAR(volume.energy(s, ElementContext{}).fluid, 2e-3 * 1e14 / (2 * oil.bulk_modulus), 1e-9);
  // A fixed volume's compression power is exactly the rate of its oil's energy.
  EXPECT_NEAR(volume.power(s, ElementContext{}).compression, 2e-3 * 1e7 * 3e6 / oil.bulk_modulus, 1e-9);
  expect_energy_account_identity(volume, s, ElementContext{});
  // The pump supplies p Q.
  EXPECT_NEAR(pump.power(pressures(1e7, 0), ElementContext{}).supplied, 1e7 * 1e-4, 1e-9);
  expect_energy_account_identity(pump, pressures(1e7, 0), ElementContext{});
  testing::expect_tangents_match_finite_differences(volume, s, ElementContext{});
  EXPECT_THROW(HydraulicVolume(0.0, oil), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
