// Linearized buckling by SLEPc against Euler's column: a steel cantilever of co-rotational
// Timoshenko beams under an axial tip load buckles at P_cr = pi^2 EI / (4 L^2) (Timoshenko & Gere,
// Theory of Elastic Stability, 2nd ed. 1961, 2.1), lowered by shear to P_cr / (1 + P_cr / (kappa G A))
// (Engesser, ibid. 2.16); the load factor is P_cr / P. The same load reversed (tension) buckles
// only reversed: lambda = -P_cr / P.
#include "timestepping/buckling_analysis.hpp"

#include "assembly/model_builder.hpp"
#include "elements/timoshenko_beam.hpp"
#include "timestepping/static_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace latticedyn {
namespace {

constexpr double kLength = 10.0, kRadius = 0.05, kE = 2.06e11, kNu = 0.3;

Model column(int n, double tip_force) {
  ModelBuilder b;
  b.set_gravity(Vec3::Zero());
  const int body = b.add_body("column", "timoshenko_beam");
  BeamProperties p{Material{7800, kE, kNu, {}, 0.0}, round_tube_section(kRadius, 0.0), kLength / n, 0.0};
  auto beam = std::make_shared<TimoshenkoBeam>(p);
  std::vector<int> t, r;
  for (int k = 0; k <= n; ++k) {
    t.push_back(b.add_block(DofBlock::translation(Vec3(kLength * k / n, 0, 0), Vec3::Zero(), "n")));
    r.push_back(b.add_block(DofBlock::rotation(Mat3::Identity(), Vec3::Zero(), "n")));
  }
  for (int k = 0; k < n; ++k) b.add_element(body, beam, {{t[k]}, {r[k]}, {t[k + 1]}, {r[k + 1]}});
  Joint foot;
  foot.name = "column.1";
  foot.translation_block = t[0];
  foot.rotation_block = r[0];
  Joint tip = foot;
  tip.name = "column.2";
  tip.translation_block = t[n];
  tip.rotation_block = r[n];
  const int jf = b.add_joint(body, foot);
  const int jt = b.add_joint(body, tip);
  Constraint c;
  c.name = "clamp";
  c.type = ConstraintType::fixed;
  c.joint1 = b.add_ground_joint("ground.o", Vec3::Zero(), Mat3::Identity());
  c.joint2 = jf;
  b.add_constraint(c, false);
  NodalLoad load;
  load.name = "tip";
  load.joint = jt;
  load.force = Vec3(-tip_force, 0, 0);  // compression for tip_force > 0
  b.add_load(load);
  return b.build();
}

double euler_cantilever_load() {
  const double A = std::numbers::pi * kRadius * kRadius, I = A * kRadius * kRadius / 4;
  const double G = kE / (2 * (1 + kNu));
  // Cowper's shear coefficient of a solid circle, as round_tube_section gives it.
  const double kappa = 6 * (1 + kNu) / (7 + 6 * kNu);
  const double pe = std::numbers::pi * std::numbers::pi * kE * I / (4 * kLength * kLength);
  return pe / (1 + pe / (kappa * G * A));
}

std::vector<BucklingMode> buckle(const Model& model, int count, std::string* message) {
  SystemAssembler sa(model, PETSC_COMM_SELF);
  Vec U0, U1, V;
  sa.create_vector(&U0);
  sa.create_vector(&V);
  sa.initial_state(U0, V);
  VecDuplicate(U0, &U1);
  VecCopy(U0, U1);
  StaticSolver statics(sa, StaticSettings{});
  StaticReport result;
  EXPECT_EQ(statics.solve(U1, &result), 0);
  EXPECT_TRUE(result.converged) << result.message;
  BucklingAnalysis analysis(sa, BucklingSettings{count, 1e-10});
  std::vector<BucklingMode> modes;
  EXPECT_EQ(analysis.solve(U0, U1, 0.0, &modes, message), 0);
  VecDestroy(&U0);
  VecDestroy(&U1);
  VecDestroy(&V);
  return modes;
}

TEST(BucklingAnalysis, CantileverColumnBucklesAtEulersLoad) {
  const double pcr = euler_cantilever_load();
  const double P = 0.25 * pcr;  // a reference load well below buckling
  std::string message;
  std::vector<BucklingMode> modes = buckle(column(20, P), 4, &message);
  ASSERT_EQ(modes.size(), 4u) << message;
  // The round section buckles in either plane at the same load: the first two factors are a pair.
  // Twenty elements: the discretisation error of the co-rotational beam (measured +0.054 %).
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(modes[k].factor, pcr / P, 2e-3 * pcr / P) << "mode " << k;
    EXPECT_LT(modes[k].residual, 1e-6);
  }
  // The second Euler load of the cantilever is 9 times the first.
  EXPECT_NEAR(modes[2].factor, 9 * pcr / P, 0.02 * 9 * pcr / P);
  destroy_modes(modes);
}

TEST(BucklingAnalysis, FactorsConvergeWithTheMesh) {
  const double pcr = euler_cantilever_load();
  const double P = 0.25 * pcr;
  double previous_error = INFINITY;
  for (int n : {2, 4, 8, 16}) {
    std::string message;
    std::vector<BucklingMode> modes = buckle(column(n, P), 1, &message);
    ASSERT_EQ(modes.size(), 1u) << message;
    const double error = std::abs(modes[0].factor * P / pcr - 1);
    EXPECT_LT(error, 0.6 * previous_error) << n << " elements";
    previous_error = error;
    destroy_modes(modes);
  }
}

TEST(BucklingAnalysis, TensionBucklesOnlyReversed) {
  const double pcr = euler_cantilever_load();
  const double P = -0.25 * pcr;  // pulls the tip
  std::string message;
  std::vector<BucklingMode> modes = buckle(column(20, P), 2, &message);
  ASSERT_EQ(modes.size(), 2u) << message;
  for (const BucklingMode& m : modes) EXPECT_NEAR(m.factor, pcr / P, 2e-3 * std::abs(pcr / P));
  destroy_modes(modes);
}

}  // namespace
}  // namespace latticedyn
