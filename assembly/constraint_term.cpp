// Constraints into the rank's residual rows and Jacobian blocks.
#include "assembly/constraint_term.hpp"

#include "core/rotation.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

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
        r[mo + j] = how.constraint_scale * (ga + ce.gamma(j) + 2 * al * be * ce.g_dot(j) + al * al * ce.g(j));
      }
    } else {
      const ConstraintInputs inc = inputs(c, at.tc, s.state_c);
      const ConstraintEval cc = distinct_c || at.tc != at.t ? evaluate_constraint(inc) : ce;
      for (int j = 0; j < ce.rows; ++j) r[mo + j] = how.constraint_scale * cc.g(j);
    }
  }
}

std::pair<Eigen::Matrix<double, Eigen::Dynamic, 3>, Eigen::Matrix<double, Eigen::Dynamic, 3>>
ConstraintTerm::acceleration_row_derivatives(int c, double t, const LocalState& s, int block, int rows) const {
  const SlotKind kind = model_.blocks[block].kind;
  const int n = kind == SlotKind::scalar ? 1 : 3;
  Eigen::Matrix<double, Eigen::Dynamic, 3> d_pose = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(rows, 3);
  Eigen::Matrix<double, Eigen::Dynamic, 3> d_vel = d_pose;
  BlockState perturbed = s.state[block];
  auto row_values = [&]() {
    ConstraintInputs in = inputs(c, t, s.state);
    in.block_state = [&](int b) -> const BlockState& { return b == block ? perturbed : s.state[b]; };
    in.with_velocity_terms = true;
    const ConstraintEval ce = evaluate_constraint(in);
    Eigen::VectorXd r(rows);
    for (int j = 0; j < rows; ++j) {
      double ga = 0.0;
      for (int k = 0; k < 4 && ce.blocks[k] >= 0; ++k)
        ga += ce.G.block<1, 3>(j, 3 * k).dot(ce.blocks[k] == block ? perturbed.acc : s.state[ce.blocks[k]].acc);
      r(j) = ga + ce.gamma(j);
    }
    return r;
  };
  const BlockState base = s.state[block];
  for (int i = 0; i < n; ++i) {
    const double hp = 1e-6 * std::max(1.0, kind == SlotKind::rotation ? 1.0 : std::abs(base.pos(i)));
    Eigen::VectorXd plus, minus;
    for (double sign : {1.0, -1.0}) {
      perturbed = base;
      if (kind == SlotKind::rotation) perturbed.rot = base.rot * rotation_matrix(Vec3(sign * hp * Vec3::Unit(i)));
      else perturbed.pos(i) += sign * hp;
      (sign > 0 ? plus : minus) = row_values();
    }
    d_pose.col(i) = (plus - minus) / (2 * hp);
    const double hv = 1e-6 * std::max(1.0, std::abs(base.vel(i)));
    for (double sign : {1.0, -1.0}) {
      perturbed = base;
      perturbed.vel(i) += sign * hv;
      (sign > 0 ? plus : minus) = row_values();
    }
    d_vel.col(i) = (plus - minus) / (2 * hv);
  }
  return {d_pose, d_vel};
}

PetscErrorCode ConstraintTerm::add_jacobian(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how,
                                            const double* lambda, double cq, double cv, Mat J,
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
      // d(G acc)/d(U, V, A) through the block's chain map (col_M = cq Q + cv S + ca T): in velocity
      // variables with cq = cv = 0 just ca G (the Baumgarte route's [M G^T; G 0]); in rotation-vector
      // rates the implicit Runge-Kutta route's rows. The derivatives of G and Gamma themselves are
      // left out: next to ca ~ 1/h^2 they are O(h^2) and only slow Newton's last digits.
      const bool rates_too = cq != 0.0 || cv != 0.0;
      for (int kj = 0; kj < nblk; ++kj) {
        const int bj = ce.blocks[kj];
        Eigen::Matrix<double, Eigen::Dynamic, 3> block = ce.G.block(0, 3 * kj, m, 3) * s.chain[bj].col_M;
        if (rates_too) {
          // The row's dependence on the block's pose and velocity (G's and Gamma's): central
          // differences of the closed-form rows, a rotation perturbed on the right.
          const auto [d_pose, d_vel] = acceleration_row_derivatives(c, at.t, s, bj, m);
          block += cq * d_pose * s.chain[bj].col_K + d_vel * s.chain[bj].col_C;
        }
        grow = how.constraint_scale * block;
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
