// Solvers on small mechanisms with closed-form answers: static equilibrium of a pendulum and of a
// loaded two-bar truss, the small-amplitude period of a physical pendulum with both integrators,
// energy conservation of a free tumbling body, and rotation-vector rescaling on a fast spin.
#include "timestepping/baumgarte.hpp"
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/implicit_runge_kutta.hpp"
#include "timestepping/static_solver.hpp"

#include "../assembly/sample_models.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace latticedyn {
namespace {

struct Recorder : StepObserver {
  SystemAssembler& sa;
  ModelState state;
  std::vector<double> t, x, z, energy;
  int joint;
  Recorder(SystemAssembler& s, int j) : sa(s), state(s.model(), s.dofs()), joint(j) {}
  PetscErrorCode on_step(const StepInfo& info) override {
    PetscFunctionBeginUser;
    PetscCall(sa.gather(info.time, info.U, info.V, nullptr, info.param, &state));
    const Vec3 p = state.joint_position(joint);
    const ElementEnergy e = state.energy();
    t.push_back(info.time);
    x.push_back(p.x());
    z.push_back(p.z());
    energy.push_back(e.kinetic + e.gravity_potential + e.strain);
    PetscFunctionReturn(0);
  }
  // Period from successive upward zero crossings of x (linear interpolation).
  double period() const {
    std::vector<double> crossings;
    for (std::size_t i = 1; i < x.size(); ++i)
      if (x[i - 1] < 0 && x[i] >= 0) crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-x[i - 1]) / (x[i] - x[i - 1]));
    if (crossings.size() < 2) return 0.0;
    return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  }
};

// A rod-like rigid body hanging from a revolute joint about y at the origin, tip joint at -L z.
struct Pendulum {
  Model model;
  int tip;
  double inertia_pivot, mass, d;
};

Pendulum physical_pendulum(double angle) {
  ModelBuilder b;
  b.set_gravity(Vec3(0, 0, -9.81));
  const int pivot = b.add_ground_joint("ground.pivot", Vec3::Zero(), Mat3::Identity());
  const double L = 1.0, m = 2.0;
  const int body = b.add_body("rod", "rigid_body");
  const int bt = b.add_block(DofBlock::translation(Vec3::Zero(), Vec3::Zero(), "rod"));
  const int br = b.add_block(DofBlock::rotation(rotation_matrix<double>(Vec3(0, angle, 0)), Vec3::Zero(), "rod"));
  RigidBodyProperties p;
  p.mass = m;
  p.centroid = Vec3(0, 0, -L / 2);
  p.inertia_centroid = Vec3(m * L * L / 12, m * L * L / 12, 1e-3).asDiagonal();
  b.add_element(body, std::make_shared<RigidBody>(p), {{bt}, {br}});
  Joint o;
  o.name = "rod.o";
  o.translation_block = bt;
  o.rotation_block = br;
  const int jo = b.add_joint(body, o);
  Joint tip = o;
  tip.name = "rod.tip";
  tip.offset = Vec3(0, 0, -L);
  const int jt = b.add_joint(body, tip);
  Constraint c;
  c.name = "hinge";
  c.type = ConstraintType::revolute;
  c.axis = 1;
  c.joint1 = pivot;
  c.joint2 = jo;
  b.add_constraint(c, false);
  return Pendulum{b.build(), jt, m * L * L / 3, m, L / 2};
}

TEST(StaticSolver, PendulumHangsStraightDown) {
  Pendulum p = physical_pendulum(0.8);  // start 46 degrees off the vertical
  SystemAssembler sa(p.model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  StaticSettings s;
  s.load_steps = 2;
  StaticSolver solver(sa, s);
  StaticReport report;
  ASSERT_EQ(solver.solve(U, &report), 0);
  EXPECT_TRUE(report.converged) << report.message;
  ModelState state(p.model, sa.dofs());
  sa.gather(0, U, V, nullptr, Parametrization::rotation_vector_rates, &state);
  if (sa.dofs().rank() == 0) {
    const Vec3 tip = state.joint_position(p.tip);
    EXPECT_NEAR(tip.x(), 0.0, 1e-9);
    EXPECT_NEAR(tip.z(), -1.0, 1e-9);
    // The hinge carries the weight: lambda of the position rows = force on joint 2 (the rod).
    EXPECT_NEAR(state.multipliers(0)(2), p.mass * 9.81, 1e-6);
  }
  VecDestroy(&U);
  VecDestroy(&V);
}

// Small-amplitude physical pendulum: T = 2 pi sqrt(I_O / (m g d)), times the finite-amplitude
// factor 1 + theta0^2/16 (e.g. Landau & Lifshitz, Mechanics, section 11, problem 1).
double pendulum_period(const Pendulum& p, double theta0) {
  return 2 * std::numbers::pi * std::sqrt(p.inertia_pivot / (p.mass * 9.81 * p.d)) * (1 + theta0 * theta0 / 16);
}

template <class Integrator>
void expect_pendulum_period(double tol) {
  const double theta0 = 0.05;
  Pendulum p = physical_pendulum(theta0);
  SystemAssembler sa(p.model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  DynamicSettings s;
  s.t_end = 5.0;
  s.time_step = 2e-3;
  s.rho_infinity = 1.0;
  Integrator integrator(sa, s);
  Recorder rec(sa, p.tip);
  DynamicReport report;
  ASSERT_EQ(integrator.run(U, V, &rec, &report), 0);
  EXPECT_TRUE(report.completed) << report.message;
  if (sa.dofs().rank() == 0) {
    const double T = pendulum_period(p, theta0);
    EXPECT_NEAR(rec.period(), T, tol * T);
    EXPECT_LT(report.max_violation, 1e-8);
  }
  VecDestroy(&U);
  VecDestroy(&V);
}

TEST(GeneralizedAlpha, PhysicalPendulumPeriod) { expect_pendulum_period<GeneralizedAlphaIntegrator>(1e-4); }
TEST(Baumgarte, PhysicalPendulumPeriod) { expect_pendulum_period<BaumgarteIntegrator>(1e-4); }
TEST(ImplicitRungeKutta, PhysicalPendulumPeriod) { expect_pendulum_period<ImplicitRungeKuttaIntegrator>(1e-4); }

// A free body spinning fast about a tilted axis (12 rad/s about z, some about x and y).
Model spinner() {
  ModelBuilder b;
  const auto body = testing::add_rigid_body(b, "spinner", 3.0, Vec3::Zero(), Vec3(0.1, 0.2, 0.0), Vec3::Zero(),
                                            Vec3(0.5, 0.2, 12.0));
  testing::add_body_joint(b, body, "o", Vec3::Zero());
  return b.build();
}

// A generalized-alpha run of a model from its initial state: a joint's x and z and the energy at
// every step, and the run's report.
struct Swing {
  std::vector<double> x, z, energy;
  DynamicReport report;
};

Swing swing(const Model& model, int joint, double t_end, double h, int reuse, double rho_infinity = 0.9) {
  SystemAssembler sa(model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  DynamicSettings s;
  s.t_end = t_end;
  s.time_step = h;
  s.rho_infinity = rho_infinity;
  s.jacobian_reuse = reuse;
  GeneralizedAlphaIntegrator integrator(sa, s);
  Recorder rec(sa, joint);
  Swing out;
  EXPECT_EQ(integrator.run(U, V, &rec, &out.report), 0);
  EXPECT_TRUE(out.report.completed) << out.report.message;
  out.x = rec.x;
  out.z = rec.z;
  out.energy = rec.energy;
  VecDestroy(&U);
  VecDestroy(&V);
  return out;
}

// Jacobian reuse (a chord Newton method) converges to the same steps as fresh Jacobians: a
// pendulum swinging at 46 degrees, 2 s, and a fast spinner whose rotation rescales must refresh
// the Jacobian. Far fewer Jacobians than Newton iterations.
TEST(GeneralizedAlpha, JacobianReuseGivesTheSameMotionWithFewerJacobians) {
  const Pendulum p = physical_pendulum(0.8);
  const Swing fresh = swing(p.model, p.tip, 2.0, 1e-2, 1);
  const Swing reused = swing(p.model, p.tip, 2.0, 1e-2, 20);
  EXPECT_EQ(fresh.report.jacobians, fresh.report.newton_iterations);
  EXPECT_LT(3 * reused.report.jacobians, reused.report.newton_iterations);
  ASSERT_EQ(fresh.x.size(), reused.x.size());
  for (std::size_t i = 0; i < fresh.x.size(); ++i) {
    EXPECT_NEAR(reused.x[i], fresh.x[i], 1e-6) << "output " << i;
    EXPECT_NEAR(reused.z[i], fresh.z[i], 1e-6) << "output " << i;
  }
}

// A free body spinning fast about a tilted axis: rotation vectors pass |phi| = pi many times and
// are rescaled; kinetic energy must stay constant.
TEST(GeneralizedAlpha, FastSpinConservesEnergyThroughRescaling) {
  const Swing run = swing(spinner(), 0, 2.0, 1e-3, 1, 1.0);
  EXPECT_GT(run.report.rotation_rescales, 3);
  const auto [lo, hi] = std::minmax_element(run.energy.begin(), run.energy.end());
  EXPECT_LT((*hi - *lo) / run.energy.front(), 1e-4);
}

TEST(GeneralizedAlpha, JacobianReuseSurvivesRotationRescales) {
  const Model model = spinner();
  const Swing reused = swing(model, 0, 1.0, 1e-3, 50);
  EXPECT_GT(reused.report.rotation_rescales, 1);
  EXPECT_LT(reused.report.jacobians, reused.report.newton_iterations);
  const auto [lo, hi] = std::minmax_element(reused.energy.begin(), reused.energy.end());
  EXPECT_LT((*hi - *lo) / reused.energy.front(), 1e-4);
}

}  // namespace
}  // namespace latticedyn
