// Constraints of thesis 4.4 along a motion: g_dot = G v + g_u u_dot and g_ddot = G a + Gamma
// against finite differences in time, for every type including the driven ones; and the
// geometric meaning of each type's equations.
#include "assembly/constraint_evaluator.hpp"
#include "assembly/constraint_kernels.hpp"
#include "assembly/dof_map.hpp"
#include "assembly/model_state.hpp"

#include "sample_models.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>

namespace latticedyn {
namespace {

// Block states of the model moving with constant acceleration from random rates.
struct Motion {
  const Model& model;
  std::vector<BlockState> s0;
  BlockState at(int b, double t) const {
    BlockState s = s0[b];
    if (model.blocks[b].fixed) return s;
    if (model.blocks[b].kind == SlotKind::rotation)
      s.rot = s.rot * rotation_matrix<double>(s0[b].vel * t + 0.5 * s0[b].acc * t * t);
    else
      s.pos += s0[b].vel * t + 0.5 * s0[b].acc * t * t;
    s.vel += s0[b].acc * t;
    return s;
  }
};

TEST(Constraints, VelocityAndAccelerationTermsMatchTimeDerivatives) {
  const Model model = testing::kitchen_sink_model();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Motion m{model, {}};
  for (const auto& b : model.blocks) {
    BlockState s;
    s.pos = b.position0;
    s.rot = b.orientation0 * rotation_matrix<double>(Vec3(u(rng), u(rng), u(rng)));
    if (!b.fixed) {
      s.vel = Vec3(u(rng), u(rng), u(rng));
      s.acc = Vec3(u(rng), u(rng), u(rng));
    }
    m.s0.push_back(s);
  }
  const double t0 = 0.37, h = 1e-4;
  for (const Constraint& c : model.constraints) {
    auto eval = [&](double t) {
      std::vector<BlockState> states(model.blocks.size());
      for (std::size_t b = 0; b < states.size(); ++b) states[b] = m.at(static_cast<int>(b), t);
      ConstraintInputs in;
      in.model = &model;
      in.constraint = &c;
      in.block_state = [states](int b) -> const BlockState& { return states[b]; };
      in.drive = c.drive >= 0 ? model.drives[c.drive].evaluate(t0 + t) : DriveValue{};
      in.with_velocity_terms = true;
      return evaluate_constraint(in);
    };
    const ConstraintEval e0 = eval(0), ep = eval(h), em = eval(-h);
    Eigen::VectorXd a = Eigen::VectorXd::Zero(e0.cols);
    for (int k = 0; k < e0.cols / 3; ++k) a.segment<3>(3 * k) = m.s0[e0.blocks[k]].acc;
    for (int r = 0; r < e0.rows; ++r) {
      const double gd_fd = (ep.g(r) - em.g(r)) / (2 * h);
      const double gdd_fd = (ep.g(r) - 2 * e0.g(r) + em.g(r)) / (h * h);
      const double gdd = e0.G.row(r).head(e0.cols).dot(a) + e0.gamma(r);
      EXPECT_NEAR(e0.g_dot(r), gd_fd, 1e-7 * (1 + std::abs(gd_fd))) << c.name << " row " << r;
      EXPECT_NEAR(gdd, gdd_fd, 2e-5 * (1 + std::abs(gdd_fd))) << c.name << " row " << r;
    }
  }
}

// The closed form against the AD reference for every constraint of the sample model (every type,
// driven and not, joints to the ground and between bodies), at random rotated, moving states:
// g, G, g_u, d(G^T lambda)/dq, g_dot and Gamma.
TEST(Constraints, ClosedFormEqualsAutomaticDifferentiation) {
  const Model model = testing::kitchen_sink_model();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<BlockState> states;
    for (const auto& b : model.blocks) {
      BlockState s;
      s.pos = b.position0 + 0.3 * Vec3(u(rng), u(rng), u(rng));
      s.rot = b.orientation0 * rotation_matrix<double>(2.0 * Vec3(u(rng), u(rng), u(rng)));
      s.vel = Vec3(u(rng), u(rng), u(rng));
      s.acc = Vec3(u(rng), u(rng), u(rng));
      states.push_back(s);
    }
    // Every type, axis and drive between two bodies, a body and the ground, and the model's own.
    std::vector<Constraint> cases = model.constraints;
    auto joint = [&](const std::string& name) {
      for (std::size_t j = 0; j < model.joints.size(); ++j)
        if (model.joints[j].name == name) return static_cast<int>(j);
      throw std::runtime_error("no joint " + name);
    };
    const std::pair<std::string, std::string> pairs[] = {{"a.1", "b.0"}, {"ground.o", "a.0"}, {"b.1", "c.0"}};
    for (const auto& [n1, n2] : pairs)
      for (ConstraintType type : {ConstraintType::fixed, ConstraintType::revolute, ConstraintType::prismatic,
                                  ConstraintType::spherical})
        for (int axis = 0; axis < 3; ++axis)
          for (int drive : {-1, 0}) {
            if (drive >= 0 && (type == ConstraintType::fixed || type == ConstraintType::spherical)) continue;
            Constraint c;
            c.name = n1 + "-" + n2 + " " + to_string(type) + " axis " + std::to_string(axis) +
                     (drive >= 0 ? " driven" : "");
            c.type = type;
            c.axis = axis;
            c.joint1 = joint(n1);
            c.joint2 = joint(n2);
            c.drive = drive;
            cases.push_back(c);
          }
    int nontrivial = 0;
    for (const Constraint& c : cases) {
      double lambda[ConstraintEval::kMaxRows];
      for (double& l : lambda) l = 10 * u(rng);
      ConstraintInputs in;
      in.model = &model;
      in.constraint = &c;
      in.block_state = [&states](int b) -> const BlockState& { return states[b]; };
      in.drive = c.drive >= 0 ? model.drives[c.drive].evaluate(0.3 + trial) : DriveValue{};
      in.lambda = lambda;
      in.with_velocity_terms = true;
      const ConstraintEval a = evaluate_constraint(in), b = evaluate_constraint_ad(in);
      ASSERT_EQ(a.cols, b.cols);
      const double scale = 1 + b.G.cwiseAbs().maxCoeff();
      EXPECT_LT((a.g - b.g).cwiseAbs().maxCoeff(), 1e-13 * scale) << c.name;
      EXPECT_LT((a.G - b.G).cwiseAbs().maxCoeff(), 1e-13 * scale) << c.name;
      EXPECT_LT((a.g_u - b.g_u).cwiseAbs().maxCoeff(), 1e-13 * scale) << c.name;
      EXPECT_LT((a.H - b.H).cwiseAbs().maxCoeff(), 1e-12 * (1 + b.H.cwiseAbs().maxCoeff())) << c.name << "\n"
                                                                                                << a.H << "\n\n" << b.H;
      EXPECT_LT((a.g_dot - b.g_dot).cwiseAbs().maxCoeff(), 1e-12 * scale) << c.name;
      EXPECT_LT((a.gamma - b.gamma).cwiseAbs().maxCoeff(), 1e-12 * (1 + b.gamma.cwiseAbs().maxCoeff())) << c.name;
      if (b.H.cwiseAbs().maxCoeff() > 0.0) ++nontrivial;  // a spherical joint at a body's origin has none
    }
    EXPECT_GT(nontrivial, static_cast<int>(cases.size()) * 3 / 4);
  }
}

JointPairFrames<double> frames(const Vec3& r1, const Mat3& R1, const Vec3& r2, const Mat3& R2) {
  return JointPairFrames<double>{r1, r2, R1, R2};
}

Eigen::VectorXd values(ConstraintType type, int axis, bool driven, const JointPairFrames<double>& f, double u = 0) {
  Constraint c;
  c.type = type;
  c.axis = axis;
  c.drive = driven ? 0 : -1;
  Eigen::VectorXd g(c.rows());
  constraint_values<double>(c, f, u, g.data());
  return g;
}

TEST(Constraints, RevoluteAllowsExactlyTheRotationAboutItsAxis) {
  const Mat3 R1 = rotation_matrix<double>(Vec3(0.3, -0.4, 0.2));
  const Vec3 p(1, 2, 3);
  for (int axis = 0; axis < 3; ++axis) {
    const Mat3 about = R1 * rotation_matrix<double>(1.1 * Vec3::Unit(axis));
    EXPECT_LT(values(ConstraintType::revolute, axis, false, frames(p, R1, p, about)).norm(), 1e-14);
    // Driven: satisfied exactly at the prescribed angle, sin(theta - u) otherwise.
    EXPECT_LT(values(ConstraintType::revolute, axis, true, frames(p, R1, p, about), 1.1).norm(), 1e-14);
    EXPECT_NEAR(values(ConstraintType::revolute, axis, true, frames(p, R1, p, about), 0.6)(5), std::sin(0.5), 1e-14);
    const Mat3 other = R1 * rotation_matrix<double>(0.2 * Vec3::Unit((axis + 1) % 3));
    EXPECT_GT(values(ConstraintType::revolute, axis, false, frames(p, R1, p, other)).norm(), 0.1);
  }
}

TEST(Constraints, PrismaticAllowsExactlyTheSlideAlongItsAxis) {
  const Mat3 R = rotation_matrix<double>(Vec3(-0.2, 0.5, 0.9));
  const Vec3 p(0.5, -1, 2);
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 q = p + 0.75 * R.col(axis);
    EXPECT_LT(values(ConstraintType::prismatic, axis, false, frames(p, R, q, R)).norm(), 1e-14);
    EXPECT_NEAR(values(ConstraintType::prismatic, axis, true, frames(p, R, q, R), 0.5)(5), 0.25, 1e-14);
    const Vec3 off = p + 0.3 * R.col((axis + 1) % 3);
    EXPECT_GT(values(ConstraintType::prismatic, axis, false, frames(p, R, off, R)).norm(), 0.1);
  }
}

TEST(Constraints, FixedAndSphericalVanishOnlyWhereTheyShould) {
  const Mat3 R = rotation_matrix<double>(Vec3(1.0, 0.2, -0.7));
  const Vec3 p(1, 1, 1);
  EXPECT_LT(values(ConstraintType::fixed, 0, false, frames(p, R, p, R)).norm(), 1e-14);
  const Mat3 turned = R * rotation_matrix<double>(Vec3(0.05, 0, 0));
  EXPECT_GT(values(ConstraintType::fixed, 0, false, frames(p, R, p, turned)).norm(), 0.04);
  EXPECT_LT(values(ConstraintType::spherical, 0, false, frames(p, R, p, turned)).norm(), 1e-14);
}

// The reaction written to the results is the constraint force of the equations of motion
// M a + F - f_ext + G^T lambda = 0: the wrench on joint 2 (and its opposite on joint 1), moved to
// each free block's origin, is -G^T lambda in that block's variables (rotations: body-frame
// torques), for every constraint type of the kitchen-sink model at a random (violated) state.
TEST(Constraints, ReactionsAreTheConstraintForcesOfTheEquationsOfMotion) {
  const Model model = testing::kitchen_sink_model();
  const DofMap dofs(model, 0, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> r(-1, 1);
  std::vector<double> u(static_cast<std::size_t>(dofs.global_size()));
  for (double& x : u) x = 0.3 * r(rng);
  for (int i = dofs.global_size() - model.num_multipliers(); i < dofs.global_size(); ++i) u[i] = 1e3 * r(rng);
  ModelState state(model, dofs);
  state.set(0.37, u, {}, {}, Parametrization::rotation_vector_rates);

  int checked = 0;
  for (int c = 0; c < static_cast<int>(model.constraints.size()); ++c) {
    const Constraint& con = model.constraints[c];
    SCOPED_TRACE(con.name);
    ConstraintInputs in;
    in.model = &model;
    in.constraint = &con;
    in.block_state = [&](int b) -> const BlockState& { return state.block(b); };
    in.drive = con.drive >= 0 ? model.drives[con.drive].evaluate(state.time()) : DriveValue{};
    const ConstraintEval e = evaluate_constraint(in);
    const Eigen::VectorXd lambda = state.multipliers(c);
    const Eigen::VectorXd q =
        -e.G.topLeftCorner(e.rows, e.cols).transpose() * lambda;  // generalized constraint forces

    const ConstraintReaction reaction = state.constraint_reaction(c);
    const Vec3 p1 = state.joint_position(con.joint1);
    EXPECT_LT((reaction.point - state.joint_position(con.joint2)).norm(), 1e-14);
    const double scale = lambda.cwiseAbs().maxCoeff();
    for (int k = 0; k < e.cols / 3; ++k) {
      const int b = e.blocks[static_cast<std::size_t>(k)];
      // Which side the block carries, and the wrench on that side about the side's joint.
      const Joint& j1 = model.joints[con.joint1];
      const Joint& j2 = model.joints[con.joint2];
      const bool side2 = b == j2.translation_block || b == j2.rotation_block;
      ASSERT_TRUE(side2 || b == j1.translation_block || b == j1.rotation_block);
      const Vec3 force = side2 ? reaction.force : Vec3(-reaction.force);
      const Vec3 moment = side2 ? reaction.moment : Vec3(-reaction.moment - (reaction.point - p1).cross(reaction.force));
      const Vec3 at = side2 ? reaction.point : p1;
      Vec3 expected;
      if (model.blocks[b].kind == SlotKind::rotation) {
        const int t = side2 ? j2.translation_block : j1.translation_block;
        expected = state.block(b).rot.transpose() * ((at - state.block(t).pos).cross(force) + moment);
      } else {
        expected = force;
      }
      // The opposite wrench on joint 1 is exact only where the constraint holds: rows r1 - r2 are
      // not invariant under a common rotation, so the state's violation |p2 - p1| shows up there.
      const double slack = side2 || model.blocks[b].kind != SlotKind::rotation
                               ? 0.0
                               : (reaction.point - p1).norm() * reaction.force.norm();
      EXPECT_LE((q.segment<3>(3 * k) - expected).norm(), 1e-9 * scale + slack) << "block " << b;
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

}  // namespace
}  // namespace latticedyn
