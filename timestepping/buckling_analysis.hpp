// Linearized buckling about a static equilibrium: the load factors lambda at which the tangent
// K0 + lambda (K1 - K0) turns singular (K0 unloaded, K1 under the reference loads), with SLEPc.
#pragma once

#include "assembly/system_assembler.hpp"

#include <slepceps.h>

#include <string>
#include <vector>

namespace latticedyn {

struct BucklingSettings {
  int modes = 4;  ///< how many load factors, smallest |lambda| first
  double tolerance = 1e-10;
};

struct BucklingMode {
  double factor = 0.0;    ///< lambda: the reference loads times lambda buckle the model (< 0: reversed loads)
  double residual = 0.0;  ///< relative residual reported by SLEPc
  Vec vector = nullptr;   ///< the mode in velocity variables (as Mode::vector), largest entry 1; owned
};

/// Linearized (pre)buckling (e.g. Bathe, Finite Element Procedures, 6.8.2; Crisfield vol. 1,
/// 9.1): the tangent at the reference equilibrium under the loads, K1 = K(U1, loads), and the
/// tangent of the unloaded reference configuration, K0 = K(U0, no gravity and nodal loads), span
/// the linear path K(lambda) = K0 + lambda (K1 - K0); K1 - K0 is the geometric (initial stress and
/// load) stiffness of the reference loads with the prebuckling deformation's first-order effect.
/// The generalized eigenproblem K0 phi = lambda (K0 - K1) phi is solved by shift-and-invert about
/// 0; the constraints stay as multiplier rows (their infinite eigenvalues never come out).
class BucklingAnalysis {
 public:
  BucklingAnalysis(SystemAssembler& assembler, BucklingSettings settings);
  ~BucklingAnalysis();
  BucklingAnalysis(const BucklingAnalysis&) = delete;
  BucklingAnalysis& operator=(const BucklingAnalysis&) = delete;

  /// U0: the unloaded reference configuration (the model's initial state); U1: the static
  /// equilibrium under the loads at time t. Returns the load factors with the smallest |lambda|,
  /// sorted by |lambda|; complex pairs (a non-conservative load) are left out and counted in
  /// `message`. Collective.
  PetscErrorCode solve(Vec U0, Vec U1, double t, std::vector<BucklingMode>* modes, std::string* message);

 private:
  SystemAssembler& sa_;
  BucklingSettings settings_;
  Mat K0_ = nullptr, KG_ = nullptr;
};

/// Frees the modes' vectors.
void destroy_modes(std::vector<BucklingMode>& modes);

}  // namespace latticedyn
