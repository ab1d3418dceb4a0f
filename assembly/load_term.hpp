// The nodal loads (thesis 4.3, 4.9) as a term of the equations of motion: -f_ext in the residual
// rows of the blocks they act on, and for follower loads -df_ext/dq in the Jacobian.
#pragma once

#include "assembly/dof_map.hpp"
#include "assembly/local_state.hpp"

#include <petscmat.h>

namespace latticedyn {

class LoadTerm {
 public:
  LoadTerm(const Model& model, const DofMap& dofs) : model_(model), dofs_(dofs) {}
  /// r -= f_ext of the rank's loads at time t, scaled by load_scale (static load ramping).
  void add_residual(const LocalState& s, double t, double load_scale, double* r) const;
  /// J -= cq df_ext/dq through the blocks' chain maps; y (residual in omega variables per rotation
  /// block, for the derivative of T^T) takes the loads' moments. Throws what the loads throw.
  PetscErrorCode add_jacobian(const LocalState& s, double t, double load_scale, double cq, Mat J,
                              std::vector<Vec3>& y) const;

 private:
  const Model& model_;
  const DofMap& dofs_;
};

}  // namespace latticedyn
