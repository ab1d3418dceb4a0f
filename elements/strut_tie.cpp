// Strut tie: validation, energy (kinetic incl. rotary inertia, gravity, strain) and the axial
// force reported in the results.
#include "elements/strut_tie.hpp"

#include <cmath>
#include <stdexcept>

namespace latticedyn {

void StrutTieProperties::validate() const {
  material.validate();
  section.validate();
  if (!(std::isfinite(rest_length) && rest_length > 0))
    throw std::invalid_argument("strut tie rest length must be positive");
  if (!(std::isfinite(smoothing) && smoothing >= 0))
    throw std::invalid_argument("strut tie smoothing factor h must be >= 0");
}

StrutTie::StrutTie(const StrutTieProperties& p) : props_(p) {
  props_.validate();
  mass_ = p.material.density * p.section.area * p.rest_length;
  ea_ = p.material.youngs_modulus * p.section.area;
  rotary_inertia_ = p.material.density * 0.5 * (p.section.Iy + p.section.Iz) * p.rest_length;
}

ElementEnergy StrutTie::energy(std::span<const SlotState<double>> s, const ElementContext& ctx) const {
  const Vec3& v1 = s[0].vel;
  const Vec3& v2 = s[1].vel;
  const Vec3 d = s[1].pos - s[0].pos;
  const Vec3 dv = v2 - v1;
  const double l2 = d.squaredNorm();
  const double l = std::sqrt(l2);
  const double L0 = props_.rest_length;
  ElementEnergy e;
  e.kinetic = mass_ / 6.0 * (v1.squaredNorm() + v1.dot(v2) + v2.squaredNorm()) +
              0.5 * rotary_inertia_ * (d.cross(dv) / l2).squaredNorm();
  e.gravity_potential = -mass_ * ctx.gravity.dot(0.5 * (s[0].pos + s[1].pos));
  const double eps = l / L0 - 1.0;
  const double eps_dot = d.dot(dv) / (l * L0);
  // The h^2/6 eps_ddot part of the averaged stress stores energy like a mass on eps_dot.
  const double h = props_.smoothing;
  e.strain = 0.5 * ea_ * L0 * (eps * eps + h * h / 6.0 * eps_dot * eps_dot);
  return e;
}

std::optional<double> StrutTie::axial_force(std::span<const SlotState<double>> s, const ElementContext&) const {
  return axial_force_from<double>(s[1].pos - s[0].pos, s[1].vel - s[0].vel, s[1].acc - s[0].acc);
}

}  // namespace latticedyn
