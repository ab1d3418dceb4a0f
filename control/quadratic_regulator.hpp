// Discrete quadratic-regulator optimal control (thesis 6.3): the whole horizon as one sparse QP,
// eq. (6-1), solved by PETSc TAO, the receding-horizon (MPC) loop of eq. (6-2), and a Riccati LQR.
#pragma once

#include <Eigen/Dense>
#include <petscsys.h>

#include <string>
#include <vector>

namespace latticedyn {

/// Problem (6-1): minimise
///   J = e_N^T P_end e_N + sum_{k=0}^{N-1} (e_k^T Q e_k + u_k^T R u_k),  e_k = x_k - x_target,
/// subject to x_{k+1} = A x_k + B u_k, x_min <= x_k <= x_max (k = 1..N), u_min <= u_k <= u_max
/// (k = 0..N-1), x_0 given. A bound of magnitude >= 1e300 (or infinite) means "no bound".
/// Q, R, P_end symmetric; R positive definite, Q and P_end positive semidefinite.
struct QuadraticRegulatorProblem {
  Eigen::MatrixXd A, B;         ///< dynamics, nx x nx and nx x nu
  Eigen::MatrixXd Q, R, P_end;  ///< weights, nx x nx, nu x nu, nx x nx
  Eigen::VectorXd x0;           ///< initial state
  Eigen::VectorXd x_target;     ///< x_e
  Eigen::VectorXd x_min, x_max; ///< state bounds, applied to x_1..x_N
  Eigen::VectorXd u_min, u_max; ///< control bounds
  int steps = 0;                ///< N
  double sample_time = 0.0;     ///< ts [s] (informational: A and B already contain it)
};

struct QuadraticRegulatorSolution {
  Eigen::MatrixXd states;    ///< (N+1) x nx, row k = x_k (forward simulated from x0 with `controls`)
  Eigen::MatrixXd controls;  ///< N x nu, row k = u_k
  double cost = 0.0;         ///< J of (6-1) evaluated on `states` and `controls`
  int iterations = 0;        ///< optimiser iterations (summed over the QPs of a receding horizon)
  bool converged = false;    ///< the optimiser converged and its states obey the dynamics
  std::string message;       ///< convergence reason and a summary
  double state_mismatch = 0.0;  ///< max |x_k(optimiser) - x_k(simulated)| (largest over MPC steps)
};

/// A point mass in d dimensions as a double integrator, x = [p; v] (2d), u = a (d): A = [I ts I;
/// 0 I], B = [ts^2/2 I; ts I]. Only A, B, steps = 0 and sample_time are filled in: the caller
/// sets weights, bounds, x0, x_target and steps. Bounds are sized and set to "none". Throws
/// std::invalid_argument for dimension < 1 or sample_time <= 0.
QuadraticRegulatorProblem double_integrator_problem(int dimension, double sample_time);

/// Empty when the problem is well formed, else what is wrong with it (sizes, symmetry, bounds).
std::string validate_quadratic_regulator(const QuadraticRegulatorProblem& problem);

/// States x_0..x_N, one per row, from x0 under `controls` (N x nu) by the dynamics.
Eigen::MatrixXd simulate_quadratic_regulator(const QuadraticRegulatorProblem& problem, const Eigen::VectorXd& x0,
                                             const Eigen::MatrixXd& controls);

/// J of (6-1) for a trajectory (states (N+1) x nx, controls N x nu).
double quadratic_regulator_cost(const QuadraticRegulatorProblem& problem, const Eigen::MatrixXd& states,
                                const Eigen::MatrixXd& controls);

/// Solves (6-1) over the whole horizon as one sparse QP on PETSC_COMM_SELF with TAO (primal-dual
/// interior point, TAOPDIPM, with KLU factorising its KKT systems; options prefix "qr_", e.g.
/// -qr_tao_monitor, -qr_tao_gatol 1e-14, -qr_pc_factor_mat_solver_type umfpack, -qr_tao_type).
/// Not converging (or a failed factorisation) is reported in `solution`, not as an error; an
/// ill-formed problem is an error.
PetscErrorCode solve_quadratic_regulator(const QuadraticRegulatorProblem& problem, QuadraticRegulatorSolution* solution);

/// Receding-horizon control (6-2): at each step m = 0..N-1 solves (6-1) over `horizon` steps from
/// the current state, applies the first control and advances with the dynamics. Returns the
/// applied controls and the resulting states (N steps), their cost J, and the summed iterations;
/// `converged` only if every QP converged. Where a QP fails outright, the step applies the next
/// control of the last plan (zero, clipped to the bounds, once that plan is used up).
PetscErrorCode solve_receding_horizon(const QuadraticRegulatorProblem& problem, int horizon,
                                      QuadraticRegulatorSolution* solution);

/// Reference without bounds: the finite-horizon LQR by the backward Riccati recursion
///   P_N = P_end,  K_k = (R + B^T P_{k+1} B)^{-1} B^T P_{k+1} A,  P_k = Q + A^T P_{k+1} (A - B K_k),
/// u_k = -K_k (x_k - x_target), which needs x_target to be an equilibrium (A x_e = x_e, checked).
/// Bounds are ignored. `gains`, if given, receives K_0..K_{N-1}. Throws std::invalid_argument on
/// an ill-formed problem.
QuadraticRegulatorSolution solve_lqr_riccati(const QuadraticRegulatorProblem& problem,
                                             std::vector<Eigen::MatrixXd>* gains = nullptr);

}  // namespace latticedyn
