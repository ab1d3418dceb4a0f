// The library's facade: statics and dynamics against closed forms, advances in pieces against one
// advance, external drives, saved and restored states, and the errors a program gets.
#include "api/simulator.hpp"

#include "io/input_node.hpp"

#include <gtest/gtest.h>
#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>

namespace latticedyn {
namespace {


double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// The physical pendulum of examples/pendulum.yaml (10 degrees off the vertical, 1 m, 2 kg): half a
// period after its release it stands 10 degrees on the other side, at rest. Period
// 2 pi sqrt(I_O / (m g d)) = 1.6382 s for small amplitudes, 0.19 % longer at 10 degrees (the
// series 1 + theta^2/16: e.g. Landau & Lifshitz, Mechanics, section 11).
TEST(Simulator, PendulumSwingsToTheOtherSideInHalfAPeriod) {
  Simulator sim = Simulator::load(PENDULUM_MODEL);
  EXPECT_DOUBLE_EQ(sim.time(), 0.0);
  const double theta = 10.0 * std::numbers::pi / 180.0;
  const double period = 2.0 * std::numbers::pi * std::sqrt((2.0 / 3.0) / (2.0 * 9.81 * 0.5)) * (1.0 + theta * theta / 16.0);
  const ElementEnergy e0 = sim.energy();
  sim.advance(period / 2);
  EXPECT_NEAR(sim.time(), period / 2, 1e-12);
  const Vec3 tip = sim.joint_position("rod.tip");
  EXPECT_NEAR(tip.x(), std::sin(theta), 2e-4);
  EXPECT_NEAR(tip.z(), -std::cos(theta), 2e-4);
  EXPECT_LT(sim.joint_velocity("rod.tip").norm(), 2e-3);
  // rho_infinity 1: no numerical damping, the energy stays.
  const ElementEnergy e1 = sim.energy();
  const double total0 = e0.kinetic + e0.gravity_potential, total1 = e1.kinetic + e1.gravity_potential;
  EXPECT_NEAR(total1, total0, 1e-6 * std::abs(total0));
  // The probe row: the tip's position and velocity.
  const std::vector<double> probes = sim.probes();
  ASSERT_EQ(probes.size(), 6u);
  EXPECT_EQ(probes[0], tip.x());
  EXPECT_EQ(probes[2], tip.z());
}

// advance() continues the integrator: the steps of 0.25 s + 0.25 s + 0.5 s are those of one
// advance of 1 s, bit for bit.
TEST(Simulator, AdvancesInPiecesStepAsOneAdvance) {
  Simulator whole = Simulator::load(PENDULUM_MODEL), pieces = Simulator::load(PENDULUM_MODEL);
  whole.advance(1.0);
  pieces.advance(0.25);
  pieces.advance(0.25);
  pieces.advance(0.5);
  EXPECT_EQ(pieces.time(), whole.time());
  EXPECT_EQ(pieces.steps(), whole.steps());
  EXPECT_EQ(pieces.steps(), 500);  // 1 s at 0.002 s
  EXPECT_EQ(pieces.coordinates(), whole.coordinates());
}

// An interval that is not a multiple of the step: the last step lands on its end.
TEST(Simulator, TheLastStepOfAnAdvanceLandsOnItsEnd) {
  Simulator sim = Simulator::load(PENDULUM_MODEL);
  sim.advance(0.0031);
  EXPECT_NEAR(sim.time(), 0.0031, 1e-15);
  EXPECT_EQ(sim.steps(), 2);
  sim.advance(0.0069);
  EXPECT_NEAR(sim.time(), 0.01, 1e-15);
}

// The hanging pendulum's equilibrium: straight down, the hinge carrying its weight, its centre
// of mass 0.5 m below the pivot.
TEST(Simulator, StaticsOfTheHangingPendulum) {
  Simulator sim = Simulator::load(PENDULUM_MODEL);
  const StaticsSummary s = sim.solve_statics();
  EXPECT_GT(s.newton_iterations, 0);
  const Vec3 tip = sim.joint_position("rod.tip");
  EXPECT_NEAR(tip.x(), 0.0, 1e-9);
  EXPECT_NEAR(tip.z(), -1.0, 1e-9);
  const ConstraintReaction hinge = sim.constraint_reaction("hinge");
  EXPECT_NEAR(hinge.force.z(), 2.0 * 9.81, 1e-6);
  EXPECT_NEAR(hinge.force.x(), 0.0, 1e-6);
  EXPECT_NEAR(sim.energy().gravity_potential, -2.0 * 9.81 * 0.5, 1e-8);
  EXPECT_NEAR(sim.energy().kinetic, 0.0, 1e-12);
  // From the equilibrium it stays there.
  sim.advance(0.1);
  EXPECT_NEAR(sim.joint_position("rod.tip").x(), 0.0, 1e-9);
}

// An external drive moves as the program says: at a rate (value continuous), then with an
// acceleration (value and rate continuous); the driven revolute turns the rod with it.
TEST(Simulator, ExternalDrivesFollowTheRateAndTheAccelerationSet) {
  Simulator sim = Simulator::load(TURNED_ROD_MODEL);
  EXPECT_EQ(sim.external_drive_names(), std::vector<std::string>{"turn"});
  EXPECT_EQ(sim.drive_names(), (std::vector<std::string>{"turn", "fixed"}));
  sim.solve_statics();
  sim.set_drive_rate("turn", 0.5);
  sim.advance(1.0);
  EXPECT_NEAR(sim.drive("turn").value, 0.5, 1e-14);
  EXPECT_NEAR(sim.drive("turn").rate, 0.5, 1e-14);
  Vec3 tip = sim.joint_position("rod.tip");
  EXPECT_NEAR(tip.x(), std::cos(0.5), 1e-8);
  EXPECT_NEAR(tip.y(), std::sin(0.5), 1e-8);
  EXPECT_NEAR(sim.joint_velocity("rod.tip").norm(), 0.5, 1e-3);
  sim.set_drive_acceleration("turn", 1.0);
  sim.advance(1.0);
  // 0.5 + 0.5 t + t^2 / 2 at t = 1, rate 0.5 + t.
  EXPECT_NEAR(sim.drive("turn").value, 1.5, 1e-14);
  EXPECT_NEAR(sim.drive("turn").rate, 1.5, 1e-14);
  tip = sim.joint_position("rod.tip");
  EXPECT_NEAR(tip.x(), std::cos(1.5), 1e-8);
  EXPECT_NEAR(tip.y(), std::sin(1.5), 1e-8);
  EXPECT_NEAR(sim.joint_velocity("rod.tip").norm(), 1.5, 1e-3);
  // The orientation turned with it: the body's x axis points at the tip.
  const Mat3 R = sim.joint_orientation("rod.tip");
  EXPECT_NEAR(R(0, 0), std::cos(1.5), 1e-8);
  EXPECT_NEAR(R(1, 0), std::sin(1.5), 1e-8);
}

// A restored state advances the same every time, bit for bit, external drives included; it
// differs from the uninterrupted run only by the integrator's start-up steps.
TEST(Simulator, RestoredStatesAdvanceTheSameEveryTime) {
  Simulator sim = Simulator::load(TURNED_ROD_MODEL, {{"solver.dynamics.rho_infinity", "1.0"}});
  sim.set_drive_rate("turn", 0.3);
  sim.advance(0.3);
  const SimulatorState saved = sim.save_state();
  sim.set_drive_acceleration("turn", 2.0);
  sim.advance(0.3);
  const std::vector<double> uninterrupted = sim.coordinates();
  std::vector<std::vector<double>> replays;
  for (int k = 0; k < 2; ++k) {
    sim.restore_state(saved);
    EXPECT_EQ(sim.time(), saved.time);
    EXPECT_NEAR(sim.drive("turn").rate, 0.3, 1e-15);  // the drive as it was
    sim.set_drive_acceleration("turn", 2.0);
    sim.advance(0.3);
    replays.push_back(sim.coordinates());
  }
  EXPECT_EQ(replays[0], replays[1]);
  EXPECT_LT(max_difference(replays[0], uninterrupted), 1e-3);
  // Into a second simulator of the same model.
  Simulator other = Simulator::load(TURNED_ROD_MODEL, {{"solver.dynamics.rho_infinity", "1.0"}});
  other.restore_state(saved);
  other.set_drive_acceleration("turn", 2.0);
  other.advance(0.3);
  EXPECT_EQ(other.coordinates(), replays[0]);
}

TEST(Simulator, OverridesReplaceKeysOfTheModelFile) {
  Simulator sim = Simulator::load(PENDULUM_MODEL, {{"solver.dynamics.time_step", "0.001"}});
  EXPECT_EQ(sim.time_step(), 0.001);
  sim.advance(0.01);
  EXPECT_EQ(sim.steps(), 10);
  // The same from the file's text.
  std::ifstream file(PENDULUM_MODEL);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  Simulator from_text = Simulator::load_string(text, "pendulum.yaml", {{"solver.dynamics.time_step", "0.001"}});
  from_text.advance(0.01);
  EXPECT_EQ(from_text.coordinates(), sim.coordinates());
}

TEST(Simulator, ErrorsNameWhatIsWrong) {
  Simulator sim = Simulator::load(TURNED_ROD_MODEL);
  auto message = [](const auto& call) -> std::string {
    try {
      call();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(message([&] { sim.joint_position("rod.nose"); }).find("no joint 'rod.nose'"), std::string::npos);
  EXPECT_NE(message([&] { sim.axial_forces("arm"); }).find("no body 'arm'"), std::string::npos);
  EXPECT_NE(message([&] { sim.constraint_reaction("hinge"); }).find("no constraint 'hinge'"), std::string::npos);
  EXPECT_NE(message([&] { sim.set_drive_rate("fixed", 1.0); }).find("drive 'fixed' is prescribed"), std::string::npos);
  EXPECT_NE(message([&] { sim.set_drive_rate("spin", 1.0); }).find("no drive 'spin'"), std::string::npos);
  EXPECT_NE(message([&] { sim.set_drive_rate("turn", NAN); }).find("finite"), std::string::npos);
  EXPECT_NE(message([&] { sim.advance(0.0); }).find("interval > 0"), std::string::npos);
  EXPECT_THROW(Simulator::load_string("title: [", "broken.yaml"), InputError);
  try {
    Simulator::load(TURNED_ROD_MODEL, {{"solver.dynamics.time_step", "-1"}});
    ADD_FAILURE() << "a negative time step was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("time_step"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Simulator::load(TURNED_ROD_MODEL, {{"solver.dynamics.integrator", "baumgarte"}}),
               std::invalid_argument);
  // An external drive inside a sum has no name a program could set it by.
  EXPECT_THROW(Simulator::load(TURNED_ROD_MODEL,
                                      {{"drives.turn", "{type: sum, terms: [{type: external}]}"}}),
               InputError);
  // A state of another model.
  Simulator pendulum = Simulator::load(PENDULUM_MODEL);
  EXPECT_THROW(pendulum.restore_state(sim.save_state()), std::invalid_argument);
  // After an error the simulator goes on.
  sim.set_drive_rate("turn", 0.1);
  sim.advance(0.1);
  EXPECT_NEAR(sim.drive("turn").value, 0.01, 1e-15);
}

// A run that stops short (here at max_steps): SolverError saying where; the state is the last
// accepted step, and the simulator can be put back and go on.
TEST(Simulator, AFailedStepSaysWhereAndKeepsTheLastState) {
  Simulator sim = Simulator::load(TURNED_ROD_MODEL, {{"solver.dynamics.max_steps", "3"}});
  const SimulatorState start = sim.save_state();
  try {
    sim.advance(1.0);
    ADD_FAILURE() << "the run went past max_steps";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("stopped at t = 0.03"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("max_steps = 3"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(sim.time(), 0.03, 1e-12);
  EXPECT_EQ(sim.steps(), 3);
  sim.restore_state(start);
  sim.advance(0.02);
  EXPECT_NEAR(sim.time(), 0.02, 1e-12);
}

// The crane of Appendix D with its hoisting rope paid in by a program: the load rises.
TEST(Simulator, CraneHoistsItsLoadWhenTheProgramPaysInTheRope) {
  Simulator crane = Simulator::load(LIFTING_MODEL, {{"drives.hoisting", "{type: external, initial: 54.8342}"}});
  crane.solve_statics();
  const double z0 = crane.joint_position("load.1").z();
  const std::vector<double> rope0 = crane.axial_forces("hoisting_rope");
  ASSERT_FALSE(rope0.empty());
  EXPECT_GT(rope0.front(), 0.0);  // in tension
  crane.set_drive_rate("hoisting", -0.5);
  crane.advance(2.0);
  EXPECT_NEAR(crane.drive("hoisting").value, 54.8342 - 1.0, 1e-12);
  EXPECT_GT(crane.joint_position("load.1").z(), z0 + 0.1);
}

// The pendulum linearised about its hanging equilibrium: one independent coordinate, eigenvalues
// +-i sqrt(m g d / I_O) (I_O = m L^2 / 3, d = L / 2), and its tip moves along x by L per radian.
TEST(Simulator, LinearisedPendulumSwingsAtItsClosedFormFrequency) {
  Simulator sim = Simulator::load(PENDULUM_MODEL);
  sim.solve_statics();
  const LinearModel lm = sim.linearize({});
  EXPECT_EQ(lm.independent, 1);
  ASSERT_EQ(lm.A.rows(), 2);
  const double omega = std::sqrt(2.0 * 9.81 * 0.5 / (2.0 / 3.0));
  const Eigen::VectorXcd lambda = lm.mechanical_eigenvalues();
  EXPECT_NEAR(std::abs(lambda(0).imag()), omega, 1e-6 * omega);
  EXPECT_NEAR(lambda(0).real(), 0.0, 1e-9);
  EXPECT_EQ(lm.outputs.front(), "rod.tip.x");
  // dx_tip / dz = L times the unit basis vector's rotation part: |C(x, z)| / |C(vx, z')| = 1.
  EXPECT_NEAR(std::abs(lm.C(0, 0)), std::abs(lm.C(3, 1)), 1e-6);
  EXPECT_NEAR(lm.C(2, 0), 0.0, 1e-6);  // no vertical motion to first order
  EXPECT_NEAR(sim.natural_frequencies(1)[0], omega / (2 * std::numbers::pi), 1e-6);
}

/// The crane with its drives external, at its static equilibrium.
Simulator crane_at_rest() {
  Simulator crane = Simulator::load(CRANE_EXTERNAL_MODEL);
  crane.solve_statics();
  return crane;
}

// The crane's linear model has the natural frequencies `latticedyn modes` computes (SLEPc on the
// constrained K, M pencil): the same linearisation reduced another way.
TEST(Simulator, LinearisedCraneHasTheFrequenciesOfItsModes) {
  Simulator crane = crane_at_rest();
  const LinearModel lm = crane.linearize({"slewing", "luffing", "hoisting"});
  EXPECT_EQ(lm.inputs, (std::vector<std::string>{"slewing", "luffing", "hoisting"}));
  EXPECT_EQ(lm.B.cols(), 3);
  EXPECT_EQ(lm.C.rows(), 6);  // the probe load.1: position and velocity
  const std::vector<double> modes = crane.natural_frequencies(6);
  std::vector<double> linear;
  const Eigen::VectorXcd lambda = lm.mechanical_eigenvalues();
  // The lowest mode is a mechanism's zero (the hook block turning about its rope), which comes out
  // as a real or a complex pair at round-off: compared where the frequencies are not zero.
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (lambda(i).imag() > 0 && std::abs(lambda(i)) > 2 * std::numbers::pi * 1e-3)
      linear.push_back(std::abs(lambda(i)) / (2 * std::numbers::pi));
  std::sort(linear.begin(), linear.end());
  std::vector<double> nonzero;
  for (double f : modes)
    if (f > 1e-3) nonzero.push_back(f);
  ASSERT_GE(nonzero.size(), 4u);
  ASSERT_GE(linear.size(), nonzero.size());
  for (std::size_t k = 0; k < nonzero.size(); ++k) EXPECT_NEAR(linear[k], nonzero[k], 1e-5 * nonzero[k]) << "mode " << k;
  // Undamped at rest: every eigenvalue on the imaginary axis.
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    EXPECT_LT(std::abs(lambda(i).real()), 1e-6 * std::max(std::abs(lambda(i)), 1.0)) << i;
}

// Small inputs: the linear model's response follows the nonlinear crane's. A slewing pulse of
// 1e-3 rad/s^2 for 2 s, then -1e-3 for 2 s (4 mrad in all), sways the load; over 12 s its path
// from the linear model (exact for inputs held over each 0.05 s) stays within 3 % of the
// nonlinear one's largest excursion.
TEST(Simulator, LinearisedCraneRespondsAsTheNonlinearOneToSmallInputs) {
  Simulator crane = crane_at_rest();
  const LinearModel lm = crane.linearize({"slewing"});
  const std::vector<double> y0 = crane.probes();
  const double h = 0.05;
  const Eigen::Index nx = lm.A.rows();
  // Zero-order hold: exp([[A, B], [0, 0]] h).
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(nx + 1, nx + 1);
  aug.topLeftCorner(nx, nx) = lm.A * h;
  aug.topRightCorner(nx, 1) = lm.B * h;
  const Eigen::MatrixXd phi = aug.exp();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(nx);
  double largest = 0.0, worst = 0.0;
  for (int k = 0; k < 240; ++k) {
    const double t = h * k, w = t < 2.0 - 1e-9 ? 1e-3 : (t < 4.0 - 1e-9 ? -1e-3 : 0.0);
    if (k == 0 || k == 40 || k == 80) crane.set_drive_acceleration("slewing", w);
    crane.advance(h);
    Eigen::VectorXd xw(nx + 1);
    xw << x, w;
    x = (phi * xw).head(nx);
    const Eigen::VectorXd y = lm.C * x;
    const std::vector<double> now = crane.probes();
    for (int i = 0; i < 3; ++i) {  // the load's position
      largest = std::max(largest, std::abs(now[i] - y0[i]));
      worst = std::max(worst, std::abs(now[i] - y0[i] - y(i)));
    }
  }
  EXPECT_GT(largest, 1e-3);  // it did move
  EXPECT_LT(worst, 0.03 * largest) << "largest excursion " << largest;
}

TEST(Simulator, LinearModelsAreWrittenAsHdf5) {
  Simulator sim = Simulator::load(TURNED_ROD_MODEL);
  sim.solve_statics();
  const LinearModel lm = sim.linearize({"turn"});
  const std::string path = ::testing::TempDir() + "/turned_rod_linear.h5";
  Simulator::write_linear_model(path, lm);
  std::ifstream f(path, std::ios::binary);
  char magic[8];
  f.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "HDF");
  // A prescribed drive is no input.
  EXPECT_THROW(sim.linearize({"fixed"}), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
