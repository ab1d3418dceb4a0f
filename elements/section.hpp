// Materials and cross sections as validated value types (thesis Table 5-1: round tube, frame,
// custom), kept apart from the elements that use them.
#pragma once

#include "elements/rayleigh_damping.hpp"

namespace latticedyn {

struct Material {
  double density = 0.0;         ///< rho [kg/m^3]
  double youngs_modulus = 0.0;  ///< E [Pa]
  double poisson_ratio = 0.0;   ///< nu [-]
  RayleighDamping damping;      ///< alpha M + beta K of every element made of it
  double yield_stress = 0.0;    ///< f_y [Pa] that members' utilization refers to; 0: not given

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Throws std::invalid_argument naming the first meaningless value.
  void validate() const;
};

/// Geometric properties of a cross section in its local y-z plane.
struct SectionProperties {
  enum class Shape { round_tube, frame, custom };
  Shape shape = Shape::custom;
  double area = 0.0;              ///< A [m^2]
  double Iy = 0.0;                ///< integral of z^2 dA [m^4]
  double Iz = 0.0;                ///< integral of y^2 dA [m^4]
  double torsion_constant = 0.0;  ///< J (Saint-Venant) [m^4]
  double outer_radius = 0.0;      ///< round tube radii (for shear coefficient and drawing)
  double inner_radius = 0.0;
  double custom_shear_coefficient = 0.0;  ///< custom sections: given kappa, or 0 for 5/6
  double mass_per_length = 0.0;  ///< custom sections: given mass per length [kg/m], or 0 for rho A
  double height = 0.0, width = 0.0, thickness = 0.0;  ///< frames: extent along z, along y, wall
  double fibre_y = 0.0, fibre_z = 0.0;  ///< custom sections: outermost fibres' distances from the z and y axes, 0: unknown

  /// The density the section's inertia uses: the material's, or mass_per_length / A when a
  /// custom section gives its mass (Table 5-1's "quality"); rotary inertia scales with it.
  double effective_density(const Material& m) const { return mass_per_length > 0 ? mass_per_length / area : m.density; }

  /// Timoshenko shear coefficient kappa (shear stiffness kappa G A): Cowper's formula for round
  /// tubes (0.886 solid, ~0.53 thin wall at nu = 0.3), A_web/A for frames, 5/6 or given otherwise.
  double shear_coefficient(double poisson_ratio) const;
  void validate() const;
};

/// Round tube of outer and inner radius (thesis tables call them "diameter"; they are radii).
SectionProperties round_tube_section(double outer_radius, double inner_radius);
/// Rectangular hollow ("frame") section: height along z, width along y, wall thickness;
/// thickness >= min(height, width)/2 gives the solid rectangle.
SectionProperties frame_section(double height, double width, double thickness);
/// User-given properties; shear_coefficient <= 0 means 5/6.
SectionProperties custom_section(double area, double Iy, double Iz, double torsion_constant,
                                 double shear_coefficient = 0.0);

}  // namespace latticedyn
