// Beams and ropes in the model format: the member is split into n elements on shared nodes at
// the right places, the section frame follows `up`, rope slopes and sag start consistent, and
// bad member input names file, line and key.
#include "io/model_reader.hpp"

#include "elements/rope.hpp"
#include "elements/cubic_spline_beam.hpp"
#include "elements/timoshenko_beam.hpp"
#include "io/input_node.hpp"

#include <gtest/gtest.h>

#include <ostream>

#include <cmath>
#include <numbers>
#include <string>

namespace latticedyn {
namespace {

const char* kMembers = R"(gravity: [0, 0, -9.81]
materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.25}
sections:
  solid: {type: round_tube, outer_radius: 0.15}
  wire: {type: round_tube, outer_radius: 0.01}
drives:
  hoist: {type: trapezoidal, t_start: 0, duration: 10, accel_time: 1, decel_time: 1, distance: 5, initial: 12}
ground:
  joints: [{name: a, position: [0, 0, 0]}, {name: b, position: [10, 0, 0]}]
bodies:
  - name: tbeam
    type: timoshenko_beam
    material: steel
    section: solid
    ends: [[0, 0, 0], [0, 6, 0]]
    elements: 3
    up: [1, 0, 1]
    joints: [{name: mid, node: 1}]
  - name: cbeam
    type: cubic_spline_beam
    material: steel
    section: solid
    ends: [[0, 0, 0], [0, 0, 4]]
    elements: 2
    gauss_points: 3
  - name: rope
    type: rope
    material: steel
    section: wire
    ends: [[0, 0, 0], [10, 0, 0]]
    elements: 4
    rest_length_drive: hoist
constraints:
  - {name: clamp, type: fixed, joints: [ground.a, tbeam.1]}
  - {name: left, type: spherical, joints: [ground.a, rope.1]}
  - {name: right, type: spherical, joints: [ground.b, rope.2]}
)";

TEST(FlexibleBodyReaders, SplitsMembersIntoElementsOnSharedNodes) {
  const Simulation sim = read_simulation_from_string(kMembers, "members.yaml");
  const Model& m = sim.model;
  const Body& tb = m.bodies[m.find_body("tbeam")];
  const Body& cb = m.bodies[m.find_body("cbeam")];
  const Body& rb = m.bodies[m.find_body("rope")];
  ASSERT_EQ(tb.elements.size(), 3u);
  ASSERT_EQ(cb.elements.size(), 2u);
  ASSERT_EQ(rb.elements.size(), 4u);
  EXPECT_EQ(tb.type, "timoshenko_beam");
  // Neighbouring elements share their node's blocks.
  const auto& e0 = m.elements[tb.elements[0]], &e1 = m.elements[tb.elements[1]];
  EXPECT_EQ(e0.slots[2].block, e1.slots[0].block);
  EXPECT_EQ(e0.slots[3].block, e1.slots[1].block);
  EXPECT_NEAR((m.blocks[e1.slots[0].block].position0 - Vec3(0, 2, 0)).norm(), 0.0, 1e-14);
  // Element length L / n; the section frame: x along the axis, z from `up` across it.
  const auto* tim = dynamic_cast<const TimoshenkoBeam*>(e0.element.get());
  ASSERT_NE(tim, nullptr);
  EXPECT_DOUBLE_EQ(tim->properties().length, 2.0);
  const Mat3& R = m.blocks[e0.slots[1].block].orientation0;
  EXPECT_NEAR((R.col(0) - Vec3(0, 1, 0)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((R.col(2) - Vec3(1, 0, 1).normalized()).norm(), 0.0, 1e-14);
  EXPECT_NEAR((R.transpose() * R - Mat3::Identity()).norm(), 0.0, 1e-14);
  // End joints keep the inertial orientation; interior ones sit on their node.
  const Joint& j1 = m.joints[m.find_joint("tbeam.1")];
  EXPECT_NEAR((R * j1.frame - Mat3::Identity()).norm(), 0.0, 1e-14);
  EXPECT_EQ(m.joints[m.find_joint("tbeam.mid")].translation_block, e1.slots[0].block);
  // A member along z takes global y as its `up`; the spline's stretch blocks start at 1.
  const auto& c0 = m.elements[cb.elements[0]];
  EXPECT_NEAR((m.blocks[c0.slots[1].block].orientation0.col(2) - Vec3(0, 1, 0)).norm(), 0.0, 1e-14);
  EXPECT_EQ(m.blocks[c0.slots[2].block].kind, SlotKind::scalar);
  EXPECT_DOUBLE_EQ(m.blocks[c0.slots[2].block].position0(0), 1.0);
  EXPECT_EQ(dynamic_cast<const CubicSplineBeam*>(c0.element.get())->properties().gauss_points, 3);
}

TEST(FlexibleBodyReaders, BeamStartsInRigidMotion) {
  std::string text = kMembers;
  const std::string anchor = "    gauss_points: 3\n";
  text.replace(text.find(anchor), anchor.size(), anchor + "    velocity: [1, 0, 0]\n    angular_velocity: [0.5, 0, 0]\n");
  const Model m = read_simulation_from_string(text, "members.yaml").model;
  const Body& cb = m.bodies[m.find_body("cbeam")];
  // Node k at (0, 0, 2k): v = velocity + omega x (r - r_end1); the sections turn with omega,
  // given to the rotation blocks in body axes.
  for (int e : cb.elements) {
    const auto& el = m.elements[e];
    const DofBlock& t = m.blocks[el.slots[3].block];
    const DofBlock& r = m.blocks[el.slots[4].block];
    EXPECT_NEAR((t.velocity0 - (Vec3(1, 0, 0) + Vec3(0.5, 0, 0).cross(t.position0))).norm(), 0.0, 1e-14);
    EXPECT_NEAR((r.orientation0 * r.velocity0 - Vec3(0.5, 0, 0)).norm(), 0.0, 1e-14);
  }
}

TEST(FlexibleBodyReaders, DrivenRopeStartsAsAShallowParabolaOfItsLength) {
  const Simulation sim = read_simulation_from_string(kMembers, "members.yaml");
  const Model& m = sim.model;
  const Body& rb = m.bodies[m.find_body("rope")];
  const auto* cable = dynamic_cast<const Rope*>(m.elements[rb.elements[0]].element.get());
  ASSERT_NE(cable, nullptr);
  EXPECT_DOUBLE_EQ(cable->rest_length(0.0).value, 12.0 / 4);
  EXPECT_DOUBLE_EQ(cable->mass(0.0), 7800 * M_PI * 1e-4 * 3.0);
  // A parabola sagging towards gravity, nodes at equal arc length, every element stretched a
  // little (in tension) by the same amount: slopes dr/dS of one length just above 1.
  std::vector<Vec3> nodes, slopes;
  for (int e : rb.elements) {
    const auto& el = m.elements[e];
    if (nodes.empty()) nodes.push_back(m.blocks[el.slots[0].block].position0), slopes.push_back(m.blocks[el.slots[1].block].position0);
    nodes.push_back(m.blocks[el.slots[2].block].position0);
    slopes.push_back(m.blocks[el.slots[3].block].position0);
  }
  ASSERT_EQ(nodes.size(), 5u);
  EXPECT_NEAR(nodes[2].x(), 5.0, 1e-9);
  EXPECT_LT(nodes[2].z(), -2.5);  // shallow-parabola estimate sqrt(3 D (L0 - D) / 8) = 2.7 m
  const double stretch = slopes[0].norm();
  EXPECT_GT(stretch, 1.0);
  EXPECT_LT(stretch, 1.01);
  double chords = 0.0;
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(slopes[k].norm(), stretch, 1e-9);
    EXPECT_NEAR(slopes[k].y(), 0.0, 1e-15);
    if (k > 0) {
      chords += (nodes[k] - nodes[k - 1]).norm();
      EXPECT_NEAR((nodes[k] - nodes[k - 1]).norm(), (nodes[1] - nodes[0]).norm(), 0.05);  // equal arcs, unequal chords
    }
  }
  EXPECT_LT(chords, 12.0 * stretch);  // the polygon is shorter than the arc it spans
  EXPECT_GT(chords, 0.99 * 12.0 * stretch);
  EXPECT_EQ(m.joints[m.find_joint("rope.2")].rotation_block, -1);
}

// Damping comes from the material and a body's own `damping` replaces it; ratios at frequencies
// become alpha and beta that give them back (zeta = alpha / (2 omega) + beta omega / 2).
TEST(FlexibleBodyReaders, DampingFromTheMaterialOrTheBody) {
  std::string text = kMembers;
  text.replace(text.find("poisson_ratio: 0.25}"), 20, "poisson_ratio: 0.25, damping: {alpha: 0.1, beta: 0.002}}");
  text.replace(text.find("gauss_points: 3"), 15, "gauss_points: 3\n    damping: {ratio: [0.02, 0.03], frequency: [1, 10]}");
  text.replace(text.find("rest_length_drive: hoist"), 24, "rest_length_drive: hoist\n    damping: {ratio: 0.05, frequency: 2}");
  const Simulation sim = read_simulation_from_string(text, "members.yaml");
  const Model& m = sim.model;
  auto material_of = [&](const char* body) -> const Material& {
    const Element& e = *m.elements[m.bodies[m.find_body(body)].elements[0]].element;
    if (auto* t = dynamic_cast<const TimoshenkoBeam*>(&e)) return t->properties().material;
    if (auto* c = dynamic_cast<const CubicSplineBeam*>(&e)) return c->properties().beam.material;
    return dynamic_cast<const Rope&>(e).properties().material;
  };
  EXPECT_DOUBLE_EQ(material_of("tbeam").damping.alpha, 0.1);
  EXPECT_DOUBLE_EQ(material_of("tbeam").damping.beta, 0.002);
  const RayleighDamping c = material_of("cbeam").damping;
  EXPECT_NEAR(c.ratio(2 * std::numbers::pi * 1), 0.02, 1e-14);
  EXPECT_NEAR(c.ratio(2 * std::numbers::pi * 10), 0.03, 1e-14);
  const RayleighDamping r = material_of("rope").damping;
  EXPECT_EQ(r.alpha, 0.0);
  EXPECT_NEAR(r.beta, 2 * 0.05 / (2 * std::numbers::pi * 2), 1e-15);
}

struct BadMember {
  const char* name;
  std::string replace, with;
  std::string key, says;
};
// ctest names the instances by this (stable across builds), not by their bytes.
void PrintTo(const BadMember& c, std::ostream* os) { *os << c.name; }

class RejectsBadMember : public ::testing::TestWithParam<BadMember> {};

TEST_P(RejectsBadMember, WithFileLineAndKey) {
  const BadMember& b = GetParam();
  std::string text = kMembers;
  const auto at = text.find(b.replace);
  ASSERT_NE(at, std::string::npos) << b.name;
  text.replace(at, b.replace.size(), b.with);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  try {
    read_simulation_from_string(text, "members.yaml");
    FAIL() << b.name << ": accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), b.key) << e.what();
    EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Classes, RejectsBadMember,
    ::testing::Values(
        BadMember{"zero_elements", "elements: 3", "elements: 0", "bodies[0].elements", "from 1 to"},
        BadMember{"up_along_axis", "up: [1, 0, 1]", "up: [0, 2, 0]", "bodies[0].up", "parallel"},
        BadMember{"node_out_of_range", "node: 1}", "node: 4}", "bodies[0].joints[0].node", "from 0 to 3"},
        BadMember{"shear_coefficient_on_spline", "gauss_points: 3", "shear_coefficient: 0.9", "bodies[1].shear_coefficient",
                  "unknown key"},
        BadMember{"too_many_gauss_points", "gauss_points: 3", "gauss_points: 65", "bodies[1].gauss_points", "1 to 64"},
        BadMember{"length_and_drive", "rest_length_drive: hoist", "rest_length_drive: hoist\n    rest_length: 12",
                  "bodies[2].rest_length_drive", "not both"},
        BadMember{"unknown_drive", "rest_length_drive: hoist", "rest_length_drive: winch", "bodies[2].rest_length_drive",
                  "no drive named"},
        BadMember{"damping_both_forms", "up: [1, 0, 1]", "damping: {alpha: 1, ratio: 0.02}\n    up: [1, 0, 1]",
                  "bodies[0].damping", "not both"},
        BadMember{"damping_negative", "up: [1, 0, 1]", "damping: {beta: -0.001}\n    up: [1, 0, 1]",
                  "bodies[0].damping.beta", ">= 0"},
        BadMember{"damping_ratio_without_frequency", "up: [1, 0, 1]", "damping: {ratio: 0.02}\n    up: [1, 0, 1]",
                  "bodies[0].damping", "missing required key 'frequency'"},
        BadMember{"damping_ratios_need_negative_alpha", "up: [1, 0, 1]",
                  "damping: {ratio: [0.01, 0.5], frequency: [2, 3]}\n    up: [1, 0, 1]", "bodies[0].damping",
                  "negative alpha or beta"},
        BadMember{"damping_one_ratio_two_frequencies", "up: [1, 0, 1]",
                  "damping: {ratio: 0.01, frequency: [2, 3]}\n    up: [1, 0, 1]", "bodies[0].damping.frequency",
                  "one frequency"},
        BadMember{"rope_alpha", "rest_length_drive: hoist", "damping: {alpha: 0.5}\n    rest_length_drive: hoist",
                  "bodies[2].damping", "stiffness-proportional damping only"},
        BadMember{"rope_rotation_constraint", "{name: right, type: spherical,", "{name: right, type: fixed,",
                  "constraints[2]", "orientation"}),
    [](const ::testing::TestParamInfo<BadMember>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace latticedyn
