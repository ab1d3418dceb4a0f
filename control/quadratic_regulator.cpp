// The quadratic regulator of thesis 6.3 as one sparse QP over the whole horizon for PETSc TAO
// (eq. 6-1), the receding-horizon loop over it (eq. 6-2), and the Riccati LQR used as reference.
#include "control/quadratic_regulator.hpp"

#include <petsctao.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

namespace latticedyn {
namespace {

// Bounds at or beyond this magnitude mean "none" (the caller's 1e300 or an infinity).
constexpr double kNoBound = 1e300;

bool is_bound(double b) { return std::isfinite(b) && std::abs(b) < kNoBound; }

// Default tolerances of the QP (options -qr_tao_gatol, -qr_tao_catol override). PDIPM measures
// the norm of the whole KKT residual (Lagrangian gradient and complementarity) against gatol and
// of the constraint residual against catol. Its barrier parameter falls tenfold an iteration, so
// a tight gatol costs only a few iterations.
constexpr double kGradientTolerance = 1e-12;
constexpr double kConstraintTolerance = 1e-10;
constexpr int kMaxIterations = 200;

// Decision vector z = [u_0, x_1, u_1, x_2, ..., u_{N-1}, x_N]: each stage's control next to the
// state it produces, so the Hessian is block diagonal and the dynamics Jacobian block bidiagonal;
// the KKT matrix is then banded in stage order and a sparse factorisation of it costs O(N).
struct Layout {
  int nx = 0, nu = 0, steps = 0;
  int stage() const { return nx + nu; }
  int u(int k) const { return k * stage(); }             // k = 0..N-1
  int x(int k) const { return (k - 1) * stage() + nu; }  // k = 1..N
  int size() const { return steps * stage(); }
};

// Sets the entries of s*M into the block at (row0, col0): only nonzeros, plus the diagonal of a
// diagonal block so that every row has its diagonal (zero for a semidefinite weight).
PetscErrorCode set_block(Mat mat, int row0, int col0, const Eigen::MatrixXd& M, double s, bool diagonal_block) {
  PetscFunctionBeginUser;
  for (int i = 0; i < M.rows(); ++i)
    for (int j = 0; j < M.cols(); ++j)
      if (M(i, j) != 0.0 || (diagonal_block && i == j))
        PetscCall(MatSetValue(mat, row0 + i, col0 + j, s * M(i, j), INSERT_VALUES));
  PetscFunctionReturn(0);
}

// One QP of horizon N over which TAO iterates; it keeps the Tao, the constant matrices and the
// symbolic factorisation, so that the receding horizon solves it again from each new x0.
class RegulatorQp {
 public:
  RegulatorQp() = default;
  ~RegulatorQp() {
    TaoDestroy(&tao_);
    MatDestroy(&H_);
    MatDestroy(&J_eq_);
    MatDestroy(&J_in_);
    VecDestroy(&z_);
    VecDestroy(&lower_);
    VecDestroy(&upper_);
    VecDestroy(&c_eq_);
    VecDestroy(&c_in_);
  }
  RegulatorQp(const RegulatorQp&) = delete;
  RegulatorQp& operator=(const RegulatorQp&) = delete;

  struct Result {
    Eigen::MatrixXd states;    // (N+1) x nx, row 0 = x0, as the optimiser left them
    Eigen::MatrixXd controls;  // N x nu, clipped to the control bounds
    int iterations = 0;
    TaoConvergedReason reason = TAO_CONTINUE_ITERATING;
    double residual = 0.0, constraint_norm = 0.0;
    PetscErrorCode error = 0;  // of TaoSolve, when it failed (and this QP can no longer be used)
    std::string type;
    std::string reason_text() const {
      return error ? "failed with PETSc error " + std::to_string(static_cast<int>(error)) : TaoConvergedReasons[reason];
    }
  };

  // `problem` must outlive this object.
  PetscErrorCode setup(const QuadraticRegulatorProblem& problem);
  // Solves from x0, starting from the last solution shifted by `shift` stages (0: as it is).
  PetscErrorCode solve(const Eigen::VectorXd& x0, int shift, Result* result);

 private:
  static PetscErrorCode objective_and_gradient(Tao, Vec z, PetscReal* f, Vec g, void* ctx);
  static PetscErrorCode hessian(Tao, Vec, Mat, Mat, void*);
  static PetscErrorCode equality_constraints(Tao, Vec z, Vec c, void* ctx);
  static PetscErrorCode inequality_constraints(Tao, Vec z, Vec c, void* ctx);
  static PetscErrorCode constant_jacobian(Tao, Vec, Mat, Mat, void*);
  PetscErrorCode assemble_hessian();
  PetscErrorCode assemble_equality_jacobian();
  PetscErrorCode set_bounds();
  PetscErrorCode configure_tao();
  PetscErrorCode initial_guess(const Eigen::VectorXd& x0, int shift);

  const QuadraticRegulatorProblem* p_ = nullptr;
  Layout layout_;
  Eigen::VectorXd x0_;
  double scale_ = 1.0;     // of the objective
  double distance_ = 1.0;  // largest initial error, at least 1
  bool solved_ = false;
  // Variables with an upper but no lower bound become inequality rows ub - z >= 0: TAOPDIPM of
  // PETSc 3.18 files such a variable under the lower-bound-only list (pdipm.c,
  // TaoPDIPMSetUpBounds: "ixub[pdipm->nxlb++]"), which corrupts its bound handling.
  std::vector<PetscInt> upper_only_;
  std::vector<double> upper_only_value_;
  Tao tao_ = nullptr;
  Mat H_ = nullptr, J_eq_ = nullptr, J_in_ = nullptr;
  Vec z_ = nullptr, lower_ = nullptr, upper_ = nullptr, c_eq_ = nullptr, c_in_ = nullptr;
};

PetscErrorCode RegulatorQp::setup(const QuadraticRegulatorProblem& problem) {
  PetscFunctionBeginUser;
  p_ = &problem;
  layout_ = Layout{static_cast<int>(problem.A.rows()), static_cast<int>(problem.B.cols()), problem.steps};
  // Objective scale 1 / (N w d^2), w the largest weight, d the largest initial error: PDIPM
  // starts every slack and bound multiplier at 1, and converges in ~30 iterations once the
  // multipliers of the scaled problem are O(1) or smaller; unscaled, the crane case (6-1) takes
  // 200 iterations and more (measured: scale 1 and 0.1 fail after 200, 1e-2 needs 163, 1e-5 to
  // 1e-9 need 26-28; 1/(N w d^2) = 4e-8 there).
  const double weight = std::max({problem.Q.cwiseAbs().maxCoeff(), problem.R.cwiseAbs().maxCoeff(),
                                   problem.P_end.cwiseAbs().maxCoeff()});
  distance_ = std::max(1.0, (problem.x0 - problem.x_target).cwiseAbs().maxCoeff());
  scale_ = 1.0 / (problem.steps * weight * distance_ * distance_);
  const int n = layout_.size();
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &z_));
  PetscCall(VecDuplicate(z_, &lower_));
  PetscCall(VecDuplicate(z_, &upper_));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, layout_.steps * layout_.nx, &c_eq_));
  PetscCall(assemble_hessian());
  PetscCall(assemble_equality_jacobian());
  PetscCall(set_bounds());
  PetscCall(configure_tao());
  PetscFunctionReturn(0);
}

// Hessian of J (and of the Lagrangian: the constraints are linear): blockdiag(2R, 2Q, ..., 2R,
// 2P_end). Constant, so assembled once; the Hessian callback leaves it as it is.
PetscErrorCode RegulatorQp::assemble_hessian() {
  const Layout& L = layout_;
  PetscFunctionBeginUser;
  std::vector<PetscInt> nnz(static_cast<std::size_t>(L.size()));
  for (int k = 0; k < L.steps; ++k) {
    std::fill_n(nnz.begin() + L.u(k), L.nu, L.nu);
    std::fill_n(nnz.begin() + L.x(k + 1), L.nx, L.nx);
  }
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, L.size(), L.size(), 0, nnz.data(), &H_));
  for (int k = 0; k < L.steps; ++k) {
    PetscCall(set_block(H_, L.u(k), L.u(k), p_->R, 2.0 * scale_, true));
    const Eigen::MatrixXd& W = k + 1 == L.steps ? p_->P_end : p_->Q;
    PetscCall(set_block(H_, L.x(k + 1), L.x(k + 1), W, 2.0 * scale_, true));
  }
  PetscCall(MatAssemblyBegin(H_, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(H_, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

// Dynamics rows c_k = x_{k+1} - A x_k - B u_k (k = 0..N-1; x_0 is data, so row block 0 has no A).
PetscErrorCode RegulatorQp::assemble_equality_jacobian() {
  const Layout& L = layout_;
  PetscFunctionBeginUser;
  const int rows = L.steps * L.nx;
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, rows, L.size(), 1 + L.nx + L.nu, nullptr, &J_eq_));
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(L.nx, L.nx);
  for (int k = 0; k < L.steps; ++k) {
    const int row0 = k * L.nx;
    PetscCall(set_block(J_eq_, row0, L.x(k + 1), I, 1.0, false));
    PetscCall(set_block(J_eq_, row0, L.u(k), p_->B, -1.0, false));
    if (k > 0) PetscCall(set_block(J_eq_, row0, L.x(k), p_->A, -1.0, false));
  }
  PetscCall(MatAssemblyBegin(J_eq_, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J_eq_, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode RegulatorQp::set_bounds() {
  const Layout& L = layout_;
  PetscScalar *lo, *hi;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayWrite(lower_, &lo));
  PetscCall(VecGetArrayWrite(upper_, &hi));
  auto put = [&](int index, double l, double h) {
    lo[index] = is_bound(l) ? l : PETSC_NINFINITY;
    hi[index] = is_bound(h) ? h : PETSC_INFINITY;
    if (!is_bound(l) && is_bound(h)) {
      upper_only_.push_back(index);
      upper_only_value_.push_back(h);
      hi[index] = PETSC_INFINITY;
    }
  };
  for (int k = 0; k < L.steps; ++k) {
    for (int i = 0; i < L.nu; ++i) put(L.u(k) + i, p_->u_min(i), p_->u_max(i));
    for (int i = 0; i < L.nx; ++i) put(L.x(k + 1) + i, p_->x_min(i), p_->x_max(i));
  }
  PetscCall(VecRestoreArrayWrite(lower_, &lo));
  PetscCall(VecRestoreArrayWrite(upper_, &hi));
  if (!upper_only_.empty()) {
    const auto m = static_cast<PetscInt>(upper_only_.size());
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, m, &c_in_));
    PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, m, L.size(), 1, nullptr, &J_in_));
    for (PetscInt j = 0; j < m; ++j) PetscCall(MatSetValue(J_in_, j, upper_only_[j], -1.0, INSERT_VALUES));
    PetscCall(MatAssemblyBegin(J_in_, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J_in_, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

// TAOPDIPM (primal-dual interior point): it takes the Hessian, the bounds and the linear equality
// constraints as they are and solves each Newton step with one sparse direct factorisation of the
// KKT matrix, so a QP converges in 20-30 iterations to tight tolerances. TAOALMM, the fallback
// (-qr_tao_type almm), was tried: it stops at ~1e-5 on the small cases, and on the crane case its
// penalty diverges after 33 s.
// The KKT matrix is symmetric indefinite and grows ill-conditioned as the barrier falls (entries
// lambda_i / z_i from 1e-10 to 1e10): sparse LU with partial pivoting, KLU, which refactorises
// with fresh pivoting each time (PETSc calls klu_factor, not klu_refactor). Measured on the crane
// case (KKT order 13,600, 30 factorisations) and on the receding horizon of 30 steps (8,100
// factorisations of order ~1,000), wall time: KLU 0.04 s / 0.9 s, SuperLU 0.15 s / 2.3 s,
// UMFPACK 0.15 s / 3.5 s, MUMPS LU 0.8 s / 15 s; all give the same solution. MUMPS also needs
// its workspace raised (-qr_mat_mumps_icntl_14 200): its pivoting outgrows the estimate of its
// analysis near convergence (FACTOR_OUTMEMORY). MUMPS Cholesky (LDL^T) cannot be used: PDIPM of
// PETSc 3.18 asks the PC for its factor in TaoSetUp, before one exists ("Matrix not yet
// factored"); the inertia correction it would enable is not needed for a convex QP.
PetscErrorCode RegulatorQp::configure_tao() {
  PetscFunctionBeginUser;
  PetscCall(TaoCreate(PETSC_COMM_SELF, &tao_));
  // Prefix before the type: PDIPM gives its inner SNES (and KSP) the prefix it finds at creation.
  PetscCall(TaoSetOptionsPrefix(tao_, "qr_"));
  PetscCall(TaoSetType(tao_, TAOPDIPM));
  PetscCall(TaoSetSolution(tao_, z_));
  PetscCall(TaoSetVariableBounds(tao_, lower_, upper_));
  PetscCall(TaoSetObjectiveAndGradient(tao_, nullptr, objective_and_gradient, this));
  PetscCall(TaoSetHessian(tao_, H_, H_, hessian, this));
  PetscCall(TaoSetEqualityConstraintsRoutine(tao_, c_eq_, equality_constraints, this));
  PetscCall(TaoSetJacobianEqualityRoutine(tao_, J_eq_, J_eq_, constant_jacobian, this));
  if (c_in_) {
    PetscCall(TaoSetInequalityConstraintsRoutine(tao_, c_in_, inequality_constraints, this));
    PetscCall(TaoSetJacobianInequalityRoutine(tao_, J_in_, J_in_, constant_jacobian, this));
  }
  // gatol on the KKT residual of the scaled QP (gradient and complementarity), catol on the
  // dynamics rows (state units).
  PetscCall(TaoSetTolerances(tao_, kGradientTolerance, 0.0, 0.0));
  PetscCall(TaoSetConstraintTolerances(tao_, kConstraintTolerance * distance_, 0.0));
  PetscCall(TaoSetMaximumIterations(tao_, kMaxIterations));
  // PDIPM evaluates once an iteration; ALMM's inner quasi-Newton solves take thousands.
  PetscCall(TaoSetMaximumFunctionEvaluations(tao_, 1000000));
  PetscCall(TaoSetFromOptions(tao_));  // -qr_tao_type, -qr_tao_gatol, ... win
  PetscBool pdipm;
  PetscCall(PetscObjectTypeCompare((PetscObject)tao_, TAOPDIPM, &pdipm));
  if (pdipm) {
    KSP ksp;
    PC pc;
    PetscCall(TaoGetKSP(tao_, &ksp));
    PetscCall(KSPSetType(ksp, KSPPREONLY));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERKLU));
    // A failed factorisation must end the solve: PDIPM (3.18) would otherwise restart its inner
    // SNES, which fails again at once, forever.
    PetscCall(KSPSetErrorIfNotConverged(ksp, PETSC_TRUE));
    PetscCall(KSPSetFromOptions(ksp));  // -qr_ksp_type, -qr_pc_factor_mat_solver_type win
  }
  PetscFunctionReturn(0);
}

// J, with the constant e_0^T Q e_0 included so that f is the cost (6-1) itself.
PetscErrorCode RegulatorQp::objective_and_gradient(Tao, Vec z, PetscReal* f, Vec g, void* ctx) {
  const auto* self = static_cast<const RegulatorQp*>(ctx);
  const QuadraticRegulatorProblem& p = *self->p_;
  const Layout& L = self->layout_;
  const PetscScalar* za;
  PetscScalar* ga;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(z, &za));
  PetscCall(VecGetArrayWrite(g, &ga));
  const Eigen::VectorXd e0 = self->x0_ - p.x_target;
  double cost = e0.dot(p.Q * e0);
  for (int k = 0; k < L.steps; ++k) {
    const Eigen::Map<const Eigen::VectorXd> u(za + L.u(k), L.nu);
    const Eigen::VectorXd e = Eigen::Map<const Eigen::VectorXd>(za + L.x(k + 1), L.nx) - p.x_target;
    const Eigen::MatrixXd& W = k + 1 == L.steps ? p.P_end : p.Q;
    const Eigen::VectorXd Ru = p.R * u, We = W * e;
    cost += u.dot(Ru) + e.dot(We);
    Eigen::Map<Eigen::VectorXd>(ga + L.u(k), L.nu) = 2.0 * Ru;
    Eigen::Map<Eigen::VectorXd>(ga + L.x(k + 1), L.nx) = 2.0 * We;
  }
  *f = self->scale_ * cost;
  PetscCall(VecRestoreArrayRead(z, &za));
  PetscCall(VecRestoreArrayWrite(g, &ga));
  PetscCall(VecScale(g, self->scale_));
  PetscFunctionReturn(0);
}

PetscErrorCode RegulatorQp::hessian(Tao, Vec, Mat, Mat, void*) {
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);  // constant, assembled in setup
}

PetscErrorCode RegulatorQp::constant_jacobian(Tao, Vec, Mat, Mat, void*) {
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);  // linear constraints: assembled in setup
}

PetscErrorCode RegulatorQp::equality_constraints(Tao, Vec z, Vec c, void* ctx) {
  const auto* self = static_cast<const RegulatorQp*>(ctx);
  const QuadraticRegulatorProblem& p = *self->p_;
  const Layout& L = self->layout_;
  const PetscScalar* za;
  PetscScalar* ca;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(z, &za));
  PetscCall(VecGetArrayWrite(c, &ca));
  for (int k = 0; k < L.steps; ++k) {
    const Eigen::Map<const Eigen::VectorXd> u(za + L.u(k), L.nu), next(za + L.x(k + 1), L.nx);
    Eigen::Map<Eigen::VectorXd> row(ca + k * L.nx, L.nx);
    if (k == 0)
      row = next - p.A * self->x0_ - p.B * u;
    else
      row = next - p.A * Eigen::Map<const Eigen::VectorXd>(za + L.x(k), L.nx) - p.B * u;
  }
  PetscCall(VecRestoreArrayRead(z, &za));
  PetscCall(VecRestoreArrayWrite(c, &ca));
  PetscFunctionReturn(0);
}

// h(z) = ub - z >= 0 for the variables bounded from above only (see upper_only_).
PetscErrorCode RegulatorQp::inequality_constraints(Tao, Vec z, Vec c, void* ctx) {
  const auto* self = static_cast<const RegulatorQp*>(ctx);
  const PetscScalar* za;
  PetscScalar* ca;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(z, &za));
  PetscCall(VecGetArrayWrite(c, &ca));
  for (std::size_t j = 0; j < self->upper_only_.size(); ++j)
    ca[j] = self->upper_only_value_[j] - za[self->upper_only_[j]];
  PetscCall(VecRestoreArrayRead(z, &za));
  PetscCall(VecRestoreArrayWrite(c, &ca));
  PetscFunctionReturn(0);
}

// First solve: zero controls and the states they give (x0 held), clipped into the bounds. Later
// solves (receding horizon): the previous solution shifted by `shift` stages, its last stage
// repeated; an interior-point method restarts its slacks and multipliers anyway, so only the
// primal part is warm.
PetscErrorCode RegulatorQp::initial_guess(const Eigen::VectorXd& x0, int shift) {
  const Layout& L = layout_;
  PetscScalar *za;
  const PetscScalar *lo, *hi;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(z_, &za));
  if (!solved_) {
    Eigen::VectorXd x = x0;
    for (int k = 0; k < L.steps; ++k) {
      Eigen::Map<Eigen::VectorXd>(za + L.u(k), L.nu).setZero();
      x = p_->A * x;
      Eigen::Map<Eigen::VectorXd>(za + L.x(k + 1), L.nx) = x;
    }
  } else if (shift > 0) {
    const int s = std::min(shift, L.steps) * L.stage();
    std::copy(za + s, za + L.size(), za);
    for (int i = L.size() - s; i < L.size(); ++i) za[i] = za[i - L.stage()];
  }
  PetscCall(VecGetArrayRead(lower_, &lo));
  PetscCall(VecGetArrayRead(upper_, &hi));
  for (int i = 0; i < L.size(); ++i) za[i] = std::clamp(za[i], lo[i], hi[i]);
  for (std::size_t j = 0; j < upper_only_.size(); ++j)
    za[upper_only_[j]] = std::min(za[upper_only_[j]], upper_only_value_[j]);
  PetscCall(VecRestoreArrayRead(lower_, &lo));
  PetscCall(VecRestoreArrayRead(upper_, &hi));
  PetscCall(VecRestoreArray(z_, &za));
  PetscFunctionReturn(0);
}

PetscErrorCode RegulatorQp::solve(const Eigen::VectorXd& x0, int shift, Result* result) {
  const Layout& L = layout_;
  PetscFunctionBeginUser;
  x0_ = x0;
  PetscCall(initial_guess(x0, shift));
  // A failure inside the solve (a factorisation that fails) is a result to report, not an error
  // to pass on: PETSc's error handler returns it silently and TAO's reason stays "iterating".
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  result->error = TaoSolve(tao_);
  PetscCall(PetscPopErrorHandler());
  solved_ = true;
  PetscInt its;
  PetscReal f, residual, cnorm, xdiff;
  PetscCall(TaoGetSolutionStatus(tao_, &its, &f, &residual, &cnorm, &xdiff, &result->reason));
  TaoType type;
  PetscCall(TaoGetType(tao_, &type));
  result->type = type;
  result->iterations = static_cast<int>(its);
  result->residual = residual;
  result->constraint_norm = cnorm;
  Vec z;
  const PetscScalar* za;
  PetscCall(TaoGetSolution(tao_, &z));
  PetscCall(VecGetArrayRead(z, &za));
  result->states.resize(L.steps + 1, L.nx);
  result->controls.resize(L.steps, L.nu);
  result->states.row(0) = x0.transpose();
  for (int k = 0; k < L.steps; ++k) {
    // An interior-point iterate may sit a round-off outside a bound (the slacks, not the
    // variables, are kept positive): clip the controls so that they obey their bounds exactly.
    const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(za + L.u(k), L.nu);
    result->controls.row(k) = u.cwiseMax(p_->u_min).cwiseMin(p_->u_max).transpose();
    result->states.row(k + 1) = Eigen::Map<const Eigen::VectorXd>(za + L.x(k + 1), L.nx).transpose();
  }
  PetscCall(VecRestoreArrayRead(z, &za));
  PetscFunctionReturn(0);
}

std::string format(const char* fmt, auto... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

// The optimiser's states may differ from the simulated ones by the constraint tolerance,
// propagated along the horizon: more than 1e-6 of the state scale means they did not converge.
double mismatch_tolerance(const Eigen::MatrixXd& states) { return 1e-6 * std::max(1.0, states.cwiseAbs().maxCoeff()); }

}  // namespace

// Exact discretisation of the double integrator with the control held over the step (zero-order
// hold): A_c = [0 I; 0 0] has A_c^2 = 0, so exp(A_c ts) = I + A_c ts and the integral of
// exp(A_c s) B_c over the step is [ts^2/2 I; ts I]. Classical 4th-order Runge-Kutta reproduces
// the series of exp(A_c ts) up to ts^4, which here is the whole series: it gives the same A, B.
QuadraticRegulatorProblem double_integrator_problem(int dimension, double sample_time) {
  if (dimension < 1 || !(sample_time > 0.0))
    throw std::invalid_argument("double_integrator_problem: dimension >= 1 and sample_time > 0 needed");
  const int d = dimension;
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(d, d);
  QuadraticRegulatorProblem p;
  p.A = Eigen::MatrixXd::Identity(2 * d, 2 * d);
  p.A.topRightCorner(d, d) = sample_time * I;
  p.B.resize(2 * d, d);
  p.B << 0.5 * sample_time * sample_time * I, sample_time * I;
  p.x_min = Eigen::VectorXd::Constant(2 * d, -inf);
  p.x_max = Eigen::VectorXd::Constant(2 * d, inf);
  p.u_min = Eigen::VectorXd::Constant(d, -inf);
  p.u_max = Eigen::VectorXd::Constant(d, inf);
  p.sample_time = sample_time;
  return p;
}

std::string validate_quadratic_regulator(const QuadraticRegulatorProblem& p) {
  const auto nx = p.A.rows(), nu = p.B.cols();
  if (nx == 0 || p.A.cols() != nx) return "A must be square and not empty";
  if (nu == 0 || p.B.rows() != nx) return "B must have as many rows as A and at least one column";
  if (p.Q.rows() != nx || p.Q.cols() != nx || p.P_end.rows() != nx || p.P_end.cols() != nx)
    return "Q and P_end must be nx x nx";
  if (p.R.rows() != nu || p.R.cols() != nu) return "R must be nu x nu";
  if (p.x0.size() != nx || p.x_target.size() != nx || p.x_min.size() != nx || p.x_max.size() != nx)
    return "x0, x_target, x_min and x_max must have nx entries";
  if (p.u_min.size() != nu || p.u_max.size() != nu) return "u_min and u_max must have nu entries";
  if (p.steps < 1) return "steps must be at least 1";
  if (!p.A.allFinite() || !p.B.allFinite() || !p.Q.allFinite() || !p.R.allFinite() || !p.P_end.allFinite() ||
      !p.x0.allFinite() || !p.x_target.allFinite())
    return "A, B, Q, R, P_end, x0 and x_target must be finite";
  for (const Eigen::MatrixXd* W : {&p.Q, &p.R, &p.P_end}) {
    const double tol = 1e-12 * std::max(1.0, W->cwiseAbs().maxCoeff());
    if ((*W - W->transpose()).cwiseAbs().maxCoeff() > tol) return "Q, R and P_end must be symmetric";
    if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(*W, Eigen::EigenvaluesOnly).eigenvalues().minCoeff() < -tol)
      return "Q, R and P_end must be positive semidefinite";
  }
  if (Eigen::LLT<Eigen::MatrixXd>(p.R).info() != Eigen::Success) return "R must be positive definite";
  for (int i = 0; i < nx; ++i)
    if (std::isnan(p.x_min(i)) || std::isnan(p.x_max(i)) || p.x_min(i) > p.x_max(i)) return "x_min <= x_max needed";
  for (int i = 0; i < nu; ++i)
    if (std::isnan(p.u_min(i)) || std::isnan(p.u_max(i)) || p.u_min(i) > p.u_max(i)) return "u_min <= u_max needed";
  return {};
}

Eigen::MatrixXd simulate_quadratic_regulator(const QuadraticRegulatorProblem& p, const Eigen::VectorXd& x0,
                                             const Eigen::MatrixXd& controls) {
  Eigen::MatrixXd states(controls.rows() + 1, x0.size());
  states.row(0) = x0.transpose();
  for (Eigen::Index k = 0; k < controls.rows(); ++k)
    states.row(k + 1) = (p.A * states.row(k).transpose() + p.B * controls.row(k).transpose()).transpose();
  return states;
}

double quadratic_regulator_cost(const QuadraticRegulatorProblem& p, const Eigen::MatrixXd& states,
                                const Eigen::MatrixXd& controls) {
  const Eigen::Index N = controls.rows();
  double cost = 0.0;
  for (Eigen::Index k = 0; k < N; ++k) {
    const Eigen::VectorXd e = states.row(k).transpose() - p.x_target, u = controls.row(k).transpose();
    cost += e.dot(p.Q * e) + u.dot(p.R * u);
  }
  const Eigen::VectorXd eN = states.row(N).transpose() - p.x_target;
  return cost + eN.dot(p.P_end * eN);
}

PetscErrorCode solve_quadratic_regulator(const QuadraticRegulatorProblem& problem, QuadraticRegulatorSolution* solution) {
  PetscFunctionBeginUser;
  std::string invalid;
  PetscCallCXX(invalid = validate_quadratic_regulator(problem));
  PetscCheck(invalid.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "quadratic regulator: %s", invalid.c_str());
  RegulatorQp qp;
  RegulatorQp::Result r;
  PetscCall(qp.setup(problem));
  PetscCall(qp.solve(problem.x0, 0, &r));
  // Returned states obey the dynamics exactly: simulated from x0 under the returned controls.
  solution->controls = r.controls;
  solution->states = simulate_quadratic_regulator(problem, problem.x0, r.controls);
  solution->cost = quadratic_regulator_cost(problem, solution->states, solution->controls);
  solution->iterations = r.iterations;
  solution->state_mismatch = (solution->states - r.states).cwiseAbs().maxCoeff();
  const bool consistent = solution->state_mismatch <= mismatch_tolerance(solution->states);
  solution->converged = !r.error && r.reason > 0 && consistent;
  solution->message = format("TAO %s: %s after %d iterations (KKT residual %.2e, constraints %.2e); "
                             "simulated states differ by %.2e%s",
                             r.type.c_str(), r.reason_text().c_str(), r.iterations, r.residual,
                             r.constraint_norm, solution->state_mismatch, consistent ? "" : " (too much)");
  PetscFunctionReturn(0);
}

PetscErrorCode solve_receding_horizon(const QuadraticRegulatorProblem& problem, int horizon,
                                      QuadraticRegulatorSolution* solution) {
  PetscFunctionBeginUser;
  std::string invalid;
  PetscCallCXX(invalid = validate_quadratic_regulator(problem));
  PetscCheck(invalid.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "quadratic regulator: %s", invalid.c_str());
  PetscCheck(horizon >= 1, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "receding horizon: horizon %d < 1", horizon);
  // One QP of `horizon` steps, set up once (matrices, bounds, symbolic factorisation) and solved
  // again from each new state; set up anew only after a failed solve.
  QuadraticRegulatorProblem window = problem;
  window.steps = horizon;
  auto qp = std::make_unique<RegulatorQp>();
  PetscCall(qp->setup(window));
  const int N = problem.steps;
  solution->states.resize(N + 1, problem.A.rows());
  solution->controls.resize(N, problem.B.cols());
  solution->states.row(0) = problem.x0.transpose();
  solution->iterations = 0;
  solution->state_mismatch = 0.0;
  int failed = 0, first_failed = -1;
  std::string first_reason;
  RegulatorQp::Result r;
  // The plan of the last QP that gave finite controls, and how many steps ago it was made.
  Eigen::MatrixXd plan = Eigen::MatrixXd::Zero(horizon, problem.B.cols());
  int plan_age = horizon;
  for (int m = 0; m < N; ++m) {
    const Eigen::VectorXd x = solution->states.row(m).transpose();
    PetscCall(qp->solve(x, m > 0 ? 1 : 0, &r));
    solution->iterations += r.iterations;
    const Eigen::MatrixXd simulated = simulate_quadratic_regulator(window, x, r.controls);
    const double mismatch = (simulated - r.states).cwiseAbs().maxCoeff();
    solution->state_mismatch = std::max(solution->state_mismatch, mismatch);
    if (r.error || r.reason <= 0 || mismatch > mismatch_tolerance(simulated)) {
      if (failed++ == 0) first_failed = m, first_reason = r.reason_text();
    }
    if (r.error) {
      qp = std::make_unique<RegulatorQp>();
      PetscCall(qp->setup(window));
    }
    if (!r.error && r.controls.allFinite()) {
      plan = r.controls;
      plan_age = 0;
    } else {
      ++plan_age;  // the usual fallback: go on with the last plan, then with zero (clipped)
    }
    // Applied: the plan's current control (clipped to its bounds), and the state it leads to.
    Eigen::VectorXd u = Eigen::VectorXd::Zero(plan.cols());
    if (plan_age < horizon) u = plan.row(plan_age).transpose();
    solution->controls.row(m) = u.cwiseMax(problem.u_min).cwiseMin(problem.u_max).transpose();
    solution->states.row(m + 1) = (problem.A * x + problem.B * solution->controls.row(m).transpose()).transpose();
  }
  solution->cost = quadratic_regulator_cost(problem, solution->states, solution->controls);
  solution->converged = failed == 0;
  solution->message = format("receding horizon %d over %d steps, TAO %s: %d iterations in all, ", horizon, N,
                             r.type.c_str(), solution->iterations);
  if (failed == 0)
    solution->message += "every QP converged";
  else
    solution->message += format("%d QPs failed, the first at step %d (%s)", failed, first_failed, first_reason.c_str());
  PetscFunctionReturn(0);
}

QuadraticRegulatorSolution solve_lqr_riccati(const QuadraticRegulatorProblem& p, std::vector<Eigen::MatrixXd>* gains) {
  if (const std::string invalid = validate_quadratic_regulator(p); !invalid.empty())
    throw std::invalid_argument("solve_lqr_riccati: " + invalid);
  const double drift = (p.A * p.x_target - p.x_target).cwiseAbs().maxCoeff();
  if (drift > 1e-12 * std::max(1.0, p.x_target.cwiseAbs().maxCoeff()))
    throw std::invalid_argument("solve_lqr_riccati: x_target is not an equilibrium (A x_e != x_e)");
  const int N = p.steps;
  std::vector<Eigen::MatrixXd> K(static_cast<std::size_t>(N));
  Eigen::MatrixXd P = p.P_end;
  for (int k = N - 1; k >= 0; --k) {
    const Eigen::MatrixXd BtP = p.B.transpose() * P;
    K[k] = (p.R + BtP * p.B).ldlt().solve(BtP * p.A);
    P = p.Q + p.A.transpose() * P * (p.A - p.B * K[k]);
    P = 0.5 * (P + P.transpose());  // keep the round-off symmetric
  }
  QuadraticRegulatorSolution s;
  s.states.resize(N + 1, p.A.rows());
  s.controls.resize(N, p.B.cols());
  s.states.row(0) = p.x0.transpose();
  for (int k = 0; k < N; ++k) {
    const Eigen::VectorXd e = s.states.row(k).transpose() - p.x_target;
    s.controls.row(k) = (-K[k] * e).transpose();
    s.states.row(k + 1) = (p.A * s.states.row(k).transpose() + p.B * s.controls.row(k).transpose()).transpose();
  }
  s.cost = quadratic_regulator_cost(p, s.states, s.controls);
  s.converged = true;
  s.message = "finite-horizon LQR (backward Riccati recursion), bounds ignored";
  if (gains) *gains = std::move(K);
  return s;
}

}  // namespace latticedyn
