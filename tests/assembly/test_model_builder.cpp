// Node sharing (the thesis's public computing nodes, 7.4.1): merged blocks, composed frame
// offsets, fixing to the ground, and clear errors for connections that cannot be shared.
#include "assembly/dof_map.hpp"
#include "assembly/member_builder.hpp"
#include "assembly/model_builder.hpp"

#include "sample_models.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace latticedyn {
namespace {

Constraint make(const char* name, ConstraintType type, int j1, int j2) {
  Constraint c;
  c.name = name;
  c.type = type;
  c.joint1 = j1;
  c.joint2 = j2;
  return c;
}

TEST(ModelBuilder, SharedFixedConnectionComposesFrames) {
  ModelBuilder b;
  const auto A = testing::add_rigid_body(b, "a", 1.0, Vec3(0, 0, 0), Vec3(0, 0, 0));
  const auto B = testing::add_rigid_body(b, "b", 1.0, Vec3(1, 0, 0), Vec3(0, 0, 0.5));
  // Joint frames chosen so both joints have the same orientation in space.
  const Mat3 Fa = rotation_matrix<double>(Vec3(0, 0, 0.5));
  const int ja = testing::add_body_joint(b, A, "end", Vec3(1, 0, 0), Fa);
  (void)ja;
  // Sharing needs joints on the block origin: B's origin is at (1, 0, 0).
  const int jb = testing::add_body_joint(b, B, "start", Vec3::Zero());
  const int ja0 = b.add_ground_joint("ground.x", Vec3(1, 0, 0), Fa);
  b.add_constraint(make("weld", ConstraintType::fixed, ja0, jb), true);
  const Model m = b.build();
  // B's blocks are merged into the ground joint's fixed blocks: 6 free DoFs remain (body a).
  EXPECT_EQ(m.num_free_dofs(), 6);
  EXPECT_EQ(m.num_multipliers(), 0);
  const auto& slots = m.elements[1].slots;
  EXPECT_TRUE(m.blocks[slots[0].block].fixed);
  EXPECT_TRUE(m.blocks[slots[1].block].fixed);
  // The element's frame is the block frame times the offset: unchanged orientation in space.
  EXPECT_LT((m.blocks[slots[1].block].orientation0 * slots[1].offset - rotation_matrix<double>(Vec3(0, 0, 0.5))).norm(), 1e-14);
}

TEST(ModelBuilder, RejectsSharingOfSeparatedJoints) {
  ModelBuilder b;
  const auto S1 = testing::add_strut(b, "s1", Vec3(0, 0, 0), Vec3(1, 0, 0));
  const auto S2 = testing::add_strut(b, "s2", Vec3(1.5, 0, 0), Vec3(2, 0, 0));
  b.add_constraint(make("gap", ConstraintType::spherical, S1.j2, S2.j1), true);
  try {
    b.build();
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("gap"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.5"), std::string::npos) << e.what();
  }
}

TEST(ModelBuilder, RejectsSharedNodesWithDifferentInitialVelocities) {
  ModelBuilder b;
  const auto S1 = testing::add_strut(b, "s1", Vec3(0, 0, 0), Vec3(1, 0, 0));
  const auto S2 = testing::add_rigid_body(b, "body", 1.0, Vec3(1, 0, 0), Vec3::Zero(), Vec3(0, 2, 0));
  const int jb = testing::add_body_joint(b, S2, "o", Vec3::Zero());
  b.add_constraint(make("ball", ConstraintType::spherical, S1.j2, jb), true);
  try {
    b.build();
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("different velocities"), std::string::npos) << e.what();
  }
}

TEST(ModelBuilder, RejectsRevoluteSharingAndOrientationOnStrutEnds) {
  ModelBuilder b;
  const auto A = testing::add_rigid_body(b, "a", 1.0, Vec3(0, 0, 0), Vec3(0, 0, 0));
  const int ja = testing::add_body_joint(b, A, "o", Vec3::Zero());
  const int g = b.add_ground_joint("ground.o", Vec3::Zero(), Mat3::Identity());
  EXPECT_THROW(b.add_constraint(make("hinge", ConstraintType::revolute, g, ja), true), ModelError);
  const auto S = testing::add_strut(b, "s", Vec3(0, 0, 0), Vec3(1, 0, 0));
  EXPECT_THROW(b.add_constraint(make("weld", ConstraintType::fixed, ja, S.j1), false), ModelError);
  EXPECT_NO_THROW(b.add_constraint(make("ball", ConstraintType::spherical, ja, S.j1), false));
}

TEST(ModelBuilder, RejectsMisalignedSharedFixedFrames) {
  ModelBuilder b;
  const auto A = testing::add_rigid_body(b, "a", 1.0, Vec3(0, 0, 0), Vec3(0, 0, 0));
  const int ja = testing::add_body_joint(b, A, "o", Vec3::Zero());
  const int g = b.add_ground_joint("ground.o", Vec3::Zero(), rotation_matrix<double>(Vec3(0.1, 0, 0)));
  b.add_constraint(make("weld", ConstraintType::fixed, g, ja), true);
  EXPECT_THROW(b.build(), ModelError);
}

TEST(DofMap, PartitionsOverRanksConsistently) {
  const Model m = testing::kitchen_sink_model();
  std::vector<int> owners_seen;
  int total_rows = 0;
  for (int p = 0; p < 3; ++p) {
    DofMap d(m, p, 3);
    EXPECT_EQ(d.global_size(), m.num_free_dofs() + m.num_multipliers());
    total_rows += d.owned_size();
    std::vector<int> dn, on;
    d.count_nonzeros(dn, on);
    EXPECT_EQ(static_cast<int>(dn.size()), d.owned_size());
    for (int i = 0; i < d.owned_size(); ++i) EXPECT_GT(dn[i] + on[i], 0);
  }
  EXPECT_EQ(total_rows, m.num_free_dofs() + m.num_multipliers());
}

// The partition keeps each node's translation and rotation on one rank, side by side (the 6 x 6
// blocks of SystemAssembler::uniform_blocks), and the parts stay balanced.
TEST(DofMap, KeepsEachNodesTranslationAndRotationTogether) {
  const Model m = testing::clamped_lattice_model();
  for (int ranks : {2, 3}) {
    std::vector<int> owned;
    for (int p = 0; p < ranks; ++p) {
      const DofMap d(m, p, ranks);
      owned.push_back(d.owned_size());
      EXPECT_EQ(d.owned_size() % 6, 0) << ranks << " ranks, rank " << p;
      int nodes = 0;  // a beam's end nodes: its slots (translation, rotation) twice
      for (const ElementEntry& e : m.elements) {
        const auto kinds = e.element->slots();
        for (std::size_t k = 0; k + 1 < kinds.size(); k += 2) {
          if (kinds[k] != SlotKind::translation || kinds[k + 1] != SlotKind::rotation) continue;
          const int t = e.slots[k].block, r = e.slots[k + 1].block;
          if (m.blocks[t].fixed || m.blocks[r].fixed) continue;
          ++nodes;
          EXPECT_EQ(d.block_owner(t), d.block_owner(r)) << m.blocks[t].label;
          EXPECT_EQ(d.block_dof(r), d.block_dof(t) + 3) << m.blocks[t].label;
          EXPECT_EQ(d.block_dof(t) % 6, 0) << m.blocks[t].label;
        }
      }
      EXPECT_GT(nodes, 20);
    }
    const auto [lo, hi] = std::minmax_element(owned.begin(), owned.end());
    EXPECT_LE(*hi - *lo, 12) << ranks << " ranks: parts of " << *lo << " to " << *hi << " DoFs";
  }
}

// Names are found by hash (the builder keeps the index as it adds), duplicates are still refused,
// and a model whose vectors were filled by hand rebuilds its index on the first lookup.
TEST(ModelBuilder, FindsBodiesAndJointsByNameAndRefusesDuplicates) {
  ModelBuilder b;
  for (int i = 0; i < 2000; ++i) {
    const int body = b.add_body("bay" + std::to_string(i), "rigid_body");
    Joint j;
    j.name = "bay" + std::to_string(i) + ".1";
    j.translation_block = b.add_block(DofBlock::translation(Vec3(i, 0, 0), Vec3::Zero(), j.name));
    b.add_joint(body, j);
  }
  EXPECT_THROW(b.add_body("bay7", "rigid_body"), ModelError);
  Joint again;
  again.name = "bay7.1";
  again.translation_block = 0;
  EXPECT_THROW(b.add_joint(1, again), ModelError);
  const Model m = b.build();
  EXPECT_EQ(m.find_body("ground"), 0);
  EXPECT_EQ(m.find_body("bay1999"), 2000);
  EXPECT_EQ(m.find_joint("bay1234.1"), 1234);
  EXPECT_EQ(m.find_joint("bay1234.2"), -1);
  EXPECT_EQ(m.find_body("nowhere"), -1);

  Model by_hand;
  by_hand.joints.resize(3);
  for (int i = 0; i < 3; ++i) by_hand.joints[i].name = "j" + std::to_string(i);
  EXPECT_EQ(by_hand.find_joint("j2"), 2);
  by_hand.joints.push_back(Joint{"j3"});
  EXPECT_EQ(by_hand.find_joint("j3"), 3);
}

// A member's elements bind consecutive nodes in their type's slot order (the one place that knows
// it), with the node's frame offset on its rotation slot; an element of another kind is refused.
TEST(MemberBuilder, BindsConsecutiveNodesInTheElementsSlotOrder) {
  ModelBuilder b;
  const int body = b.add_body("beam", "timoshenko_beam");
  const BeamProperties beam{Material{7800, 2.1e11, 0.3, {}, 0.0}, round_tube_section(0.05, 0.04), 1.0, 0.0};
  const Mat3 offset = rotation_matrix<double>(Vec3(0, 0, 0.3));
  std::vector<MemberNode> nodes;
  for (int k = 0; k < 3; ++k) {
    const std::string label = "beam.node" + std::to_string(k);
    nodes.push_back({b.add_block(DofBlock::translation(member_point(Vec3::Zero(), Vec3(2, 0, 0), k, 2), Vec3::Zero(), label)),
                     b.add_block(DofBlock::rotation(Mat3::Identity(), Vec3::Zero(), label)), k == 0 ? offset : Mat3::Identity()});
  }
  EXPECT_EQ(add_member_elements(b, body, MemberElement::timoshenko_beam,
                                make_beam_element(MemberElement::timoshenko_beam, beam), nodes),
            2);
  EXPECT_THROW(add_member_elements(b, body, MemberElement::rope,
                                   make_beam_element(MemberElement::timoshenko_beam, beam), nodes),
               std::invalid_argument);
  EXPECT_THROW(add_member_elements(b, body, MemberElement::cubic_spline_beam,
                                   make_beam_element(MemberElement::cubic_spline_beam, beam), nodes),
               std::invalid_argument);  // no stretch blocks
  EXPECT_THROW(make_beam_element(MemberElement::rope, beam), std::invalid_argument);
  const Model m = b.build();
  ASSERT_EQ(m.elements.size(), 2u);
  for (int e = 0; e < 2; ++e) {
    const auto& s = m.elements[e].slots;
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s[0].block, nodes[e].translation);
    EXPECT_EQ(s[1].block, nodes[e].orientation);
    EXPECT_EQ(s[2].block, nodes[e + 1].translation);
    EXPECT_EQ(s[3].block, nodes[e + 1].orientation);
  }
  EXPECT_TRUE(m.elements[0].slots[1].offset.isApprox(offset));
  EXPECT_TRUE(m.blocks[nodes[1].translation].position0.isApprox(Vec3(1, 0, 0)));
}

}  // namespace
}  // namespace latticedyn
