// Linearisation from the assembled tangents: K, C, M and G out of the Jacobian taken with three
// sets of shifts, the inputs' columns by central differences of the residual in the drive values,
// the outputs' rows by central differences of the gathered joint states along the reduced basis.
#include "timestepping/linearization.hpp"

#include "assembly/model_state.hpp"

#include <Eigen/SVD>

#include <stdexcept>

namespace latticedyn {

namespace {

void check(PetscErrorCode status, const char* what) {
  if (status != 0) throw std::runtime_error(std::string("linearize: PETSc failed to ") + what);
}

Eigen::MatrixXd dense(Mat J) {
  Mat D;
  check(MatConvert(J, MATSEQDENSE, MAT_INITIAL_MATRIX, &D), "convert the Jacobian to dense");
  PetscInt rows, cols;
  check(MatGetSize(D, &rows, &cols), "size the Jacobian");
  const PetscScalar* a;
  check(MatDenseGetArrayRead(D, &a), "read the Jacobian");
  Eigen::MatrixXd out = Eigen::Map<const Eigen::MatrixXd>(a, rows, cols);  // column-major, as PETSc's dense
  check(MatDenseRestoreArrayRead(D, &a), "read the Jacobian");
  MatDestroy(&D);
  return out;
}

Eigen::VectorXd values(Vec X) {
  PetscInt n;
  check(VecGetSize(X, &n), "size a vector");
  const PetscScalar* x;
  check(VecGetArrayRead(X, &x), "read a vector");
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(x, n);
  check(VecRestoreArrayRead(X, &x), "read a vector");
  return out;
}

void set_values(Vec X, const Eigen::VectorXd& v) {
  PetscScalar* x;
  check(VecGetArray(X, &x), "write a vector");
  Eigen::Map<Eigen::VectorXd>(x, v.size()) = v;
  check(VecRestoreArray(X, &x), "write a vector");
}

/// Rows (or columns) `idx` of a matrix.
Eigen::MatrixXd rows_of(const Eigen::MatrixXd& m, const std::vector<int>& idx) {
  Eigen::MatrixXd out(idx.size(), m.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = m.row(idx[i]);
  return out;
}
Eigen::MatrixXd block_of(const Eigen::MatrixXd& m, const std::vector<int>& r, const std::vector<int>& c) {
  Eigen::MatrixXd out(r.size(), c.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = 0; j < c.size(); ++j) out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m(r[i], c[j]);
  return out;
}

}  // namespace

Eigen::VectorXcd LinearModel::mechanical_eigenvalues() const {
  const Eigen::Index n = 2 * independent;
  return Eigen::EigenSolver<Eigen::MatrixXd>(A.topLeftCorner(n, n), false).eigenvalues();
}

LinearModel linearize(SystemAssembler& sa, Vec U, Vec V, Vec A, double t, const std::vector<int>& input_drives,
                      const std::vector<int>& output_joints) {
  const Model& model = sa.model();
  const DofMap& dofs = sa.dofs();
  const int size = dofs.global_size();
  // Coordinates and multipliers.
  std::vector<char> is_multiplier(static_cast<std::size_t>(size), 0);
  std::vector<int> q, lambda;
  for (std::size_t c = 0; c < model.constraints.size(); ++c)
    for (int i = 0; i < model.constraints[c].rows(); ++i) is_multiplier[dofs.multiplier_dof(static_cast<int>(c)) + i] = 1;
  for (int i = 0; i < size; ++i) (is_multiplier[i] ? lambda : q).push_back(i);
  const auto nq = static_cast<Eigen::Index>(q.size());
  const auto nu = static_cast<Eigen::Index>(input_drives.size());

  std::vector<drive::ExternalSignal*> signals;
  LinearModel lm;
  lm.time = t;
  for (int d : input_drives) {
    drive::ExternalSignal* s = model.drives.at(d).external_signal();
    if (!s) throw std::invalid_argument("linearize: drive '" + model.drive_names[d] + "' is prescribed; inputs are external drives");
    signals.push_back(s);
    lm.inputs.push_back(model.drive_names[d]);
  }

  // The tangents: J(cq, cv, ca) = cq dF/dU + cv dF/dV + ca dF/dA, constraint rows unscaled.
  EvaluationSettings how;
  how.param = Parametrization::rotation_vector_rates;
  const EvaluationPoint at{U, V, A, U, t, t};
  Mat J;
  check(sa.create_matrix(&J, 1), "create a matrix");
  auto tangent = [&](double cq, double cv, double ca) {
    check(sa.jacobian(at, how, cq, cv, ca, J), "assemble the Jacobian");
    return dense(J);
  };
  const Eigen::MatrixXd Jq = tangent(1.0, 0.0, 0.0);
  // C and M as differences of Jacobians without stiffness (what is left, the multiplier columns,
  // cancels exactly), so that the stiffness's round-off does not swamp them.
  const Eigen::MatrixXd J0 = tangent(0.0, 0.0, 0.0);
  const Eigen::MatrixXd Jv = tangent(0.0, 1.0, 0.0) - J0, Ja = tangent(0.0, 0.0, 1.0) - J0;
  MatDestroy(&J);
  const Eigen::MatrixXd K = block_of(Jq, q, q), C = block_of(Jv, q, q), M = block_of(Ja, q, q);
  const Eigen::MatrixXd G = block_of(Jq, lambda, q);

  // The inputs: dF/du by central differences in each drive's value.
  Eigen::MatrixXd Fu = Eigen::MatrixXd::Zero(size, nu);
  {
    Vec F;
    check(sa.create_vector(&F), "create a vector");
    for (Eigen::Index k = 0; k < nu; ++k) {
      drive::ExternalSignal& s = *signals[k];
      const drive::ExternalSignal kept = s;
      const double value_now = model.drives[input_drives[k]].evaluate(t).value;
      const double eps = 1e-6 * std::max(1.0, std::abs(value_now));
      Eigen::VectorXd plus, minus;
      for (const double sign : {1.0, -1.0}) {
        s = drive::ExternalSignal{t, value_now + sign * eps, 0.0, 0.0};
        PetscBool finite;
        check(sa.residual(at, how, F, &finite), "evaluate the residual");
        (sign > 0 ? plus : minus) = values(F);
      }
      s = kept;
      Fu.col(k) = (plus - minus) / (2.0 * eps);
    }
    VecDestroy(&F);
  }
  const Eigen::MatrixXd Bf = -rows_of(Fu, q), E = -rows_of(Fu, lambda);  // M q'' + ... = Bf u, G q = E u

  // Independent coordinates: dq = N z + P u.
  Eigen::MatrixXd N, P;
  if (G.rows() == 0) {
    N = Eigen::MatrixXd::Identity(nq, nq);
    P = Eigen::MatrixXd::Zero(nq, nu);
  } else {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    Eigen::Index rank = 0;
    while (rank < sigma.size() && sigma(rank) > 1e-10 * sigma(0)) ++rank;
    N = svd.matrixV().rightCols(nq - rank);
    const Eigen::MatrixXd Vr = svd.matrixV().leftCols(rank), Ur = svd.matrixU().leftCols(rank);
    P = Vr * sigma.head(rank).cwiseInverse().asDiagonal() * Ur.transpose() * E;
  }
  const Eigen::Index r = N.cols();
  lm.independent = static_cast<int>(r);
  const Eigen::MatrixXd Mr = N.transpose() * M * N, Kr = N.transpose() * K * N, Cr = N.transpose() * C * N;
  const Eigen::FullPivLU<Eigen::MatrixXd> mass(Mr);
  if (!mass.isInvertible())
    throw std::runtime_error("linearize: the mass matrix on the independent coordinates is singular (" +
                             std::to_string(mass.rank()) + " of " + std::to_string(r) + "): a mechanism without mass");
  const Eigen::Index nx = 2 * r + 2 * nu;
  lm.A = Eigen::MatrixXd::Zero(nx, nx);
  lm.B = Eigen::MatrixXd::Zero(nx, nu);
  lm.A.block(0, r, r, r).setIdentity();
  lm.A.block(r, 0, r, r) = -mass.solve(Kr);
  lm.A.block(r, r, r, r) = -mass.solve(Cr);
  if (nu > 0) {
    lm.A.block(r, 2 * r, r, nu) = mass.solve(N.transpose() * (Bf - K * P));
    lm.A.block(r, 2 * r + nu, r, nu) = -mass.solve(N.transpose() * C * P);
    lm.A.block(2 * r, 2 * r + nu, nu, nu).setIdentity();
    lm.B.block(r, 0, r, nu) = -mass.solve(N.transpose() * M * P);
    lm.B.block(2 * r + nu, 0, nu, nu).setIdentity();
  }

  // Outputs: joint positions and velocities along each basis column, by central differences.
  const auto ny = static_cast<Eigen::Index>(6 * output_joints.size());
  lm.C = Eigen::MatrixXd::Zero(ny, nx);
  lm.D = Eigen::MatrixXd::Zero(ny, nu);
  for (int j : output_joints)
    for (const char* c : {".x", ".y", ".z", ".vx", ".vy", ".vz"}) lm.outputs.push_back(model.joints[j].name + c);
  if (ny > 0) {
    const Eigen::VectorXd u0 = values(U), v0 = values(V);
    Vec Up, Vp;
    check(sa.create_vector(&Up), "create a vector");
    check(sa.create_vector(&Vp), "create a vector");
    ModelState state(model, dofs);
    auto outputs = [&]() {
      check(sa.gather(t, Up, Vp, nullptr, Parametrization::rotation_vector_rates, &state), "gather the state");
      Eigen::VectorXd y(ny);
      for (std::size_t i = 0; i < output_joints.size(); ++i) {
        y.segment<3>(static_cast<Eigen::Index>(6 * i)) = state.joint_position(output_joints[i]);
        y.segment<3>(static_cast<Eigen::Index>(6 * i + 3)) = state.joint_velocity(output_joints[i]);
      }
      return y;
    };
    const double h = 1e-6;
    // d y / d(coordinates along b) and d y / d(rates along b).
    auto along = [&](const Eigen::VectorXd& b, bool rates) {
      Eigen::VectorXd full = Eigen::VectorXd::Zero(size), y[2];
      for (Eigen::Index i = 0; i < nq; ++i) full(q[i]) = b(i);
      for (int s = 0; s < 2; ++s) {
        const double sign = s == 0 ? 1.0 : -1.0;
        set_values(Up, rates ? u0 : Eigen::VectorXd(u0 + sign * h * full));
        set_values(Vp, rates ? Eigen::VectorXd(v0 + sign * h * full) : v0);
        y[s] = outputs();
      }
      return Eigen::VectorXd((y[0] - y[1]) / (2.0 * h));
    };
    for (Eigen::Index k = 0; k < r; ++k) {
      lm.C.col(k) = along(N.col(k), false);
      lm.C.col(r + k) = along(N.col(k), true);
    }
    for (Eigen::Index k = 0; k < nu; ++k) {
      lm.C.col(2 * r + k) = along(P.col(k), false);
      lm.C.col(2 * r + nu + k) = along(P.col(k), true);
    }
    VecDestroy(&Up);
    VecDestroy(&Vp);
  }
  return lm;
}

}  // namespace latticedyn
