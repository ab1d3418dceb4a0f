// The state-space model of a linearisation (timestepping/linearization.hpp): matrices and the
// names of its inputs and outputs; no PETSc, so the library's facade can hand it out.
#pragma once

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace latticedyn {

/// x' = A x + B w, y = C x + D w about the state it was taken at (all deviations from it).
/// States: x = [z, z', u, u'] with z the independent coordinates (dq = N z + P u, N an orthonormal
/// basis of the null space of G, P = -G^+ E the least-norm motion a drive input imposes), u the
/// inputs' drive values; inputs w = u'' (the drives' accelerations, as external drives take
/// them); outputs y: per output joint its position (x, y, z) and velocity (vx, vy, vz), as the
/// probe CSV has them.
struct LinearModel {
  Eigen::MatrixXd A, B, C, D;
  int independent = 0;  ///< dim z
  std::vector<std::string> inputs;   ///< drive names
  std::vector<std::string> outputs;  ///< "joint.x", ..., "joint.vz"
  double time = 0.0;
  /// The eigenvalues of the mechanical part ([z, z'] without the drives' double integrators).
  Eigen::VectorXcd mechanical_eigenvalues() const;
};

}  // namespace latticedyn
