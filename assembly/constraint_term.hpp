// The constraints (thesis 4.4) as a term of the equations of motion: G^T lambda in the force rows
// of the blocks they join, and their own rows (s g at position level, or the Baumgarte-stabilised
// acceleration level), with the Jacobian of both (geometric stiffness d(G^T lambda)/dq included).
#pragma once

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
  /// Their Jacobian for J = cq dR/dU + ca dR/dA (cv: no velocity terms); y takes G^T lambda per
  /// rotation block, for the derivative of T^T. Throws what the constraints throw.
  PetscErrorCode add_jacobian(const LocalState& s, const EvaluationPoint& at, const EvaluationSettings& how,
                              const double* lambda, double cq, double ca, Mat J, std::vector<Vec3>& y) const;

 private:
  /// The evaluation inputs of constraint c at time t in `states` (the one setup both share).
  ConstraintInputs inputs(int c, double t, const std::vector<BlockState>& states) const;

  const Model& model_;
  const DofMap& dofs_;
};

}  // namespace latticedyn
