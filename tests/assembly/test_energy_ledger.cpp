// The energy account of a circuit in closed form: a pressure supply (a fixed node at 100 bar)
// feeding a hose through one orifice, drained to the tank through another; the powers at a state
// are p_s Q_1 in, dp_1 Q_1 + dp_2 Q_2 as heat and p V p_dot / beta into the hose's oil, and the
// ledger integrates them by the trapezoidal rule.
#include "assembly/energy_ledger.hpp"
#include "assembly/model_builder.hpp"
#include "elements/hydraulic_node_elements.hpp"
#include "elements/hydraulic_orifice.hpp"

#include <gtest/gtest.h>

namespace latticedyn {
namespace {

struct Circuit {
  Model model;
  std::shared_ptr<const HydraulicOrifice> in, out;
  Circuit() {
    ModelBuilder b;
    auto node = [&](double pressure, const char* label, bool fixed) {
      DofBlock d = DofBlock::scalar(pressure, 0.0, label, fixed);
      d.first_order = true;
      return b.add_block(d);
    };
    const int supply = node(1e7, "hydraulic node supply", true);
    const int hose = node(4e6, "hydraulic node hose", false);
    const int tank = node(0.0, "hydraulic node tank", true);
    HydraulicOrificeProperties p;
    p.area = 1e-5;
    in = std::make_shared<HydraulicOrifice>(p);
    p.area = 2e-5;
    out = std::make_shared<HydraulicOrifice>(p);
    const int body = b.add_body("circuit", "hydraulic_node");
    b.add_element(body, std::make_shared<HydraulicVolume>(1e-3, HydraulicFluid{}), {{hose}});
    b.add_element(body, in, {{supply}, {hose}});
    b.add_element(body, out, {{hose}, {tank}});
    model = b.build();
  }
};

TEST(EnergyLedger, ItemizesACircuitsPowersInClosedForm) {
  Circuit c;
  ASSERT_TRUE(EnergyLedger::applies(c.model));
  const DofMap dofs(c.model, 0, 1);
  ModelState state(c.model, dofs);
  const double p = 4e6, p_dot = 2e8;
  const std::vector<double> u = dofs.from_model_order(std::vector<double>{p}), v = dofs.from_model_order(std::vector<double>{p_dot});
  EnergyLedger ledger(c.model);
  state.set(0.0, u, v, {}, Parametrization::rotation_vector_rates);
  ledger.record(state);
  state.set(0.5, u, v, {}, Parametrization::rotation_vector_rates);
  ledger.record(state);
  const double q1 = c.in->flow(1e7, p, 0.0), q2 = c.out->flow(p, 0.0, 0.0);
  const EnergyAccount& a = ledger.account();
  EXPECT_NEAR(a.supplied, 0.5 * 1e7 * q1, 1e-9 * 1e7 * q1);  // the supply's p Q: nothing from the tank
  EXPECT_NEAR(a.dissipated, 0.5 * ((1e7 - p) * q1 + p * q2), 1e-9 * 1e7 * q1);
  EXPECT_NEAR(a.compression, 0.5 * p * 1e-3 * p_dot / 1.4e9, 1e-12);
  EXPECT_EQ(a.mechanical_change, 0.0);
  EXPECT_EQ(a.fluid_change, 0.0);  // the same state twice
  EXPECT_EQ(a.time, 0.5);
  // With the hose's rate consistent with its flows (V / beta p_dot = Q_1 - Q_2) the account closes.
  const double consistent = (q1 - q2) * 1.4e9 / 1e-3;
  EnergyLedger closed(c.model);
  for (double t : {0.0, 1e-3}) {
    state.set(t, u, dofs.from_model_order(std::vector<double>{consistent}), {}, Parametrization::rotation_vector_rates);
    closed.record(state);
  }
  EXPECT_NEAR(closed.account().imbalance(), 0.0, 1e-12 * closed.account().supplied);
  EXPECT_GT(closed.account().supplied, 0.0);
}

TEST(EnergyLedger, ModelsWithoutACircuitKeepNone) {
  ModelBuilder b;
  b.add_block(DofBlock::translation(Vec3::Zero(), Vec3::Zero(), "n"));
  EXPECT_FALSE(EnergyLedger::applies(b.build()));
}

}  // namespace
}  // namespace latticedyn
