// Where and how the equations of motion are evaluated: the state vectors and times of one
// evaluation, the constraint rows' form and the scalings the solvers choose.
#pragma once

#include "assembly/block_kinematics.hpp"

#include <petscvec.h>

namespace latticedyn {

struct EvaluationPoint {
  Vec U = nullptr, V = nullptr, A = nullptr, Uc = nullptr;
  double t = 0.0;   ///< time of the force balance
  double tc = 0.0;  ///< time of the constraint rows (drives)
};

enum class ConstraintRows {
  position,     ///< s g(Uc, tc) = 0: index-3 (generalized-alpha, statics)
  acceleration  ///< G a + Gamma + 2 alpha beta g_dot + alpha^2 g = 0: Baumgarte (4-27)
};

struct EvaluationSettings {
  Parametrization param = Parametrization::rotation_vector_rates;
  double load_scale = 1.0;        ///< multiplies gravity and nodal loads (static load ramping)
  double constraint_scale = 1.0;  ///< s of the position-level constraint rows
  double uc_per_u = 1.0;          ///< dUc/dU: 1/alpha_f for generalized-alpha, else 1
  ConstraintRows rows = ConstraintRows::position;
  double baumgarte_alpha = 0.0;
  double baumgarte_beta = 1.0;
};

/// Names under which create_matrix's matrices carry ISs of their owned rows that have no mass or
/// stiffness of their own: the multipliers', and those of frames no element touches (held by
/// constraints alone). A pivoting-free LU orders them behind the rows they couple to.

}  // namespace latticedyn
