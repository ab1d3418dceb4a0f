// Truss sections and lattice bodies in the model format: the full model has one node per
// lattice node (two blocks each), one beam element per member, rigid end sections as fixed
// constraints to reference nodes, joints at the ends; bad section definitions name their place.
#include "io/model_reader.hpp"

#include "elements/super_truss.hpp"
#include "elements/timoshenko_beam.hpp"
#include "io/input_node.hpp"

#include <gtest/gtest.h>

#include <ostream>

#include <algorithm>
#include <string>

namespace latticedyn {
namespace {

const char* kLattice = R"(materials:
  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.25}
sections:
  chord: {type: round_tube, outer_radius: 0.1, inner_radius: 0.08}
  lacing: {type: round_tube, outer_radius: 0.05, inner_radius: 0.04}
truss_sections:
  foot:
    length: 5
    order: 3
    end1: [[1.5, 0], [-1.5, 0]]
    end2: [[1.5, 1.4], [-1.5, 1.4], [-1.5, -1.4], [1.5, -1.4]]
    main_beams: [[1, 1], [2, 2], [2, 3], [1, 4]]
    cross_beams1: [[1, 2]]
    cross_beams2: [[1, 2], [2, 3], [3, 4], [4, 1]]
    connection: tp_type1
    material: steel
    main_section: chord
    sub_section: lacing
  middle:
    length: 15
    order: 6
    end1: [[1.5, 1.4], [-1.5, 1.4], [-1.5, -1.4], [1.5, -1.4]]
    main_beams: [[1, 1], [2, 2], [3, 3], [4, 4]]
    cross_beams1: [[1, 2], [2, 3], [3, 4], [4, 1]]
    cross_beams2: [[1, 2], [2, 3], [3, 4], [4, 1]]
    material: steel
    main_section: chord
    sub_section: lacing
ground:
  joints: [{name: hinge}]
bodies:
  - {name: foot, type: lattice, section: foot, rotation_deg: [0, -90, 0]}
  - {name: mid, type: lattice, section: middle, position: [0, 0, 5], rotation_deg: [0, -90, 0], rigid_ends: false}
constraints:
  - {name: base, type: fixed, joints: [ground.hinge, foot.1]}
  - {name: splice, type: fixed, joints: [foot.e2n1, mid.e1n1], shared: true}
)";

TEST(LatticeReaders, BuildsTheFullModelMemberByMember) {
  const Model m = read_simulation_from_string(kLattice, "lattice.yaml").model;
  const Body& foot = m.bodies[m.find_body("foot")];
  const Body& mid = m.bodies[m.find_body("mid")];
  EXPECT_EQ(foot.type, "lattice");
  EXPECT_EQ(foot.elements.size(), 29u);
  EXPECT_EQ(mid.elements.size(), 56u);
  // Rigid ends of the foot: 2 + 4 fixed constraints to its reference nodes; the middle piece
  // has none. Plus the base; the splice is shared (no multipliers).
  int rigid = 0;
  for (const Constraint& c : m.constraints) rigid += c.name.rfind("foot.rigid_end", 0) == 0 ? 1 : 0;
  EXPECT_EQ(rigid, 6);
  EXPECT_EQ(m.constraints.size(), 7u);
  // Joints: at the end nodes, and at the reference points of rigid ends (on the truss axis).
  const Joint& top = m.joints[m.find_joint("foot.2")];
  EXPECT_NEAR((m.blocks[top.translation_block].position0 - Vec3(0, 0, 5)).norm(), 0.0, 1e-12);
  EXPECT_GE(m.find_joint("mid.e2n4"), 0);
  EXPECT_LT(m.find_joint("mid.1"), 0);
  // The truss frame: x along the truss (turned to +z by rotation_deg [0, -90, 0]).
  const Joint& n1 = m.joints[m.find_joint("mid.e1n1")];
  EXPECT_NEAR((m.blocks[n1.rotation_block].orientation0 * n1.frame).col(0).dot(Vec3::UnitZ()), 1.0, 1e-12);
  // A shared splice: both bodies' elements use one node there.
  EXPECT_EQ(m.joints[m.find_joint("foot.e2n1")].translation_block, n1.translation_block);
}

TEST(LatticeReaders, TrussBodiesSwitchesEveryLatticeBody) {
  // Spliced at the end sections' reference points, which both body types have (a super truss's
  // end-node joints sit off its nodes and cannot be shared); rigid_ends is accepted (and ignored)
  // on a super truss.
  std::string text = kLattice;
  text.replace(text.find("rigid_ends: false"), 17, "rigid_ends: true");
  text.replace(text.find("[foot.e2n1, mid.e1n1]"), 21, "[foot.2, mid.1]");
  const Model m = read_simulation_from_string(text + "truss_bodies: super_truss\n", "lattice.yaml").model;
  for (const char* name : {"foot", "mid"}) {
    const Body& b = m.bodies[m.find_body(name)];
    EXPECT_EQ(b.type, "super_truss") << name;
    EXPECT_EQ(b.elements.size(), 1u) << name;
  }
  EXPECT_GE(m.find_joint("mid.e1n1"), 0);
  // Written on a super truss body, a full-model key is an error.
  std::string reduced = text;
  reduced.replace(reduced.find("type: lattice, section: middle"), 13, "type: super_truss");
  EXPECT_THROW(read_simulation_from_string(reduced, "lattice.yaml"), InputError);
  const Model full = read_simulation_from_string(text + "truss_bodies: lattice\n", "lattice.yaml").model;
  EXPECT_EQ(full.bodies[full.find_body("mid")].elements.size(), 56u);
}

// A damped material reaches every member of a lattice and the super truss.
TEST(LatticeReaders, DampedMaterialDampsTheLatticeAndTheSuperTruss) {
  std::string text = kLattice;
  text.replace(text.find("poisson_ratio: 0.25}"), 20, "poisson_ratio: 0.25, damping: {alpha: 0.1, beta: 0.001}}");
  const Model m = read_simulation_from_string(text, "lattice.yaml").model;
  const Body& mid = m.bodies[m.find_body("mid")];
  const auto* beam = dynamic_cast<const TimoshenkoBeam*>(m.elements[mid.elements[0]].element.get());
  ASSERT_NE(beam, nullptr);
  EXPECT_DOUBLE_EQ(beam->properties().material.damping.beta, 0.001);
  text.replace(text.find("[foot.e2n1, mid.e1n1]"), 21, "[foot.2, mid.1]");
  const Model reduced = read_simulation_from_string(text + "truss_bodies: super_truss\n", "lattice.yaml").model;
  const Body& r = reduced.bodies[reduced.find_body("mid")];
  const auto* truss = dynamic_cast<const SuperTrussElement*>(reduced.elements[r.elements[0]].element.get());
  ASSERT_NE(truss, nullptr);
  EXPECT_DOUBLE_EQ(truss->spec().material.damping.alpha, 0.1);
}

struct BadLattice {
  const char* name;
  std::string replace, with, key, says;
};
// ctest names the instances by this (stable across builds), not by their bytes.
void PrintTo(const BadLattice& c, std::ostream* os) { *os << c.name; }

class RejectsBadLattice : public ::testing::TestWithParam<BadLattice> {};

TEST_P(RejectsBadLattice, WithFileLineAndKey) {
  const BadLattice& b = GetParam();
  std::string text = kLattice;
  const auto at = text.find(b.replace);
  ASSERT_NE(at, std::string::npos) << b.name;
  text.replace(at, b.replace.size(), b.with);
  try {
    read_simulation_from_string(text, "lattice.yaml");
    FAIL() << b.name << ": accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), b.key) << e.what();
    EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Classes, RejectsBadLattice,
    ::testing::Values(
        BadLattice{"node_out_of_range", "main_beams: [[1, 1], [2, 2], [2, 3], [1, 4]]", "main_beams: [[1, 1], [2, 2], [2, 3], [3, 4]]",
                   "truss_sections.foot.main_beams[3][0]", "no node 3"},
        BadLattice{"not_a_pair", "cross_beams1: [[1, 2]]", "cross_beams1: [[1, 2, 3]]", "truss_sections.foot.cross_beams1[0]",
                   "pair of node numbers"},
        BadLattice{"non_planar_face", "end2: [[1.5, 1.4], [-1.5, 1.4], [-1.5, -1.4], [1.5, -1.4]]",
                   "end2: [[1.5, 1.4], [-1.5, 1.4], [-1.5, -1.4], [1.5, -0.4]]", "truss_sections.foot", "one plane"},
        BadLattice{"unknown_form", "connection: tp_type1", "connection: warren", "truss_sections.foot.connection", "not one of"},
        BadLattice{"unknown_section", "section: middle,", "section: centre,", "bodies[1].section", "no truss section named 'centre'"},
        BadLattice{"node_yz", "end1: [[1.5, 0], [-1.5, 0]]", "end1: [[1.5, 0, 0], [-1.5, 0]]", "truss_sections.foot.end1[0]",
                   "[y, z]"}),
    [](const ::testing::TestParamInfo<BadLattice>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace latticedyn
