// Constraints into the rank's residual rows and Jacobian blocks.
#include "assembly/constraint_term.hpp"

namespace latticedyn {

namespace {
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}  // namespace

ConstraintInputs ConstraintTerm::inputs(int c, double t, const std::vector<BlockState>& states) const {
  const Constraint& con = model_.constraints[c];
  ConstraintInputs in;
  in.model = &model_;
  in.constraint = &con;
  in.block_state = [&states](int b) -> const BlockState& { return states[b]; };
  in.drive = con.drive >= 0 ? model_.drives[con.drive].evaluate(t) : DriveValue{};
  return in;
}

void ConstraintTerm::add_residual(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how,
                                  const double* lambda, bool distinct_c, double* r) const {
  for (int c : dofs_.local_constraints()) {
    const int mo = s.multiplier_offset[c];
    ConstraintInputs in = inputs(c, at.t, s.state);
    in.with_velocity_terms = how.rows == ConstraintRows::acceleration;
    const ConstraintEval ce = evaluate_constraint(in);
    for (int k = 0; k < 4 && ce.blocks[k] >= 0; ++k) {
      const int lo = s.offset(ce.blocks[k]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < ce.rows; ++j) r[lo + i] += ce.G(j, 3 * k + i) * lambda[mo + j];
    }
    if (how.rows == ConstraintRows::acceleration) {
      const double al = how.baumgarte_alpha, be = how.baumgarte_beta;
      // G a + Gamma* = 0 (4-3, 4-27): the second time derivative of g, stabilised.
      for (int j = 0; j < ce.rows; ++j) {
        double ga = 0.0;
        for (int k = 0; k < 4 && ce.blocks[k] >= 0; ++k) ga += ce.G.block<1, 3>(j, 3 * k).dot(s.state[ce.blocks[k]].acc);
        r[mo + j] = ga + ce.gamma(j) + 2 * al * be * ce.g_dot(j) + al * al * ce.g(j);
      }
    } else {
      const ConstraintInputs inc = inputs(c, at.tc, s.state_c);
      const ConstraintEval cc = distinct_c || at.tc != at.t ? evaluate_constraint(inc) : ce;
      for (int j = 0; j < ce.rows; ++j) r[mo + j] = how.constraint_scale * cc.g(j);
    }
  }
}

PetscErrorCode ConstraintTerm::add_jacobian(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how,
                                            const double* lambda, double cq, double ca, Mat J,
                                            std::vector<Vec3>& y) const {
  PetscFunctionBeginUser;
  const Eigen::Matrix3d zero3 = Eigen::Matrix3d::Zero();
  for (int c : dofs_.local_constraints()) {
    const Constraint& con = model_.constraints[c];
    const int mo = s.multiplier_offset[c];
    const int m = con.rows();
    ConstraintInputs in = inputs(c, at.t, s.state);
    in.lambda = lambda + mo;
    const ConstraintEval ce = evaluate_constraint(in);
    const int nblk = ce.cols / 3;
    std::vector<PetscInt> mult(m);
    for (int j = 0; j < m; ++j) mult[j] = dofs_.multiplier_dof(c) + j;

    for (int ki = 0; ki < nblk; ++ki) {
      const int bi = ce.blocks[ki];
      y[bi] += (ce.G.block(0, 3 * ki, m, 3).transpose() * Eigen::Map<const Eigen::VectorXd>(lambda + mo, m)).eval();
      PetscInt ri = dofs_.block_dof(bi);
      PetscInt rows[3] = {ri, ri + 1, ri + 2};
      // Geometric stiffness d(G^T lambda)/dq.
      for (int kj = 0; kj < nblk; ++kj) {
        const int bj = ce.blocks[kj];
        const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> blk = s.chain_block(bi, bj, cq, ce.H.block<3, 3>(3 * ki, 3 * kj), zero3, zero3);
        PetscInt cj = dofs_.block_dof(bj);
        PetscInt cols[3] = {cj, cj + 1, cj + 2};
        PetscCall(MatSetValues(J, 3, rows, 3, cols, blk.data(), ADD_VALUES));
      }
      // Multiplier columns: rows_I G^T, times dUc/dU since lambda is read from Uc.
      RowMajor gt = how.uc_per_u * s.chain[bi].rows * ce.G.block(0, 3 * ki, m, 3).transpose();
      PetscCall(MatSetValues(J, 3, rows, m, mult.data(), gt.data(), ADD_VALUES));
    }

    // Constraint rows.
    RowMajor grow;
    if (how.rows == ConstraintRows::acceleration) {
      for (int kj = 0; kj < nblk; ++kj) {
        const int bj = ce.blocks[kj];
        grow = ca * ce.G.block(0, 3 * kj, m, 3);
        PetscInt cj = dofs_.block_dof(bj);
        PetscInt cols[3] = {cj, cj + 1, cj + 2};
        PetscCall(MatSetValues(J, m, mult.data(), 3, cols, grow.data(), ADD_VALUES));
      }
    } else {
      const ConstraintInputs inc = inputs(c, at.tc, s.state_c);
      const ConstraintEval cc = evaluate_constraint(inc);
      for (int kj = 0; kj < cc.cols / 3; ++kj) {
        const int bj = cc.blocks[kj];
        grow = (cq * how.constraint_scale * how.uc_per_u) * cc.G.block(0, 3 * kj, m, 3) * s.chain_c[bj].col_K;
        PetscInt cj = dofs_.block_dof(bj);
        PetscInt cols[3] = {cj, cj + 1, cj + 2};
        PetscCall(MatSetValues(J, m, mult.data(), 3, cols, grow.data(), ADD_VALUES));
      }
    }
    for (int j = 0; j < m; ++j) PetscCall(MatSetValue(J, mult[j], mult[j], 0.0, ADD_VALUES));
  }
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
