// Natural frequencies and mode shapes of the model linearised about a static equilibrium: the
// generalized eigenproblem K phi = omega^2 M phi with the constraints kept as multiplier rows,
// symmetric in the velocity variables, solved by SLEPc with shift-and-invert and purification
// (the multipliers' infinite eigenvalues never come out).
#pragma once

#include "assembly/system_assembler.hpp"

#include <slepceps.h>

#include <vector>

namespace latticedyn {

struct ModalSettings {
  int modes = 6;          ///< how many of the lowest modes
  double tolerance = 1e-10;
};

struct Mode {
  double omega2 = 0.0;     ///< eigenvalue omega^2 [1/s^2]
  double frequency = 0.0;  ///< sqrt(omega2) / (2 pi) [Hz] (0 for omega2 <= 0)
  double residual = 0.0;   ///< relative residual |K phi - omega^2 M phi| / |K phi| reported by SLEPc
  double damping_ratio = 0.0;  ///< phi^T C phi / (2 omega phi^T M phi), C the damping at rest
  Vec vector = nullptr;    ///< the mode in the system's unknowns as velocity variables (gather with
                           ///< Parametrization::velocity_variables); owned
};

class ModalAnalysis {
 public:
  ModalAnalysis(SystemAssembler& assembler, ModalSettings settings);
  ~ModalAnalysis();
  ModalAnalysis(const ModalAnalysis&) = delete;
  ModalAnalysis& operator=(const ModalAnalysis&) = delete;

  /// The lowest modes about the state U at time t, by increasing frequency. Collective. Modes of
  /// a free body (omega^2 near 0) are found like the others. Fewer than `modes` come back when
  /// fewer converged; `message` says how many did.
  PetscErrorCode solve(Vec U, double t, std::vector<Mode>* modes, std::string* message);

 private:
  SystemAssembler& sa_;
  ModalSettings settings_;
  Mat K_ = nullptr, M_ = nullptr, C_ = nullptr;
};

/// Frees the modes' vectors.
void destroy_modes(std::vector<Mode>& modes);

}  // namespace latticedyn
