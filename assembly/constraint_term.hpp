// The constraints (thesis 4.4) as a term of the equations of motion: G^T lambda in the force rows
// of the blocks they join, and their own rows (s g at position level, or the Baumgarte-stabilised
// acceleration level), with the Jacobian of both (geometric stiffness d(G^T lambda)/dq included).
#pragma once

#include <utility>

#include "assembly/constraint_evaluator.hpp"
#include "assembly/dof_map.hpp"
#include "assembly/evaluation_settings.hpp"
#include "assembly/local_state.hpp"

#include <petscmat.h>

namespace latticedyn {

class ConstraintTerm {
 public:
  ConstraintTerm(const Model& model, const DofMap& dofs) : model_(model), dofs_(dofs) {}
  /// The rank's constraints into r: G^T lambda into the blocks' rows, the constraint rows at the
  /// multipliers' offsets. `lambda`: the local vector the multipliers are read from; `distinct_c`:
  /// the constraint rows' state (LocalState::state_c) differs from the force balance's.
  void add_residual(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how, const double* lambda,
                    bool distinct_c, double* r) const;
  /// Their Jacobian for J = cq dR/dU + cv dR/dV + ca dR/dA (the chain maps carry cv and ca); y takes G^T lambda per
  /// rotation block, for the derivative of T^T. Throws what the constraints throw.
  PetscErrorCode add_jacobian(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how,
                              const double* lambda, double cq, double cv, Mat J, std::vector<Vec3>& y) const;

 private:
  /// The evaluation inputs of constraint c at time t in `states` (the one setup both share).
  ConstraintInputs inputs(int c, double t, const std::vector<BlockState>& states) const;
  /// d(G acc + Gamma)/d(pose) and /d(velocity) of constraint c's acceleration-level rows with
  /// respect to one of its blocks (rotations perturbed on the right, body omega), by central
  /// differences of the closed-form rows: the implicit Runge-Kutta route's Newton matrix, where
  /// the velocity terms enter with the shift (the Baumgarte route needs only G).
  std::pair<Eigen::Matrix<double, Eigen::Dynamic, 3>, Eigen::Matrix<double, Eigen::Dynamic, 3>>
  acceleration_row_derivatives(int c, double t, const LocalState& s, int block, int rows) const;

  const Model& model_;
  const DofMap& dofs_;
};

}  // namespace latticedyn
