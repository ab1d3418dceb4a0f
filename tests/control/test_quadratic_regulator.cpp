// Quadratic regulator (thesis 6.3) by TAO against closed forms: the Riccati LQR without bounds,
// the optimality (KKT) conditions with active control bounds, a saturated speed, the receding
// horizon (6-2) against the full horizon (6-1), and the crane case of thesis Table 8-2.
#include "control/quadratic_regulator.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <random>

namespace latticedyn {
namespace {

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A symmetric positive definite n x n matrix with entries of order 1.
Eigen::MatrixXd random_spd(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = U(rng);
  return M * M.transpose() + 0.5 * Eigen::MatrixXd::Identity(n, n);
}

// Thesis Table 8-2: the load end point in the vertical plane, x = [p_x, p_z, v_x, v_z].
QuadraticRegulatorProblem crane_case(int steps) {
  QuadraticRegulatorProblem p = double_integrator_problem(2, 0.1);
  p.Q = 100 * Eigen::MatrixXd::Identity(4, 4);
  p.P_end = p.Q;
  p.R = Eigen::MatrixXd::Identity(2, 2);
  p.x0 = Eigen::Vector4d(-10, 0, 0, 0);
  p.x_target = Eigen::Vector4d(-35, 10, 0, 0);
  p.x_max = Eigen::Vector4d(-5, 30, 1, 1);
  p.x_min = Eigen::Vector4d(-50, 0, -1, -1);
  p.u_min = Eigen::Vector2d(-0.2, -0.2);
  p.u_max = Eigen::Vector2d(0.2, 0.2);
  p.steps = steps;
  return p;
}

// A 1-D move by 1 m in 5 s with |u| <= 0.5: the unconstrained LQR starts with u_0 = 2.8.
QuadraticRegulatorProblem control_bounded_case() {
  QuadraticRegulatorProblem p = double_integrator_problem(1, 0.1);
  p.Q = Eigen::Vector2d(10, 1).asDiagonal();
  p.R = Eigen::MatrixXd::Identity(1, 1);
  p.P_end = Eigen::Vector2d(100, 10).asDiagonal();
  p.x0 = Eigen::Vector2d(0, 0);
  p.x_target = Eigen::Vector2d(1, 0);
  p.u_min = Eigen::VectorXd::Constant(1, -0.5);
  p.u_max = Eigen::VectorXd::Constant(1, 0.5);
  p.steps = 50;
  return p;
}

// Reduced gradient dJ/du_k with the states eliminated by the dynamics (adjoint recursion):
// lambda_N = 2 P_end e_N, lambda_k = 2 Q e_k + A^T lambda_{k+1}, dJ/du_k = 2 R u_k + B^T lambda_{k+1}.
Eigen::MatrixXd reduced_gradient(const QuadraticRegulatorProblem& p, const QuadraticRegulatorSolution& s) {
  const int N = p.steps;
  Eigen::MatrixXd g(N, p.B.cols());
  Eigen::VectorXd lambda = 2.0 * p.P_end * (s.states.row(N).transpose() - p.x_target);
  for (int k = N - 1; k >= 0; --k) {
    g.row(k) = (2.0 * p.R * s.controls.row(k).transpose() + p.B.transpose() * lambda).transpose();
    lambda = 2.0 * p.Q * (s.states.row(k).transpose() - p.x_target) + p.A.transpose() * lambda;
  }
  return g;
}

TEST(QuadraticRegulator, DoubleIntegratorIsTheExactDiscretisation) {
  const double ts = 0.1;
  const QuadraticRegulatorProblem p = double_integrator_problem(2, ts);
  // Constant acceleration a over one step from p0, v0: p0 + v0 ts + a ts^2 / 2, v0 + a ts.
  const Eigen::Vector4d x(1, 2, 3, 4);
  const Eigen::Vector2d a(5, 6);
  const Eigen::Vector4d expected(1 + 3 * ts + 2.5 * ts * ts, 2 + 4 * ts + 3 * ts * ts, 3 + 5 * ts, 4 + 6 * ts);
  EXPECT_LT(max_abs(p.A * x + p.B * a - expected), 1e-14);
}

// Without bounds, (6-1) is the finite-horizon LQR: TAO's QP solution equals the Riccati one.
TEST(QuadraticRegulator, UnconstrainedEqualsRiccati) {
  std::mt19937 rng(7);
  QuadraticRegulatorProblem p = double_integrator_problem(2, 0.1);
  p.Q = random_spd(4, rng);
  p.R = random_spd(2, rng);
  p.P_end = 10 * random_spd(4, rng);
  p.x0 = Eigen::Vector4d(1.0, -2.0, 0.5, 0.3);
  p.x_target = Eigen::Vector4d(-1.0, 0.5, 0, 0);  // at rest: an equilibrium
  p.steps = 20;
  p.x_min.setConstant(-1e300);  // 1e300 means "no bound", like infinity
  p.x_max.setConstant(1e300);
  QuadraticRegulatorSolution s;
  ASSERT_EQ(solve_quadratic_regulator(p, &s), 0);
  ASSERT_TRUE(s.converged) << s.message;
  const QuadraticRegulatorSolution ref = solve_lqr_riccati(p);
  EXPECT_LT(max_abs(s.controls - ref.controls), 1e-6 * max_abs(ref.controls)) << s.message;
  EXPECT_LT(max_abs(s.states - ref.states), 1e-6 * max_abs(ref.states));
  EXPECT_NEAR(s.cost, ref.cost, 1e-9 * ref.cost);
}

// Tight control bounds, active at the start: the bounds hold, the first controls sit on the
// upper bound, the KKT conditions of the control-bounded problem hold (reduced gradient zero
// where a control is free, pointing out of the box where it is at a bound), and the optimum beats
// the unconstrained LQR controls clipped to the bounds.
TEST(QuadraticRegulator, ActiveControlBoundsSatisfyKkt) {
  const QuadraticRegulatorProblem p = control_bounded_case();
  std::vector<Eigen::MatrixXd> K;
  const QuadraticRegulatorSolution lqr = solve_lqr_riccati(p, &K);
  ASSERT_GT(lqr.controls(0, 0), 2 * p.u_max(0));  // the bound must matter

  QuadraticRegulatorSolution s;
  ASSERT_EQ(solve_quadratic_regulator(p, &s), 0);
  ASSERT_TRUE(s.converged) << s.message;
  EXPECT_LE(s.controls.maxCoeff(), p.u_max(0));
  EXPECT_GE(s.controls.minCoeff(), p.u_min(0));
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(s.controls(k, 0), p.u_max(0), 1e-7) << "step " << k;

  const Eigen::MatrixXd g = reduced_gradient(p, s);
  const double tol = 1e-6 * max_abs(g), at_bound = 1e-7;
  int free_controls = 0;
  for (int k = 0; k < p.steps; ++k) {
    const double u = s.controls(k, 0);
    if (u >= p.u_max(0) - at_bound) {
      EXPECT_LE(g(k, 0), tol) << "upper bound, step " << k;
    } else if (u <= p.u_min(0) + at_bound) {
      EXPECT_GE(g(k, 0), -tol) << "lower bound, step " << k;
    } else {
      EXPECT_LE(std::abs(g(k, 0)), tol) << "free, step " << k;
      ++free_controls;
    }
  }
  EXPECT_GE(free_controls, 10);

  // The unconstrained LQR controls clipped to the bounds: feasible, but not optimal. The LQR
  // feedback saturated at the bounds comes close here (the bounds are active only at the start,
  // after which the feedback is optimal for the state reached): not better, to the round-off of
  // the interior point (its controls stop ~1e-9 inside the active bounds).
  const Eigen::MatrixXd clipped = lqr.controls.cwiseMax(p.u_min(0)).cwiseMin(p.u_max(0));
  const double clipped_cost = quadratic_regulator_cost(p, simulate_quadratic_regulator(p, p.x0, clipped), clipped);
  EXPECT_LT(s.cost, clipped_cost);
  Eigen::MatrixXd saturated(p.steps, 1);
  Eigen::VectorXd x = p.x0;
  for (int k = 0; k < p.steps; ++k) {
    saturated(k, 0) = std::clamp((-K[k] * (x - p.x_target))(0), p.u_min(0), p.u_max(0));
    x = p.A * x + p.B * saturated.row(k).transpose();
  }
  const double saturated_cost = quadratic_regulator_cost(p, simulate_quadratic_regulator(p, p.x0, saturated), saturated);
  EXPECT_LT(s.cost, saturated_cost * (1 + 1e-8));
  EXPECT_GT(s.cost, lqr.cost);
}

// A long move with |v| <= 1: the speed saturates at its bound for a stretch of the way, and a
// bound given on one side only (the other infinite) gives the same optimum.
TEST(QuadraticRegulator, SpeedBoundSaturates) {
  QuadraticRegulatorProblem p = double_integrator_problem(1, 0.1);
  p.Q = Eigen::Vector2d(10, 0).asDiagonal();  // semidefinite: position error only
  p.R = Eigen::MatrixXd::Identity(1, 1);
  p.P_end = Eigen::Vector2d(100, 100).asDiagonal();
  p.x0 = Eigen::Vector2d(0, 0);
  p.x_target = Eigen::Vector2d(10, 0);
  p.x_min(1) = -1;
  p.x_max(1) = 1;
  p.u_min(0) = -1;
  p.u_max(0) = 1;
  p.steps = 150;
  ASSERT_GT(solve_lqr_riccati(p).states.col(1).maxCoeff(), 1.5);  // the bound must matter

  QuadraticRegulatorSolution s;
  ASSERT_EQ(solve_quadratic_regulator(p, &s), 0);
  ASSERT_TRUE(s.converged) << s.message;
  const Eigen::VectorXd v = s.states.col(1);
  EXPECT_LE(v.maxCoeff(), 1 + 1e-8);
  EXPECT_GE(v.minCoeff(), -1 - 1e-8);
  EXPECT_LE(max_abs(s.controls), 1.0);
  int saturated = 0;
  for (Eigen::Index k = 0; k < v.size(); ++k) saturated += v(k) > 1 - 1e-6;
  EXPECT_GE(saturated, 30) << "steps at the speed bound";
  EXPECT_NEAR(s.states(p.steps, 0), 10.0, 0.05);

  p.x_min(1) = -std::numeric_limits<double>::infinity();  // upper bound only
  QuadraticRegulatorSolution one_sided;
  ASSERT_EQ(solve_quadratic_regulator(p, &one_sided), 0);
  ASSERT_TRUE(one_sided.converged) << one_sided.message;
  EXPECT_LT(max_abs(one_sided.controls - s.controls), 1e-6 * max_abs(s.controls));
}

// MPC with the full horizon applies, at each step, the first control of the full-horizon QP from
// the current state: the first equals that of (6-1), the second that of a QP solved from x_1
// (this also checks that the QP reused across steps solves like a fresh one).
TEST(QuadraticRegulator, RecedingHorizonStartsWithTheFullHorizonControl) {
  QuadraticRegulatorProblem p = control_bounded_case();
  p.u_min(0) = -2;  // active over the first steps (the LQR starts with u_0 = 2.8)
  p.u_max(0) = 2;
  const int horizon = p.steps;
  QuadraticRegulatorSolution full;
  ASSERT_EQ(solve_quadratic_regulator(p, &full), 0);
  ASSERT_TRUE(full.converged) << full.message;

  QuadraticRegulatorProblem two_steps = p;
  two_steps.steps = 2;
  QuadraticRegulatorSolution mpc;
  ASSERT_EQ(solve_receding_horizon(two_steps, horizon, &mpc), 0);
  ASSERT_TRUE(mpc.converged) << mpc.message;
  EXPECT_NEAR(mpc.controls(0, 0), full.controls(0, 0), 1e-6 * max_abs(full.controls));

  QuadraticRegulatorProblem from_x1 = p;
  from_x1.x0 = mpc.states.row(1).transpose();
  QuadraticRegulatorSolution second;
  ASSERT_EQ(solve_quadratic_regulator(from_x1, &second), 0);
  ASSERT_TRUE(second.converged) << second.message;
  EXPECT_NEAR(mpc.controls(1, 0), second.controls(0, 0), 1e-6 * max_abs(second.controls));
}

// MPC with a 3 s horizon on the crane case (Table 8-2) brings the load to the target within the
// bounds.
TEST(QuadraticRegulator, RecedingHorizonReachesCraneTarget) {
  const QuadraticRegulatorProblem p = crane_case(400);
  QuadraticRegulatorSolution s;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(solve_receding_horizon(p, 30, &s), 0);
  const double wall = seconds_since(start);
  RecordProperty("wall_time_s", std::to_string(wall));
  std::printf("receding horizon 30, N = 400: %.3f s; %s\n", wall, s.message.c_str());
  ASSERT_TRUE(s.converged) << s.message;
  const Eigen::VectorXd xN = s.states.row(p.steps).transpose();
  EXPECT_LT((xN.head(2) - p.x_target.head(2)).norm(), 0.05);
  for (int k = 1; k <= p.steps; ++k)
    for (int i = 0; i < 4; ++i) {
      EXPECT_LE(s.states(k, i), p.x_max(i) + 1e-8) << "step " << k << ", state " << i;
      EXPECT_GE(s.states(k, i), p.x_min(i) - 1e-8) << "step " << k << ", state " << i;
    }
  EXPECT_LE(max_abs(s.controls), 0.2);
}

// Thesis Table 8-2 over the full horizon (Figure 8-15): the load ends within 1 cm of the target,
// the speed runs at its bound of 1 m/s for part of the way, and no bound is exceeded.
TEST(QuadraticRegulator, CraneCaseTable8_2) {
  const QuadraticRegulatorProblem p = crane_case(400);
  QuadraticRegulatorSolution s;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(solve_quadratic_regulator(p, &s), 0);
  const double wall = seconds_since(start);
  RecordProperty("wall_time_s", std::to_string(wall));
  std::printf("full horizon N = 400: %.3f s; %s\n", wall, s.message.c_str());
  ASSERT_TRUE(s.converged) << s.message;
  const Eigen::VectorXd xN = s.states.row(p.steps).transpose();
  EXPECT_LT((xN.head(2) - p.x_target.head(2)).norm(), 0.01);
  EXPECT_LE(max_abs(s.states.rightCols(2)), 1 + 1e-8);
  EXPECT_LE(max_abs(s.controls), 0.2);
  EXPECT_GT(s.states.col(2).cwiseAbs().maxCoeff(), 1 - 1e-6) << "the horizontal speed reaches its bound";
  for (int i = 0; i < 2; ++i) {
    EXPECT_LE(s.states.col(i).maxCoeff(), p.x_max(i) + 1e-8);
    EXPECT_GE(s.states.col(i).minCoeff(), p.x_min(i) - 1e-8);
  }
  EXPECT_LT(s.state_mismatch, 1e-8);
}

// MUMPS factorises the KKT matrix as well, given room for its pivoting (ICNTL(14)).
TEST(QuadraticRegulator, MumpsOptionGivesTheSameOptimum) {
  const QuadraticRegulatorProblem p = control_bounded_case();
  QuadraticRegulatorSolution base, mumps;
  ASSERT_EQ(solve_quadratic_regulator(p, &base), 0);
  ASSERT_EQ(PetscOptionsSetValue(nullptr, "-qr_pc_factor_mat_solver_type", "mumps"), 0);
  ASSERT_EQ(PetscOptionsSetValue(nullptr, "-qr_mat_mumps_icntl_14", "200"), 0);
  const PetscErrorCode error = solve_quadratic_regulator(p, &mumps);
  PetscOptionsClearValue(nullptr, "-qr_pc_factor_mat_solver_type");
  PetscOptionsClearValue(nullptr, "-qr_mat_mumps_icntl_14");
  ASSERT_EQ(error, 0);
  ASSERT_TRUE(base.converged && mumps.converged) << base.message << "\n" << mumps.message;
  EXPECT_LT(max_abs(mumps.controls - base.controls), 1e-7);
}

TEST(QuadraticRegulator, IllFormedProblemIsAnError) {
  QuadraticRegulatorProblem p = control_bounded_case();
  p.R = Eigen::MatrixXd::Identity(2, 2);  // nu is 1
  EXPECT_FALSE(validate_quadratic_regulator(p).empty());
  QuadraticRegulatorSolution s;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode error = solve_quadratic_regulator(p, &s);
  PetscPopErrorHandler();
  EXPECT_NE(error, 0);
  EXPECT_THROW(solve_lqr_riccati(p), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
