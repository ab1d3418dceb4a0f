// The model format: a valid model reads into the expected model, and every class of bad input
// (syntax, unknown key, missing field, meaningless value, dangling reference) is rejected with
// the file, line and key of the offending entry.
#include "io/model_reader.hpp"

#include "io/input_node.hpp"

#include <gtest/gtest.h>

#include <ostream>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

namespace latticedyn {
namespace {

const char* kValid = R"(title: two links
gravity: {direction: [0, 0, -1], magnitude: 9.8}
materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.3}
sections:
  rod: {type: round_tube, outer_radius: 0.02, inner_radius: 0.01}
drives:
  swing: {type: cosine_step, t_start: 0, t_end: 1, y_start: 0, y_end: 0.5}
ground:
  joints:
    - {name: o, position: [0, 0, 0]}
bodies:
  - name: arm
    type: rigid_body
    mass: 3
    centroid: [0.5, 0, 0]
    inertia: [0.01, 0.1, 0.1]
    joints:
      - {name: base, position: [0, 0, 0]}
      - {name: tip, position: [1, 0, 0]}
  - name: tie
    type: strut_tie
    material: steel
    section: rod
    ends: [[1, 0, 0], [1, 0, -1]]
  - {name: tie2, type: strut_tie, material: steel, section: rod, ends: [[1, 0, -1], [1, 0, -2]]}
constraints:
  - {name: hinge, type: revolute, axis: z, joints: [ground.o, arm.base], drive: swing}
  - {name: hook, type: spherical, joints: [arm.tip, tie.1]}
  - {name: link, type: spherical, joints: [tie.2, tie2.1], shared: true}
loads:
  - {joint: tie2.2, force: [0, 0, -100]}
solver:
  static: {load_steps: 2}
  dynamics: {t_end: 2, time_step: 0.01, rho_infinity: 0.8}
output:
  interval: 0.1
  probes: [tie.2]
  body_blocks: true
)";

TEST(ModelReader, ReadsAValidModel) {
  const Simulation sim = read_simulation_from_string(kValid, "valid.yaml");
  const Model& m = sim.model;
  EXPECT_EQ(m.title, "two links");
  EXPECT_NEAR(m.gravity.z(), -9.8, 1e-15);
  EXPECT_EQ(m.bodies.size(), 4u);  // ground, arm, tie, tie2
  EXPECT_EQ(m.constraints.size(), 2u);  // the shared spherical costs no multipliers
  EXPECT_EQ(m.constraints[0].rows(), 6);  // driven revolute
  EXPECT_EQ(m.num_free_dofs(), 6 + 3 + 3 + 3);  // arm, tie's ends (one shared with tie2), tie2's end
  EXPECT_TRUE(sim.run_static);
  EXPECT_TRUE(sim.run_dynamics);
  EXPECT_EQ(sim.statics.load_steps, 2);
  EXPECT_DOUBLE_EQ(sim.dynamics.rho_infinity, 0.8);
  EXPECT_DOUBLE_EQ(sim.dynamics.newton_tolerance, 1e-6);  // the default
  EXPECT_EQ(sim.output.directory, "results/valid");
  ASSERT_EQ(sim.output.probe_joints.size(), 1u);
  EXPECT_EQ(m.joints[sim.output.probe_joints[0]].name, "tie.2");
  EXPECT_TRUE(sim.output.body_blocks);
}

struct BadInput {
  const char* name;
  std::string replace;  // text of kValid to replace
  std::string with;
  int line;             // line of the error, counted from the line where `replace` starts
  std::string key;      // expected key path
  std::string says;     // part of the message
};
// ctest names the instances by this (stable across builds), not by their bytes.
void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

std::string edited(const BadInput& b) {
  std::string text = kValid;
  const auto at = text.find(b.replace);
  EXPECT_NE(at, std::string::npos) << b.name << ": the test's anchor text is missing";
  text.replace(at, b.replace.size(), b.with);
  return text;
}

class RejectsBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(RejectsBadInput, WithFileLineAndKey) {
  const BadInput& b = GetParam();
  const std::string text = kValid;
  const int anchor = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(text.find(b.replace)), '\n'));
  const int line = anchor + b.line;
  try {
    read_simulation_from_string(edited(b), "model.yaml");
    FAIL() << b.name << ": accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "model.yaml");
    EXPECT_EQ(e.line(), line) << what;
    EXPECT_EQ(e.key(), b.key) << what;
    EXPECT_NE(what.find(b.says), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    EXPECT_EQ(what.rfind("model.yaml:" + std::to_string(line) + ":", 0), 0u) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Classes, RejectsBadInput,
    ::testing::Values(
        BadInput{"syntax_error", "  - name: tie\n", "  - name: [tie\n", 1, "", "YAML syntax error"},
        BadInput{"unknown_key", "    mass: 3\n", "    mass: 3\n    colour: red\n", 1, "bodies[0].colour", "unknown key 'colour'"},
        BadInput{"unknown_top_level_key", "title: two links\n", "title: two links\ngravty: [0, 0, -9.81]\n", 1, "gravty",
                 "unknown key"},
        BadInput{"missing_field", "    mass: 3\n", "", -2, "bodies[0]", "missing required key 'mass'"},
        BadInput{"negative_mass", "    mass: 3\n", "    mass: -3\n", 0, "bodies[0].mass", "positive"},
        BadInput{"rigid_body_beta", "    mass: 3\n", "    mass: 3\n    damping: {beta: 0.01}\n", 1, "bodies[0].damping",
                 "no stiffness"},
        BadInput{"material_damping_unknown_key", "poisson_ratio: 0.3}", "poisson_ratio: 0.3, damping: {zeta: 0.1}}", 0,
                 "materials.steel.damping.zeta", "unknown key"},
        BadInput{"negative_length", "    ends: [[1, 0, 0], [1, 0, -1]]\n",
                 "    ends: [[1, 0, 0], [1, 0, -1]]\n    rest_length: -2\n", 1, "bodies[1].rest_length", "positive"},
        BadInput{"zero_length_axis", "    - {name: o, position: [0, 0, 0]}\n",
                 "    - {name: o, position: [0, 0, 0], axis_angle: {axis: [0, 0, 0], angle_deg: 30}}\n", 0,
                 "ground.joints[0].axis_angle.axis", "zero length"},
        BadInput{"zero_length_strut", "    ends: [[1, 0, 0], [1, 0, -1]]\n", "    ends: [[1, 0, 0], [1, 0, 0]]\n", 0,
                 "bodies[1].ends", "coincide"},
        BadInput{"zero_gravity_direction", "direction: [0, 0, -1]", "direction: [0, 0, 0]", 0, "gravity.direction",
                 "zero length"},
        BadInput{"non_positive_time_step", "time_step: 0.01", "time_step: 0", 0, "solver.dynamics.time_step",
                 "positive"},
        BadInput{"end_before_start", "t_end: 2,", "t_start: 3, t_end: 2,", 0, "solver.dynamics.t_end",
                 "later than t_start"},
        BadInput{"rho_out_of_range", "rho_infinity: 0.8", "rho_infinity: 1.5", 0, "solver.dynamics.rho_infinity",
                 "[0, 1]"},
        BadInput{"not_a_number", "    mass: 3\n", "    mass: three\n", 0, "bodies[0].mass", "expected a finite number"},
        BadInput{"unknown_body", "joints: [arm.tip, tie.1]", "joints: [arm.tip, rope.1]", 0, "constraints[1].joints[1]",
                 "no body named 'rope'"},
        BadInput{"unknown_joint", "joints: [ground.o, arm.base]", "joints: [ground.o, arm.elbow]", 0,
                 "constraints[0].joints[1]", "has no joint 'elbow'"},
        BadInput{"unknown_drive", "drive: swing}", "drive: spin}", 0, "constraints[0].drive", "no drive named 'spin'"},
        BadInput{"unknown_material", "    material: steel\n", "    material: oak\n", 0, "bodies[1].material",
                 "no material named 'oak'"},
        BadInput{"unknown_probe", "probes: [tie.2]", "probes: [tie2.3]", 0, "output.probes[0]", "has no joint '3'"},
        BadInput{"unknown_type", "type: strut_tie", "type: strut", 0, "bodies[1].type", "not one of"},
        BadInput{"shared_joints_apart", "ends: [[1, 0, -1], [1, 0, -2]]", "ends: [[1, 0, -1.5], [1, 0, -2]]", 4,
                 "constraints[2]", "apart"},
        BadInput{"unknown_rk_scheme", "rho_infinity: 0.8}", "rho_infinity: 0.8, rk_type: rk99}", 0,
                 "solver.dynamics.rk_type", "not one of"},
        BadInput{"unknown_implicit_method", "rho_infinity: 0.8}",
                 "rho_infinity: 0.8, integrator: implicit_rk, implicit_method: \"bdf:2\"}", 0,
                 "solver.dynamics.implicit_method", "not one of"},
        BadInput{"adaptive_undamped_alpha", "rho_infinity: 0.8}", "rho_infinity: 1.0, adaptive: true}", 0,
                 "solver.dynamics.adaptive", "rho_infinity below 1"},
        BadInput{"minimum_dof_on_strut_ties", "rho_infinity: 0.8}", "rho_infinity: 0.8, integrator: minimum_dof}", 0,
                 "solver.dynamics.integrator", "rigid bodies only"},
        BadInput{"loose_newton_tolerance", "rho_infinity: 0.8}", "rho_infinity: 0.8, newton_tolerance: 0.1}", 0,
                 "solver.dynamics.newton_tolerance", "below 1e-2"},
        BadInput{"duplicate_constraint_name", "{name: hook,", "{name: hinge,", 0, "constraints[1].name",
                 "exists already"},
        BadInput{"material_on_custom_body", "    mass: 3\n", "    mass: 3\n    material: steel\n", 1,
                 "bodies[0].material", "applies to a rigid body built from section"},
        BadInput{"axis_on_spherical", "type: spherical,", "type: spherical, axis: x,", 0, "constraints[1].axis",
                 "only revolute and prismatic"}),
    [](const ::testing::TestParamInfo<BadInput>& info) { return std::string(info.param.name); });

// A model built on a base file: its top-level keys replace the base's, errors name the file the
// offending key came from, and a cycle or a missing base is an input error.
class BaseFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("latticedyn_base_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "sub");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  std::filesystem::path dir_;
};

TEST_F(BaseFiles, KeysOfTheFileReplaceTheBasesWholeKeys) {
  write("sub/base.yaml", kValid);
  const std::string top = write("maneuver.yaml",
                                "base: sub/base.yaml\ntitle: a maneuver\n"
                                "drives:\n  swing: {type: constant, value: 0.25}\n"
                                "solver:\n  dynamics: {t_end: 1, time_step: 0.02}\n");
  const Simulation sim = read_simulation(top);
  EXPECT_EQ(sim.model.title, "a maneuver");
  EXPECT_EQ(sim.model.bodies.size(), 4u);  // ground and three bodies, from the base
  ASSERT_EQ(sim.model.drives.size(), 1u);
  EXPECT_DOUBLE_EQ(sim.model.drives[0].evaluate(5.0).value, 0.25);
  EXPECT_DOUBLE_EQ(sim.dynamics.t_end, 1.0);
  EXPECT_FALSE(sim.run_static) << "solver replaced as a whole: no static block";
  EXPECT_EQ(sim.output.interval, 0.1) << "output from the base";
}

TEST_F(BaseFiles, ErrorsNameTheFileTheKeyCameFrom) {
  std::string bad = kValid;
  bad.replace(bad.find("mass: 3"), 7, "mass: -3");
  const std::string base = write("sub/base.yaml", bad);
  const std::string top = write("top.yaml", "base: sub/base.yaml\ntitle: x\n");
  try {
    read_simulation(top);
    FAIL() << "expected an input error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), base);
    EXPECT_NE(std::string(e.what()).find("base.yaml:15:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bodies[0].mass"), std::string::npos) << e.what();
  }
  write("top2.yaml", "base: sub/base.yaml\ntitle: x\ngravity: [0, 0]\n");
  try {
    read_simulation((dir_ / "top2.yaml").string());
    FAIL() << "expected an input error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("top2.yaml:3:"), std::string::npos) << e.what();
  }
}

TEST_F(BaseFiles, CyclesAndMissingBasesAreInputErrors) {
  write("a.yaml", "base: b.yaml\ntitle: a\n");
  write("b.yaml", "base: a.yaml\ntitle: b\n");
  try {
    read_simulation((dir_ / "a.yaml").string());
    FAIL() << "expected an input error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
  }
  write("c.yaml", "base: nowhere.yaml\n");
  try {
    read_simulation((dir_ / "c.yaml").string());
    FAIL() << "expected an input error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c.yaml:1:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nowhere.yaml"), std::string::npos) << e.what();
  }
}

TEST(ModelReader, ReadsTheImplicitRungeKuttaRoute) {
  std::string text = kValid;
  const std::string at = "rho_infinity: 0.8}";
  ASSERT_NE(text.find(at), std::string::npos);
  text.replace(text.find(at), at.size(), "rho_infinity: 0.8, integrator: implicit_rk, implicit_method: \"rosw:rodas3\"}");
  const Simulation sim = read_simulation_from_string(text, "model.yaml");
  EXPECT_EQ(sim.dynamics.integrator, IntegratorKind::implicit_rk);
  EXPECT_EQ(sim.dynamics.implicit_method, "rosw:rodas3");
}

// The quintic step by name: its values from the YAML keys; a span that ends before it starts is
// an input error at the drive.
TEST(ModelReader, ReadsAQuinticStepDrive) {
  std::string text = kValid;
  const std::string at = "swing: {type: cosine_step,";
  ASSERT_NE(text.find(at), std::string::npos);
  text.replace(text.find(at), at.size(), "swing: {type: quintic_step,");
  const Simulation sim = read_simulation_from_string(text, "quintic.yaml");
  ASSERT_EQ(sim.model.drives.size(), 1u);
  const Drive& d = sim.model.drives[0];
  EXPECT_NEAR(d.evaluate(0.5).value, 0.25, 1e-15);  // halfway, half of 0.5
  EXPECT_NEAR(d.evaluate(0.5).rate, 15.0 / 8.0 * 0.5, 1e-14);
  EXPECT_EQ(d.evaluate(0.0).accel, 0.0);
  EXPECT_NE(d.describe().find("quintic step"), std::string::npos) << d.describe();
  text.replace(text.find("t_end: 1,"), 9, "t_end: 0,");
  try {
    read_simulation_from_string(text, "quintic.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("drives.swing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("t_end"), std::string::npos) << e.what();
  }
}

TEST(ModelReader, MissingFileIsAnInputError) {
  EXPECT_THROW(read_simulation("/nonexistent/model.yaml"), InputError);
}

}  // namespace
}  // namespace latticedyn

namespace latticedyn {
namespace {

// Overrides (batch runs): values replaced at dotted paths through maps and list items (by name
// or index) after the base is merged, a new last key added, a path that leads nowhere rejected
// at the override's origin.
TEST_F(BaseFiles, OverridesReplaceValuesAtDottedPaths) {
  write("base.yaml", kValid);
  const std::string path = write("top.yaml", "base: base.yaml\ntitle: on a base\n");
  auto override_at = [](const std::string& p, const YAML::Node& v) {
    KeyOverride o;
    o.path = p;
    o.value = v;
    o.origin_file = "batch.yaml";
    o.origin_line = 7;
    o.origin_column = 3;
    return o;
  };
  const Simulation plain = read_simulation(path);
  const Simulation sim = read_simulation(
      path, {override_at("bodies.arm.mass", YAML::Node(6.0)), override_at("bodies.arm.centroid.0", YAML::Node(0.25)),
             override_at("gravity.magnitude", YAML::Node(1.62)), override_at("title", YAML::Node("changed"))});
  EXPECT_EQ(sim.model.title, "changed");
  EXPECT_NEAR(sim.model.gravity.norm(), 1.62, 1e-12);
  EXPECT_NEAR(plain.model.gravity.norm(), 9.8, 1e-12);
  const InputNode root = InputNode::load_file(path, {override_at("bodies.0.mass", YAML::Node(6.0))});
  EXPECT_DOUBLE_EQ(root.at_path("bodies.arm.mass")->as_double(), 6.0);
  EXPECT_DOUBLE_EQ(root.at_path("bodies.arm.centroid.0")->as_double(), 0.5);
  EXPECT_FALSE(root.at_path("bodies.nobody.mass"));
  try {
    (void)InputNode::load_file(path, {override_at("bodies.arm.joints.elbow.position", YAML::Node(1.0))});
    FAIL() << "a path through a missing list item must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("batch.yaml:7:3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("without an item named 'elbow'"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)InputNode::load_file(path, {override_at("solvr.static.load_steps", YAML::Node(2))}), InputError);
  // An index beyond any list (std::stoul would throw out of range): an input error at the origin.
  EXPECT_THROW((void)InputNode::load_file(path, {override_at("bodies.99999999999999999999999.mass", YAML::Node(1.0))}),
               InputError);
}

}  // namespace
}  // namespace latticedyn

namespace latticedyn {
namespace {

// YAML aliases (found by the model reader's fuzz target): an alias inside its own anchor is a
// node that contains itself, and anchors that list the one before ten times make a few hundred
// bytes a billion nodes. Both are input errors at once, not an endless walk or all the memory.
TEST(ModelReader, AliasesThatNeverEndAreInputErrors) {
  const auto message = [](const std::string& yaml) {
    try {
      read_simulation_from_string(yaml, "alias.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("title: &a [*a]\n").find("an alias *name inside its own anchor"), std::string::npos)
      << message("title: &a [*a]\n");
  std::string laughs = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k <= 9; ++k) {
    const std::string prev = "*a" + std::to_string(k - 1);
    laughs += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [" + prev;
    for (int i = 1; i < 10; ++i) laughs += ", " + prev;
    laughs += "]\n";
  }
  const std::string m = message(laughs);
  EXPECT_NE(m.find("expand the document to too many nodes"), std::string::npos) << m;
  EXPECT_NE(m.find("alias.yaml:"), std::string::npos) << m;
  // (Stopped at the limit, 4 nodes a byte and at least 100,000; without it the walk takes 10^10.)
}

// A sum of sums through aliases (found by the fuzz target): 40 references to a sum of 30
// constants make a drive of 1,241 functions in 400 bytes; every evaluation would add them all.
TEST(ModelReader, DrivesOfTooManyFunctionsAreInputErrors) {
  std::string drives = "drives:\n  c: &c {type: constant, value: 0.001}\n  s: &s {type: sum, terms: [*c";
  for (int i = 1; i < 30; ++i) drives += ", *c";
  drives += "]}\n  big: {type: sum, terms: [*s";
  for (int i = 1; i < 40; ++i) drives += ", *s";
  drives += "]}\n";
  std::string yaml = kValid;
  yaml.replace(yaml.find("drives:\n"), 8, drives);
  try {
    read_simulation_from_string(yaml, "drives.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a drive of at most 1000 functions"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("drives.big"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace latticedyn
