// The implicit Runge-Kutta route on a double pendulum (two rods on revolute joints, released from
// the horizontal): each method reaches its order of convergence against a fine reference, the
// projection keeps the joints closed to round-off, the energy of the undamped motion holds,
// adaptive steps follow their tolerances on both routes, and a slow swing is not taken for rest.
#include "timestepping/generalized_alpha.hpp"
#include "timestepping/implicit_runge_kutta.hpp"

#include "assembly/model_builder.hpp"
#include "assembly/model_state.hpp"
#include "elements/rigid_body.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace latticedyn {
namespace {

// Two uniform rods (1 m, 1 kg) along x, joined by revolute joints about y; the tip joint is 'tip'.
struct DoublePendulum {
  Model model;
  int tip = -1;
};

// `rods` such rods in a chain from the ground pivot, under `gravity`, the first one turning at w0
// about y at the start.
DoublePendulum rod_chain(int rods, const Vec3& gravity, double w0) {
  ModelBuilder b;
  b.set_gravity(gravity);
  const int pivot = b.add_ground_joint("ground.pivot", Vec3::Zero(), Mat3::Identity());
  RigidBodyProperties p;
  p.mass = 1.0;
  p.centroid = Vec3(0.5, 0, 0);
  p.inertia_centroid = Vec3(1e-4, 1.0 / 12, 1.0 / 12).asDiagonal();
  int previous = pivot, tip = -1;
  for (int k = 0; k < rods; ++k) {
    const std::string name = k == 0 ? "upper" : "lower";
    const int body = b.add_body(name, "rigid_body");
    const int bt = b.add_block(DofBlock::translation(Vec3(k, 0, 0), Vec3::Zero(), name));
    const int br = b.add_block(DofBlock::rotation(Mat3::Identity(), Vec3(0, k == 0 ? w0 : 0.0, 0), name));
    b.add_element(body, std::make_shared<RigidBody>(p), {{bt}, {br}});
    Joint top;
    top.name = name + ".top";
    top.translation_block = bt;
    top.rotation_block = br;
    const int jt = b.add_joint(body, top);
    Joint bottom = top;
    bottom.name = name + ".bottom";
    bottom.offset = Vec3(1, 0, 0);
    tip = b.add_joint(body, bottom);
    Constraint c;
    c.name = k == 0 ? "shoulder" : "elbow";
    c.type = ConstraintType::revolute;
    c.axis = 1;
    c.joint1 = previous;
    c.joint2 = jt;
    b.add_constraint(c, false);
    previous = tip;
  }
  return DoublePendulum{b.build(), tip};
}

DoublePendulum double_pendulum() { return rod_chain(2, Vec3(0, 0, -9.81), 0.0); }

struct Outcome {
  Vec3 tip = Vec3::Zero();
  double energy_drift = 0.0;  // largest |E - E0| over the run / largest kinetic energy
  DynamicReport report;
};

struct EnergyWatch : StepObserver {
  SystemAssembler& sa;
  ModelState state;
  double e0 = 0.0, drift = 0.0, kinetic = 0.0;
  bool first = true;
  explicit EnergyWatch(SystemAssembler& s) : sa(s), state(s.model(), s.dofs()) {}
  PetscErrorCode on_step(const StepInfo& info) override {
    PetscFunctionBeginUser;
    PetscCall(sa.gather(info.time, info.U, info.V, nullptr, info.param, &state));
    if (sa.dofs().rank() == 0) {
      const ElementEnergy e = state.energy();
      const double total = e.kinetic + e.gravity_potential + e.strain;
      if (first) e0 = total;
      first = false;
      drift = std::max(drift, std::abs(total - e0));
      kinetic = std::max(kinetic, e.kinetic);
    }
    PetscFunctionReturn(0);
  }
};

template <class Integrator>
Outcome simulate(const DoublePendulum& dp, DynamicSettings s) {
  SystemAssembler sa(dp.model, PETSC_COMM_WORLD);
  Vec U, V;
  sa.create_vector(&U);
  sa.create_vector(&V);
  sa.initial_state(U, V);
  Outcome out;
  EnergyWatch watch(sa);
  {
    Integrator integrator(sa, s);
    EXPECT_EQ(integrator.run(U, V, &watch, &out.report), 0);
  }
  ModelState state(dp.model, sa.dofs());
  sa.gather(s.t_end, U, V, nullptr, Parametrization::rotation_vector_rates, &state);
  if (sa.dofs().rank() == 0) out.tip = state.joint_position(dp.tip);
  out.energy_drift = watch.kinetic > 0 ? watch.drift / watch.kinetic : 0.0;
  VecDestroy(&U);
  VecDestroy(&V);
  return out;
}

DynamicSettings settings(const std::string& method, double h, double t_end = 1.0) {
  DynamicSettings s;
  s.integrator = IntegratorKind::implicit_rk;
  s.implicit_method = method;
  s.t_end = t_end;
  s.time_step = h;
  s.newton_tolerance = 1e-11;
  s.rho_infinity = 1.0;
  return s;
}

// Generalized-alpha (TSALPHA2) with rho_inf 0.9 and step h.
DynamicSettings alpha_settings(double h) {
  DynamicSettings s = settings("", h);
  s.integrator = IntegratorKind::generalized_alpha;
  s.rho_infinity = 0.9;
  return s;
}

// The tip at t = 1 s by ARKIMEX 5 with h = 1e-3 (its error there is below 1e-12: the method's
// fifth order from h = 0.01, where it errs by 1e-9).
const Vec3& reference_tip(const DoublePendulum& dp) {
  static const Vec3 tip = simulate<ImplicitRungeKuttaIntegrator>(dp, settings("arkimex:5", 1e-3)).tip;
  return tip;
}

struct OrderCase {
  std::string method;
  double order;
};

class ObservedOrder : public ::testing::TestWithParam<OrderCase> {};

// Error at t = 1 s for h = 0.01 and 0.005; the observed order log2(e1/e2) is the method's
// classical order (ARK3(2)4L[2]SA 3, ARK4(3)6L[2]SA 4, SDIRK l2 2: Kennedy & Carpenter 2003)
// on the index-1 system with projection. The Rosenbrock method ra34pw2 (order 3 for constant
// mass, Rang & Angermann 2005) is linearly implicit and here meets a mass matrix that depends
// on the rotation vectors: it falls to order 2, as Rosenbrock methods do for M(y) y' = f
// (Hairer & Wanner, Solving ODEs II, VI.4).
TEST_P(ObservedOrder, OnTheDoublePendulum) {
  const DoublePendulum dp = double_pendulum();
  const Vec3 ref = reference_tip(dp);
  const OrderCase c = GetParam();
  const Outcome coarse = simulate<ImplicitRungeKuttaIntegrator>(dp, settings(c.method, 0.01));
  const Outcome fine = simulate<ImplicitRungeKuttaIntegrator>(dp, settings(c.method, 0.005));
  ASSERT_TRUE(coarse.report.completed) << coarse.report.message;
  ASSERT_TRUE(fine.report.completed) << fine.report.message;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  const double e1 = (coarse.tip - ref).norm(), e2 = (fine.tip - ref).norm();
  EXPECT_NEAR(std::log2(e1 / e2), c.order, 0.25) << c.method << ": errors " << e1 << ", " << e2;
  EXPECT_LT(fine.report.max_violation, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(ImplicitRungeKutta, ObservedOrder,
                         ::testing::Values(OrderCase{"arkimex:3", 3.0}, OrderCase{"arkimex:4", 4.0},
                                           OrderCase{"arkimex:l2", 2.0}, OrderCase{"rosw:ra34pw2", 2.0}),
                         [](const auto& info) {
                           std::string n = info.param.method;
                           for (char& ch : n)
                             if (ch == ':') ch = '_';
                           return n;
                         });

// Generalized-alpha on the same pendulum: second order (Chung & Hulbert 1993).
TEST(GeneralizedAlpha, SecondOrderOnTheDoublePendulum) {
  const DoublePendulum dp = double_pendulum();
  const Vec3 ref = reference_tip(dp);
  DynamicSettings s = settings("", 0.01);
  s.integrator = IntegratorKind::generalized_alpha;
  const Outcome coarse = simulate<GeneralizedAlphaIntegrator>(dp, s);
  s.time_step = 0.005;
  const Outcome fine = simulate<GeneralizedAlphaIntegrator>(dp, s);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  EXPECT_NEAR(std::log2((coarse.tip - ref).norm() / (fine.tip - ref).norm()), 2.0, 0.2);
}

// Over 5 s of chaotic motion: the joints stay closed to round-off (the projection), and the
// energy, a constant of the motion, changes only by the method's damping of its local error.
TEST(ImplicitRungeKutta, ConstraintsAndEnergyOverFiveSeconds) {
  const DoublePendulum dp = double_pendulum();
  const Outcome out = simulate<ImplicitRungeKuttaIntegrator>(dp, settings("arkimex:4", 0.005, 5.0));
  ASSERT_TRUE(out.report.completed) << out.report.message;
  EXPECT_GE(out.report.steps, 1000);  // and a few cut steps
  EXPECT_LT(out.report.max_violation, 1e-11);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_LT(out.energy_drift, 1e-5);
  }
}

// Adaptive steps on the embedded error estimate (multipliers left out): a tolerance 100 times
// tighter gives an error at least 10 times smaller, with more steps. Returns the errors at t = 1 s
// and the runs (loose, tight).
struct ToleranceRuns {
  Outcome loose, tight;
  double e_loose = 0.0, e_tight = 0.0;
};

template <class Integrator>
ToleranceRuns expect_tolerance_control(DynamicSettings s, double tight_tolerance) {
  const DoublePendulum dp = double_pendulum();
  const Vec3 ref = reference_tip(dp);
  ToleranceRuns r;
  s.adaptive = true;
  s.time_step = 0.01;
  s.rtol = s.atol = 1e-4;
  r.loose = simulate<Integrator>(dp, s);
  s.rtol = s.atol = tight_tolerance;
  r.tight = simulate<Integrator>(dp, s);
  EXPECT_TRUE(r.loose.report.completed) << r.loose.report.message;
  EXPECT_TRUE(r.tight.report.completed) << r.tight.report.message;
  EXPECT_GT(r.tight.report.steps, r.loose.report.steps);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return r;
  r.e_loose = (r.loose.tip - ref).norm();
  r.e_tight = (r.tight.tip - ref).norm();
  EXPECT_LT(r.e_tight, 0.1 * r.e_loose) << r.e_loose << " -> " << r.e_tight;
  EXPECT_LT(r.e_tight, 1e-3);
  return r;
}

TEST(ImplicitRungeKutta, AdaptiveStepsFollowTheTolerance) {
  expect_tolerance_control<ImplicitRungeKuttaIntegrator>(settings("arkimex:3", 0.01), 1e-6);
}

// Generalized-alpha's adaptive steps (TSALPHA2's estimate: backward differences of positions and
// velocities over the last three steps, multipliers left out; rho_inf 0.9). The estimate is a
// second difference, O(h^2), so the step follows tol^(1/2) (100 times tighter: about 10 times the
// steps) and the error of the second-order method, O(h^2), follows the tolerance itself:
// measured 2.26e-5 m at 1e-4 (313 steps), 2.26e-6 at 1e-5 (992), 2.26e-7 at 1e-6 (3140), 2.2e-8
// at 1e-7 (9979). Second order is kept on the varying steps: the algorithmic acceleration lags
// the true one by (alpha_f - alpha_m) h (-0.053 h at rho_inf 0.9), so a step change dh shifts it by
// that factor times dh times the jerk; the controller's steps vary smoothly along the motion (dh =
// O(h^2)), which leaves O(h^3) per step. The joints stay closed. With rho_inf = 1 the index-3
// accelerations oscillate undamped, the estimate never falls and at 1e-6 the steps shrink until
// Newton fails: the model reader refuses that pairing.
TEST(GeneralizedAlpha, AdaptiveStepsFollowTheTolerance) {
  const ToleranceRuns r = expect_tolerance_control<GeneralizedAlphaIntegrator>(alpha_settings(0.01), 1e-6);
  EXPECT_GT(r.tight.report.steps, 5 * r.loose.report.steps);
  EXPECT_LT(r.tight.report.steps, 20 * r.loose.report.steps);
  EXPECT_LT(r.tight.report.max_violation, 1e-9);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  // The error proportional to the tolerance: 100 times tighter, at least 30 times smaller.
  EXPECT_LT(r.e_tight, r.e_loose / 30) << r.e_loose << " -> " << r.e_tight;
  EXPECT_LT(r.e_loose, 1e-4);
}

// A slow motion is still a motion: one rod hanging from its pivot (gravity along +x, its axis),
// set swinging at w0 = 1e-4 rad/s, its tip after a quarter period against the small-angle
// pendulum's -L sin(theta), theta = w0/wn sin(wn t), wn^2 = m g (L/2) / (m L^2/3). Every stage
// of the implicit Runge-Kutta route takes a Newton step, even where its first guess (the last
// stage, standing still) already meets the Newton tolerance in force units, as it does here from
// the first step on (|V| = 1e-4 rad/s against atol 1e-3 N): taken as guessed, a stage froze the
// rod where it was (tip at -1e-10 m), as it froze the reduced crane lifting from t = 55.6 s.
// Generalized-alpha's first guess is its predictor, which moves on.
template <class Integrator>
void expect_quarter_swing(DynamicSettings s, double rel_tol) {
  const double w0 = 1e-4, wn = std::sqrt(9.81 * 0.5 * 3.0);
  s.t_end = 0.5 * M_PI / wn;
  s.newton_tolerance = 1e-4;
  const Outcome out = simulate<Integrator>(rod_chain(1, Vec3(9.81, 0, 0), w0), s);
  ASSERT_TRUE(out.report.completed) << out.report.message;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  const double expected = -std::sin(w0 / wn);
  EXPECT_NEAR(out.tip.z(), expected, rel_tol * std::abs(expected)) << "tip " << out.tip.transpose();
}

TEST(ImplicitRungeKutta, ASlowSwingIsNotTakenForRest) {
  expect_quarter_swing<ImplicitRungeKuttaIntegrator>(settings("arkimex:3", 0.01), 1e-3);
}

TEST(GeneralizedAlpha, ASlowSwingIsNotTakenForRest) {
  expect_quarter_swing<GeneralizedAlphaIntegrator>(alpha_settings(0.01), 1e-2);
}

// A method the route does not have is refused by name.
TEST(ImplicitRungeKutta, RefusesAnUnknownFamily) {
  const DoublePendulum dp = double_pendulum();
  SystemAssembler sa(dp.model, PETSC_COMM_WORLD);
  EXPECT_THROW(ImplicitRungeKuttaIntegrator(sa, settings("bdf:2", 0.01)), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
