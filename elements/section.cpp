// Section properties of round tubes, rectangular frames and custom sections, and the
// validation of materials and sections.
#include "elements/section.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace latticedyn {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}
bool positive(double x) { return std::isfinite(x) && x > 0.0; }
}  // namespace

void Material::validate() const {
  require(positive(density), "density must be a positive number (kg/m^3)");
  require(positive(youngs_modulus), "youngs_modulus must be a positive number (Pa)");
  require(std::isfinite(poisson_ratio) && poisson_ratio > -1.0 && poisson_ratio < 0.5,
          "poisson_ratio must lie in (-1, 0.5)");
  damping.validate();
  require(std::isfinite(yield_stress) && yield_stress >= 0.0, "yield_stress must be a number >= 0 (Pa)");
}

void SectionProperties::validate() const {
  require(positive(area), "section area must be positive");
  require(positive(Iy) && positive(Iz), "section moments of inertia Iy, Iz must be positive");
  require(positive(torsion_constant), "section torsion constant must be positive");
}

double SectionProperties::shear_coefficient(double nu) const {
  switch (shape) {
    case Shape::round_tube: {
      // Cowper (1966), J. Appl. Mech. 33:335, hollow circular section with m = ri/ro.
      const double m = inner_radius / outer_radius;
      const double m2 = m * m, s = (1 + m2) * (1 + m2);
      return 6 * (1 + nu) * s / ((7 + 6 * nu) * s + (20 + 12 * nu) * m2);
    }
    case Shape::frame:
      return custom_shear_coefficient;  // set by frame_section from the web areas
    case Shape::custom:
      return custom_shear_coefficient > 0 ? custom_shear_coefficient : 5.0 / 6.0;
  }
  return 5.0 / 6.0;
}

SectionProperties round_tube_section(double ro, double ri) {
  require(positive(ro), "outer radius must be positive");
  require(std::isfinite(ri) && ri >= 0.0 && ri < ro, "inner radius must lie in [0, outer radius)");
  SectionProperties s;
  s.shape = SectionProperties::Shape::round_tube;
  const double pi = std::numbers::pi;
  s.area = pi * (ro * ro - ri * ri);
  s.Iy = s.Iz = pi / 4 * (std::pow(ro, 4) - std::pow(ri, 4));
  s.torsion_constant = s.Iy + s.Iz;
  s.outer_radius = ro;
  s.inner_radius = ri;
  return s;
}

SectionProperties frame_section(double h, double b, double t) {
  require(positive(h) && positive(b), "frame height and width must be positive");
  require(positive(t), "frame wall thickness must be positive");
  SectionProperties s;
  s.shape = SectionProperties::Shape::frame;
  s.height = h;
  s.width = b;
  s.thickness = std::min(t, 0.5 * std::min(h, b));
  const bool solid = 2 * t >= std::min(h, b);
  if (solid) {
    s.area = b * h;
    s.Iy = b * h * h * h / 12;
    s.Iz = h * b * b * b / 12;
    // Roark's approximation for a solid rectangle with long side a and short side c.
    const double a = std::max(h, b), c = std::min(h, b);
    s.torsion_constant = a * c * c * c * (1.0 / 3 - 0.21 * (c / a) * (1 - std::pow(c / a, 4) / 12));
    s.custom_shear_coefficient = 5.0 / 6.0;
  } else {
    const double hi = h - 2 * t, bi = b - 2 * t;
    s.area = b * h - bi * hi;
    s.Iy = (b * h * h * h - bi * hi * hi * hi) / 12;
    s.Iz = (h * b * b * b - hi * bi * bi * bi) / 12;
    // Bredt's formula for a thin-walled closed section on the wall's mid line.
    const double am = (h - t) * (b - t);
    s.torsion_constant = 4 * am * am * t / (2 * ((h - t) + (b - t)));
    // Shear is carried by the webs parallel to the load; take the weaker direction.
    s.custom_shear_coefficient = std::min(2 * h * t, 2 * b * t) / s.area;
  }
  return s;
}

SectionProperties custom_section(double area, double Iy, double Iz, double J, double kappa) {
  SectionProperties s;
  s.shape = SectionProperties::Shape::custom;
  s.area = area;
  s.Iy = Iy;
  s.Iz = Iz;
  s.torsion_constant = J;
  s.custom_shear_coefficient = kappa;
  s.validate();
  return s;
}

}  // namespace latticedyn
