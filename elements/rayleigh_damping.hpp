// Rayleigh damping of a material or body, alpha M + beta K, and how to choose it from damping
// ratios at given frequencies.
#pragma once

namespace latticedyn {

/// Damping matrix alpha M + beta K of a linear structure: mode i then has the damping ratio
/// zeta_i = alpha / (2 omega_i) + beta omega_i / 2 (Chopra, Dynamics of Structures, 11.4).
/// In latticedyn the beta part acts on the elements' deformation rates (the co-rotated strains),
/// never on rigid motion, and the alpha part on the absolute velocities (it damps rigid motion
/// too: a mass-proportional damping is an outside viscous drag).
struct RayleighDamping {
  double alpha = 0.0;  ///< mass-proportional coefficient [1/s]
  double beta = 0.0;   ///< stiffness-proportional coefficient [s]

  bool active() const { return alpha != 0.0 || beta != 0.0; }
  /// The damping ratio of a mode of circular frequency omega [rad/s].
  double ratio(double omega) const { return alpha / (2.0 * omega) + 0.5 * beta * omega; }
  /// Throws std::invalid_argument unless both coefficients are finite and >= 0.
  void validate() const;
};

/// Stiffness-proportional damping with ratio zeta at circular frequency omega: beta = 2 zeta / omega.
RayleighDamping rayleigh_from_ratio(double zeta, double omega);
/// The alpha, beta that give ratios zeta1, zeta2 at omega1 != omega2 (both must come out >= 0).
RayleighDamping rayleigh_from_ratios(double zeta1, double omega1, double zeta2, double omega2);

}  // namespace latticedyn
