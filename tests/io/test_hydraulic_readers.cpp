// The hydraulic circuit in the model format: nodes become scalar pressure blocks (first order,
// tanks fixed), valves their orifices, the cylinder a body on two nodes; every bad entry is an
// input error at its key.
#include "io/hydraulic_readers.hpp"
#include "io/model_reader.hpp"

#include "elements/hydraulic_orifice.hpp"
#include "io/input_node.hpp"

#include <gtest/gtest.h>

#include <string>

namespace latticedyn {
namespace {

const std::string kCircuit = R"(title: circuit
gravity: [0, 0, -9.81]
drives:
  spool: {type: constant, value: 0.5}
hydraulics:
  fluid: {bulk_modulus: 1.5e9, density: 880}
  nodes:
    - {name: supply, volume: 1.0e-3, pressure: 1.0e7}
    - {name: a, volume: 1.0e-4, pressure: 2.0e6}
    - {name: b, volume: 1.0e-4, pressure: 1.0e6}
    - {name: tank, pressure: 0, fixed: true}
  elements:
    - {name: pump, type: pump, node: supply, flow: 1.0e-4}
    - {name: relief, type: relief_valve, from: supply, to: tank, area: 1.0e-5, cracking_pressure: 2.0e7, full_open_pressure: 2.2e7}
    - {name: valve, type: directional_valve, ports: {P: supply, T: tank, A: a, B: b}, area: 2.0e-5, spool: spool}
ground:
  joints:
    - {name: o, position: [0, 0, 0]}
bodies:
  - {name: ram, type: hydraulic_cylinder, ends: [[0, 0, 0], [0, 0, 1.5]], retracted_length: 1.0, stroke: 1.0,
     piston_diameter: 0.1, rod_diameter: 0.05, dead_volumes: [1.0e-4, 1.0e-4], ports: [a, b]}
constraints:
  - {name: foot, type: spherical, joints: [ground.o, ram.1]}
solver:
  dynamics: {t_end: 1, time_step: 0.01}
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(HydraulicReaders, BuildsTheCircuit) {
  const Simulation sim = read_simulation_from_string(kCircuit, "circuit.yaml");
  const Model& m = sim.model;
  int free_nodes = 0, fixed_nodes = 0;
  for (const DofBlock& b : m.blocks)
    if (b.label.starts_with(kHydraulicNodeLabel)) {
      EXPECT_EQ(b.kind, SlotKind::scalar);
      EXPECT_TRUE(b.first_order);
      (b.fixed ? fixed_nodes : free_nodes)++;
    }
  EXPECT_EQ(free_nodes, 3);
  EXPECT_EQ(fixed_nodes, 1);
  // The reversing valve is four orifices; at spool 0.5 the P->A and B->T ones are half open.
  const Body& valve = m.bodies[m.find_body("valve")];
  ASSERT_EQ(valve.elements.size(), 4u);
  const auto* pa = dynamic_cast<const HydraulicOrifice*>(m.elements[valve.elements[0]].element.get());
  const auto* pb = dynamic_cast<const HydraulicOrifice*>(m.elements[valve.elements[2]].element.get());
  ASSERT_TRUE(pa && pb);
  EXPECT_GT(pa->flow(1e7, 0, 0), 0.0);
  EXPECT_EQ(pb->flow(1e7, 0, 0), 0.0);
  EXPECT_EQ(pa->properties().fluid.density, 880.0);
  EXPECT_EQ(m.bodies[m.find_body("ram")].type, "hydraulic_cylinder");
  EXPECT_GE(m.find_joint("ram.2"), 0);
  EXPECT_FALSE(sim.dynamics.hydraulic_cosimulation);
  const Simulation cosim = read_simulation_from_string(
      replaced(kCircuit, "time_step: 0.01}", "time_step: 0.01, hydraulic_coupling: cosimulation, coupling_step: 0.02}"),
      "circuit.yaml");
  EXPECT_TRUE(cosim.dynamics.hydraulic_cosimulation);
  EXPECT_EQ(cosim.dynamics.coupling_step, 0.02);
}

TEST(HydraulicReaders, CosimulationNeedsACircuit) {
  const std::string mechanism = R"(title: no circuit
gravity: [0, 0, -9.81]
bodies:
  - {name: b, type: rigid_body, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0]}
solver:
  dynamics: {t_end: 1, time_step: 0.01, hydraulic_coupling: cosimulation}
)";
  try {
    read_simulation_from_string(mechanism, "m.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "solver.dynamics.hydraulic_coupling") << e.what();
    EXPECT_NE(std::string(e.what()).find("no 'hydraulics'"), std::string::npos) << e.what();
  }
}

struct Bad {
  const char* name;
  std::string from, to, key, says;
};

class HydraulicInput : public ::testing::TestWithParam<Bad> {};

TEST_P(HydraulicInput, IsAnErrorAtItsKey) {
  const Bad& b = GetParam();
  try {
    read_simulation_from_string(replaced(kCircuit, b.from, b.to), "circuit.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), b.key) << e.what();
    EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
    EXPECT_GT(e.line(), 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, HydraulicInput,
    ::testing::Values(
        Bad{"unknown_port", "ports: [a, b]", "ports: [a, c]", "bodies[0].ports[1]", "no hydraulic node named 'c'"},
        Bad{"same_port", "ports: [a, b]", "ports: [a, a]", "bodies[0].ports", "two different nodes"},
        Bad{"outside_stroke", "[0, 0, 1.5]], retracted", "[0, 0, 2.5]], retracted", "bodies[0].ends", "outside [0, stroke]"},
        Bad{"thick_rod", "rod_diameter: 0.05", "rod_diameter: 0.15", "bodies[0]", "rod_diameter"},
        Bad{"relief_backwards", "full_open_pressure: 2.2e7", "full_open_pressure: 1.0e7", "hydraulics.elements[1].full_open_pressure",
            "above cracking_pressure"},
        Bad{"node_without_volume", "{name: a, volume: 1.0e-4, pressure: 2.0e6}", "{name: a, pressure: 2.0e6}",
            "hydraulics.nodes[1]", "volume"},
        Bad{"tank_with_volume", "{name: tank, pressure: 0, fixed: true}", "{name: tank, pressure: 0, fixed: true, volume: 1}",
            "hydraulics.nodes[3].volume", "holds its pressure"},
        Bad{"unknown_spool", "spool: spool}", "spool: lever}", "hydraulics.elements[2].spool", "no drive named 'lever'"},
        Bad{"statics", "  dynamics: {t_end: 1, time_step: 0.01}", "  static: {load_steps: 1}\n  dynamics: {t_end: 1, time_step: 0.01}",
            "solver.static", "no static solve"},
        Bad{"baumgarte", "time_step: 0.01}", "time_step: 0.01, integrator: baumgarte}", "solver.dynamics.integrator",
            "generalized_alpha or implicit_rk"},
        Bad{"negative_end_stop", "dead_volumes: [1.0e-4, 1.0e-4]", "dead_volumes: [1.0e-4, 1.0e-4], end_stop_stiffness: -1",
            "bodies[0].end_stop_stiffness", "positive"},
        Bad{"coupling_step_alone", "time_step: 0.01}", "time_step: 0.01, coupling_step: 0.02}",
            "solver.dynamics.coupling_step", "hydraulic_coupling: cosimulation"},
        Bad{"coupling_step_short", "time_step: 0.01}", "time_step: 0.01, hydraulic_coupling: cosimulation, coupling_step: 0.005}",
            "solver.dynamics.coupling_step", "at least the time step"},
        Bad{"cosimulation_implicit_rk", "time_step: 0.01}", "time_step: 0.01, integrator: implicit_rk, hydraulic_coupling: cosimulation}",
            "solver.dynamics.hydraulic_coupling", "generalized_alpha"},
        Bad{"unknown_coupling", "time_step: 0.01}", "time_step: 0.01, hydraulic_coupling: staggered}",
            "solver.dynamics.hydraulic_coupling", "monolithic"}),
    [](const ::testing::TestParamInfo<Bad>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace latticedyn
