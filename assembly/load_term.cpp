// Nodal loads into the rank's residual rows and Jacobian blocks.
#include "assembly/load_term.hpp"

#include "assembly/nodal_load.hpp"

namespace latticedyn {

void LoadTerm::add_residual(const LocalState& s, double t, double load_scale, double* r) const {
  auto state_of = [&s](int b) -> const BlockState& { return s.state[b]; };
  for (int l : dofs_.local_loads()) {
    const NodalLoad& load = model_.loads[l];
    const double scale = load_scale * (load.drive >= 0 ? model_.drives[load.drive].evaluate(t).value : 1.0);
    const LoadEval le = evaluate_load(model_, load, state_of, scale, false);
    for (int k = 0; k < 2; ++k)
      if (le.blocks[k] >= 0) {
        const int lo = s.offset(le.blocks[k]);
        for (int i = 0; i < 3; ++i) r[lo + i] -= le.f(3 * k + i);
      }
  }
}

PetscErrorCode LoadTerm::add_jacobian(const LocalState& s, double t, double load_scale, double cq, Mat J,
                                      std::vector<Vec3>& y) const {
  PetscFunctionBeginUser;
  auto state_of = [&s](int b) -> const BlockState& { return s.state[b]; };
  const Eigen::Matrix3d zero3 = Eigen::Matrix3d::Zero();
  for (int l : dofs_.local_loads()) {
    const NodalLoad& load = model_.loads[l];
    const double scale = load_scale * (load.drive >= 0 ? model_.drives[load.drive].evaluate(t).value : 1.0);
    const LoadEval le = evaluate_load(model_, load, state_of, scale, true);
    if (le.blocks[1] >= 0) y[le.blocks[1]] -= le.f.tail<3>();
    for (int ki = 0; ki < 2; ++ki)
      for (int kj = 0; kj < 2; ++kj) {
        if (le.blocks[ki] < 0 || le.blocks[kj] < 0) continue;
        const Eigen::Matrix3d K = -le.K.block<3, 3>(3 * ki, 3 * kj);
        if (K.isZero(0.0)) continue;
        const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> blk = s.chain_block(le.blocks[ki], le.blocks[kj], cq, K, zero3, zero3);
        PetscInt ri = dofs_.block_dof(le.blocks[ki]), cj = dofs_.block_dof(le.blocks[kj]);
        PetscInt rows[3] = {ri, ri + 1, ri + 2}, cols[3] = {cj, cj + 1, cj + 2};
        PetscCall(MatSetValues(J, 3, rows, 3, cols, blk.data(), ADD_VALUES));
      }
  }
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
