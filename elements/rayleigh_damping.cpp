// Rayleigh damping: validation and the coefficients that give chosen damping ratios.
#include "elements/rayleigh_damping.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

void RayleighDamping::validate() const {
  if (!(std::isfinite(alpha) && alpha >= 0)) throw std::invalid_argument("damping alpha must be a number >= 0 (1/s)");
  if (!(std::isfinite(beta) && beta >= 0)) throw std::invalid_argument("damping beta must be a number >= 0 (s)");
}

RayleighDamping rayleigh_from_ratio(double zeta, double omega) {
  if (!(std::isfinite(zeta) && zeta >= 0)) throw std::invalid_argument("damping ratio must be a number >= 0");
  if (!(std::isfinite(omega) && omega > 0)) throw std::invalid_argument("damping frequency must be positive");
  return RayleighDamping{0.0, 2.0 * zeta / omega};
}

RayleighDamping rayleigh_from_ratios(double zeta1, double omega1, double zeta2, double omega2) {
  for (double z : {zeta1, zeta2})
    if (!(std::isfinite(z) && z >= 0)) throw std::invalid_argument("damping ratios must be numbers >= 0");
  for (double w : {omega1, omega2})
    if (!(std::isfinite(w) && w > 0)) throw std::invalid_argument("damping frequencies must be positive");
  if (std::abs(omega1 - omega2) <= 1e-9 * (omega1 + omega2))
    throw std::invalid_argument("the two damping frequencies must differ");
  // zeta_i = alpha / (2 omega_i) + beta omega_i / 2, two linear equations in alpha, beta.
  const double d = omega2 * omega2 - omega1 * omega1;
  RayleighDamping r;
  r.alpha = 2.0 * omega1 * omega2 * (zeta1 * omega2 - zeta2 * omega1) / d;
  r.beta = 2.0 * (zeta2 * omega2 - zeta1 * omega1) / d;
  if (r.alpha < 0 || r.beta < 0)
    throw std::invalid_argument("these damping ratios need a negative alpha or beta (no dissipative Rayleigh damping "
                                "gives them): the ratio may fall with frequency at most like 1/omega and rise at most like omega");
  return r;
}

}  // namespace latticedyn
